"""A campaign from its file to its results folder: load, plan, check, run what is missing, report.

The steps, in order (each needs the one before):

1. :func:`~robogen.campaign.spec.load_campaign`: the file against its schema, the base system
   loaded (located errors);
2. :func:`~robogen.campaign.plan.make_plan`: the space expanded, every run's files and values
   resolved and checked against the FMUs, every run keyed by its specification hash;
3. :func:`check_base`: the base system simulated for zero time in a separate process, so that
   what ``robogen simulate`` would reject (connections, types, FMUs) is reported before any run;
4. (``--dry-run`` stops here and lists the runs)
5. the runs not yet in the journal, on Dask (:mod:`robogen.campaign.engine`), each result
   journaled as it arrives;
6. the tables, the figure and ``summary.md`` from the journal, for every run of the campaign.
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from robogen.campaign.journal import Journal
from robogen.campaign.plan import CampaignPlan, Run, make_plan
from robogen.campaign.spec import Campaign, load_campaign
from robogen.diagnostics import RobogenError
from robogen.outputs import output_folder

CHECK_TIMEOUT = 120.0


@dataclass
class CampaignResult:
    folder: Path
    runs: int
    executed: int  # runs executed by this invocation
    reused: int  # runs found in the journal
    counts: dict[str, int]  # status -> runs
    wall: float  # seconds, cluster start and report included
    execution: float  # seconds from the first run submitted (workers ready) to the last result


def _zero_length(system: Path, start: float, step: float | None):
    """In a separate process: the base system, simulated from its start time to its start time."""
    from robogen.cosim import simulate_system

    try:
        simulate_system(system, stop=start, step=step, keep_rows=False, progress=False)
    except RobogenError as exc:
        return exc.diagnostics
    return None


def check_base(campaign: Campaign) -> None:
    """Raise what ``robogen simulate`` would say about the base system (when its FMUs exist;
    a campaign may give every run another FMU than the base's)."""
    from robogen.campaign.isolate import Zygote

    if not all(spec.fmu.is_file() for spec in campaign.system.instances.values()):
        return
    zygote = Zygote()
    try:
        outcome = zygote.run((), min(campaign.timeout, CHECK_TIMEOUT), _zero_length,
                             (campaign.system_path, campaign.system.start, campaign.step))
    finally:
        zygote.close()
    if outcome.failure is not None:
        raise RobogenError.at(f"the base system failed a zero-length simulation: {outcome.failure}",
                              campaign.span("system"))
    if outcome.result:
        raise RobogenError(outcome.result)


def describe(plan: CampaignPlan) -> str:
    """The dry-run listing: what was checked, then one line per run."""
    c = plan.campaign
    params = list(c.targets)
    distinct = len({r.spec.key for r in plan.runs})
    lines = [f"{c.path}: {len(plan.runs)} runs ({distinct} distinct) of {c.system_path}, "
             f"{len(plan.fmu_files)} FMU file(s); checked: the base system, {len(params)} parameter(s), "
             f"{len(c.metrics)} metric(s); nothing was run"]
    cells = [["run", "id", *params]] + [[str(r.index), r.id, *(_text(r.values.get(p)) for p in params)] for r in plan.runs]
    widths = [max(len(row[i]) for row in cells) for i in range(len(cells[0]))]
    lines += ["  ".join(cell.ljust(w) for cell, w in zip(row, widths)).rstrip() for row in cells]
    return "\n".join(lines)


def _text(value) -> str:
    return "-" if value is None else (f"{value:.6g}" if isinstance(value, float) else str(value))


def default_folder(campaign_path: Path) -> Path:
    return Path(f"{campaign_path.stem}-results")


def run_campaign(path: str | Path, out: str | Path | None = None, *, workers: int | None = None,
                 scheduler: str | None = None, retries: int = 2, dry_run: bool = False,
                 progress: bool | None = None, echo: Callable[[str], None] = print) -> CampaignResult | None:
    """Run the campaign in ``path`` (the runs not already in ``out``'s journal); None for a dry run."""
    campaign = load_campaign(path)
    plan = make_plan(campaign)
    check_base(campaign)
    if dry_run:
        echo(describe(plan))
        return None
    folder = output_folder(out if out is not None else default_folder(campaign.path), command="campaign",
                           inputs=[campaign.path, campaign.system_path])
    journal = Journal(folder / "journal.jsonl")
    try:
        return _run(plan, folder, journal, workers, scheduler, retries, progress, echo)
    except KeyboardInterrupt:
        echo(f"interrupted: {len(journal.rows)} finished runs are kept in {journal.path}; "
             "run the same command again to continue")
        raise
    finally:
        journal.close()


def _run(plan: CampaignPlan, folder: Path, journal: Journal, workers, scheduler, retries, progress, echo) -> CampaignResult:
    from robogen.campaign.dashboard import publisher
    from robogen.campaign.engine import Progress, connect, execute
    from robogen.campaign.report import write_report

    unique: dict[str, Run] = {}
    for run in plan.runs:
        unique.setdefault(run.spec.key, run)
    todo = [run for key, run in unique.items() if key not in journal]
    echo(f"{plan.campaign.title}: {len(plan.runs)} runs ({len(unique)} distinct): "
         f"{len(unique) - len(todo)} already done, {len(todo)} to run -> {folder}")
    started = time.monotonic()
    lost: dict[str, str] = {}
    execution = 0.0
    if todo:
        with connect(workers, scheduler, echo) as client:
            bar = Progress(len(todo), sys.stderr.isatty() if progress is None else progress, title=plan.campaign.title,
                           publish=publisher(client))
            try:
                lost = execute(plan, todo, client, retries=retries, record=_recorder(plan, folder, journal), progress=bar)
                execution = time.monotonic() - bar.started
            finally:
                bar.close()
    wall = time.monotonic() - started
    rows = [journal.rows.get(run.spec.key) or _lost(lost.get(run.spec.key, "lost")) for run in plan.runs]
    counts = write_report(plan, rows, folder, wall=execution, executed=len(todo))
    echo(f"{plan.campaign.title}: " + ", ".join(f"{n} {status}" for status, n in counts.items())
         + f" in {wall:.1f} s -> {folder / 'runs.parquet'}, {folder / 'summary.md'}")
    return CampaignResult(folder, len(plan.runs), len(todo), len(unique) - len(todo), counts, wall, execution)


def _recorder(plan: CampaignPlan, folder: Path, journal: Journal) -> Callable[[Run, dict], None]:
    from robogen.campaign.results import write_series

    def record(run: Run, row: dict) -> None:
        series = row.pop("series", None)
        if series is not None:
            write_series(*series, folder / "results" / f"{run.id}.parquet")
        journal.add(run.spec.key, row)

    return record


def _lost(reason: str) -> dict:
    return {"status": "lost", "error": reason, "end_time": None, "metrics": {}, "wall_time": None, "worker": None}
