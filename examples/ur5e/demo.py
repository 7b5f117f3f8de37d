"""`make demo`: the UR5e case study end to end, from a fresh clone.

1. check the UR5e models and draw their state machines;
2. build the FMUs: the d-model generated from ``models/ur5e/ur5e.rst`` (exhaustive and stepwise),
   the RoboChart variant from ``ur5e.rct``, the PyBullet platform and the plan controller;
3. co-simulate ``models/ur5e/system.toml`` (and its two variants) with robogen's master;
4. analyse the runs, draw ``figure.png``, write ``summary.md``; a short paced run shows
   ``--realtime``.

Outputs go to ``build/ur5e/``: ``results.csv``, ``events.jsonl``, ``figure.png``, ``summary.md``
(and ``results-<variant>.csv`` / ``events-<variant>.jsonl`` for the variants). The exit status is
1 if a property the case study must show does not hold.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from examples.ur5e.build import MODELS, ROOT
from robogen.cli import main as robogen

OUT = ROOT / "build" / "ur5e"
REALTIME_FACTOR = 50.0


def _rel(path: Path | str) -> str:
    try:
        return str(Path(path).absolute().relative_to(ROOT))
    except ValueError:
        return str(path)


def _step(text: str) -> None:
    print(f"== {text}", flush=True)


def run(out: Path = OUT, realtime: bool = True) -> int:
    from examples.ur5e.analysis import analyse, load_run, node_names_of
    from examples.ur5e.build import TIME_UNIT, VARIANTS, build_all
    from examples.ur5e.figure import draw
    from examples.ur5e.report import Timing, summary
    from robogen.cosim import simulate_system
    from robogen.diagnostics import RobogenError, SourceMap, render_all

    out.mkdir(parents=True, exist_ok=True)
    timings: list[Timing] = []
    started = time.perf_counter()
    _step("check and draw the models")
    for args in (
        ["check", str(MODELS)],
        ["graph", str(MODELS / "ur5e.rst"), "--format", "mermaid", "-o", str(out / "ur5e-rst.mmd")],
        ["graph", str(MODELS / "ur5e.rst"), "--format", "dot", "-o", str(out / "ur5e-rst.dot")],
        ["graph", str(MODELS / "ur5e.rct"), "--format", "mermaid", "-o", str(out / "ur5e-rct.mmd")],
        ["graph", str(MODELS / "ur5e.rct"), "--format", "dot", "-o", str(out / "ur5e-rct.dot")],
    ):
        print("$ robogen " + " ".join(_rel(a) if "/" in a else a for a in args), flush=True)
        code = robogen(args)
        if code:
            return code
    timings.append(Timing("check and draw", time.perf_counter() - started))
    try:
        _step(f"build the FMUs into {_rel(out)}/")
        t0 = time.perf_counter()
        built = build_all(out)
        timings.append(Timing("build 5 FMUs (3 generated d-models, 2 Python FMUs)", time.perf_counter() - t0))
        for what, seconds in built.timings.items():
            print(f"   {what}: {seconds:.2f} s")
        reports, titles, sim_wall = {}, {}, {}
        runs = {}
        for v in VARIANTS:
            suffix = "" if v.name == "exhaustive" else f"-{v.name}"
            results, events = out / f"results{suffix}.csv", out / f"events{suffix}.jsonl"
            _step(f"co-simulate: {v.title}")
            t0 = time.perf_counter()
            result = simulate_system(built.systems[v.name], output=results, events=events, keep_rows=False)
            sim_wall[v.name] = time.perf_counter() - t0
            timings.append(Timing(f"co-simulation, {v.name}", sim_wall[v.name]))
            s = result.stats
            print(f"   100 s simulated in {sim_wall[v.name]:.2f} s: {s.steps} steps, {s.event_iterations} event iterations, "
                  f"{s.instants} super-dense instants, {s.early_returns} early returns -> {_rel(results)}")
            names, machine = node_names_of(out / v.fmu)
            run_ = load_run(v.name, results, events, names, machine)
            run_.wall, run_.event_iterations, run_.instants = sim_wall[v.name], s.event_iterations, s.instants
            runs[v.name] = run_
            reports[v.name] = analyse(run_, float(TIME_UNIT))
            titles[v.name] = v.title
        rt = None
        if realtime:
            _step(f"a paced run: --realtime={REALTIME_FACTOR:g} (100 s in {100 / REALTIME_FACTOR:g} s of wall time)")
            t0 = time.perf_counter()
            paced = simulate_system(built.systems["exhaustive"], output=out / "results-paced.csv", realtime=REALTIME_FACTOR, keep_rows=False)
            timings.append(Timing(f"paced co-simulation (--realtime={REALTIME_FACTOR:g})", time.perf_counter() - t0))
            rt = paced.stats.realtime
            if rt:
                print(f"   mean lag {rt['mean_lag'] * 1000:.2f} ms, worst {rt['worst_lag'] * 1000:.2f} ms, {rt['overruns']} overrun(s)")
        _step("analyse, draw and summarise")
        t0 = time.perf_counter()
        draw(runs["exhaustive"], out / "figure.png", stepwise=runs.get("stepwise"))
        timings.append(Timing("figure", time.perf_counter() - t0))
        text = summary(reports, titles, timings, sim_wall, rt, float(TIME_UNIT))
        (out / "summary.md").write_text(text, encoding="utf-8")
    except RobogenError as exc:
        print(render_all(exc.diagnostics, SourceMap()), file=sys.stderr)
        return 1
    failed = [(name, check) for name, r in reports.items() for check, ok in r.checks.items() if not ok]
    for name, r in reports.items():
        print(f"   {titles[name]}: {sum(r.checks.values())}/{len(r.checks)} checks hold")
    for name, check in failed:
        print(f"FAILED ({name}): {check}", file=sys.stderr)
    print(f"wrote {_rel(out / 'results.csv')}, {_rel(out / 'events.jsonl')}, {_rel(out / 'figure.png')}, "
          f"{_rel(out / 'summary.md')} in {time.perf_counter() - started:.1f} s")
    return 1 if failed else 0


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m examples.ur5e.demo", description=__doc__.splitlines()[0])
    p.add_argument("-o", "--output", default=str(OUT), help="output folder (default build/ur5e)")
    p.add_argument("--no-realtime", action="store_true", help="skip the paced run")
    args = p.parse_args(argv)
    return run(Path(args.output), realtime=not args.no_realtime)


if __name__ == "__main__":
    sys.exit(main())
