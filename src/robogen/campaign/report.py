"""The campaign's report: the tables, the summary figure and ``summary.md``.

``summary.md`` says what ran (runs by status, wall time and throughput of this invocation),
what the parameters were, each metric's spread over the runs that have it (min, median, max; for
booleans how many were true), the metrics per value of the figure's facet, and the failures with
their messages. The figure is ``summary.png`` (:mod:`robogen.campaign.figure`).
"""

from __future__ import annotations

import statistics
from pathlib import Path

from robogen.campaign import figure as figures
from robogen.campaign.plan import CampaignPlan
from robogen.campaign.results import metric_names, table, write_tables
from robogen.outputs import write_text

STATUS_ORDER = ("ok", "terminated", "failed", "lost")
MAX_FAILURES = 20


def write_report(plan: CampaignPlan, rows: list[dict], folder: Path, *, wall: float, executed: int) -> dict[str, int]:
    """Write runs.parquet, runs.csv, summary.png (when there is something to draw) and
    summary.md; return the number of runs per status."""
    runs = table(plan, rows)
    write_tables(runs, folder)
    params, metrics = list(plan.campaign.targets), metric_names(plan, rows)
    records = runs.to_pylist()
    choice = figures.choose(plan.campaign.figure, records, params, metrics)
    png = folder / "summary.png"
    if choice is not None:
        figures.draw(choice, records, png, plan.campaign.title)
    elif png.exists():
        png.unlink()
    counts = {s: n for s in STATUS_ORDER if (n := sum(r["status"] == s for r in records))}
    text = _summary(plan, records, params, metrics, counts, choice, wall=wall, executed=executed)
    write_text(folder / "summary.md", text)
    return counts


def _fmt(v) -> str:
    if v is None:
        return "–"
    if isinstance(v, float):
        return f"{v:.4g}"
    return str(v)


def _summary(plan: CampaignPlan, records: list[dict], params: list[str], metrics: list[str], counts: dict[str, int],
             choice, *, wall: float, executed: int) -> str:
    c = plan.campaign
    rate = f", {executed / wall:.2f} runs/s" if executed and wall > 0 else ""
    lines = [f"# {c.title}", "",
             f"Campaign `{c.path}` over `{c.system_path}`: {len(records)} runs, "
             + ", ".join(f"{n} {s}" for s, n in counts.items()) + ".",
             f"This invocation ran {executed} of them in {wall:.1f} s of wall time{rate} (workers ready to last result); "
             "the others came from the journal.",
             ""]
    if choice is not None:
        lines += ["![summary figure](summary.png)", ""]
    lines += ["## Parameters", "", "| parameter | sets | values |", "| --- | --- | --- |"]
    for name in params:
        target = c.targets[name]
        sets = {"start": "start value", "fmu": "the FMU file", "resource": "a file in the FMU's resources",
                "variable": "a variable of [files]", "setting": f"how the instance uses its FMU ({target.name})"}[target.kind]
        values = figures.sorted_values(records, name)
        shown = ", ".join(_fmt(v) for v in values[:6]) + (f", … ({len(values)} values)" if len(values) > 6 else "")
        lines.append(f"| `{name}` | {sets} | {shown} |")
    lines += ["", *_metric_table(records, metrics)]
    if choice is not None and choice.facet:
        lines += ["", *_facet_table(records, choice, metrics)]
    lines += ["", *_failures(records, params)]
    return "\n".join(lines) + "\n"


def _metric_table(records: list[dict], metrics: list[str]) -> list[str]:
    lines = ["## Metrics", "", "| metric | runs with a value | min | median | max |", "| --- | --- | --- | --- | --- |"]
    for name in metrics:
        values = [r[name] for r in records if r.get(name) is not None]
        if values and all(isinstance(v, bool) for v in values):
            lines.append(f"| `{name}` | {len(values)} | true in {sum(values)} | | false in {len(values) - sum(values)} |")
        elif values and all(isinstance(v, (int, float)) for v in values):
            lines.append(f"| `{name}` | {len(values)} | {_fmt(min(values))} | {_fmt(statistics.median(values))} | "
                         f"{_fmt(max(values))} |")
        else:
            common = max(set(map(str, values)), key=[str(v) for v in values].count) if values else None
            lines.append(f"| `{name}` | {len(values)} | most often: {_fmt(common)} | | |")
    return lines


def _facet_table(records: list[dict], choice, metrics: list[str]) -> list[str]:
    facet = choice.facet
    shown = [m for m in metrics if any(isinstance(r.get(m), (int, float)) for r in records)]
    lines = [f"## By {facet}", "", "Medians over the runs with a value; for a boolean, the runs where it is true.", "",
             f"| {facet} | runs | ok | " + " | ".join(f"`{m}`" for m in shown) + " |",
             "| --- " * (3 + len(shown)) + "|"]
    for value in figures.sorted_values(records, facet):
        subset = [r for r in records if r[facet] == value]
        cells = []
        for m in shown:
            values = [r[m] for r in subset if isinstance(r.get(m), (int, float))]
            if values and all(isinstance(v, bool) for v in values):
                cells.append(f"{sum(values)} true")
            else:
                cells.append(_fmt(statistics.median(values)) if values else "–")
        ok = sum(r["status"] == "ok" for r in subset)
        lines.append(f"| {_fmt(value)} | {len(subset)} | {ok} | " + " | ".join(cells) + " |")
    return lines


def _failures(records: list[dict], params: list[str]) -> list[str]:
    failed = [r for r in records if r["status"] in ("failed", "lost")]
    if not failed:
        return ["## Failures", "", "None."]
    lines = ["## Failures", "", f"{len(failed)} run(s); the first {min(len(failed), MAX_FAILURES)}:", "",
             "| run | id | parameters | error |", "| --- | --- | --- | --- |"]
    for r in failed[:MAX_FAILURES]:
        values = ", ".join(f"{p} = {_fmt(r[p])}" for p in params)
        message = (r["error"] or "").strip().splitlines()
        lines.append(f"| {r['run']} | `{r['id']}` | {values} | {message[0] if message else ''} |".replace("\n", " "))
    return lines
