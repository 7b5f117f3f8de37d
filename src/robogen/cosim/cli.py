"""``robogen simulate SYSTEM.toml|SYSTEM.ssp|SYSTEM.ssd [--stop T] [--step H] [-o RESULTS.csv|RESULTS.parquet] [--events E.jsonl] [--realtime[=FACTOR]] [--isolate]``.

Exit status: 0 the run reached its stop time; 1 a problem in the input or an FMU that failed (or
crashed in its worker process, with ``--isolate``); 4 an FMU asked to terminate before the stop
time; 128 + n after signal n (SIGINT 130, SIGTERM 143, SIGHUP 129), with the rows recorded so
far kept. An FMU that crashes this process is reported by a watching process
(:mod:`robogen.cosim.crash`); the exit status is then the signal's (139 for SIGSEGV).
"""

from __future__ import annotations

import argparse
import signal
import sys
from pathlib import Path

from robogen.diagnostics import RobogenError, SourceMap, render_all

#: Exit status when an FMU asked to terminate before the stop time (its results are on disk).
EXIT_TERMINATED = 4
#: Where results go unless -o says otherwise (under build/, like every default output of robogen).
DEFAULT_OUTPUT = Path("build") / "results.csv"
#: The signals that stop a run cleanly.
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


def _factor(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from None
    if not value > 0:
        raise argparse.ArgumentTypeError("the real-time factor must be positive")
    return value


def _number(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from None


def configure(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("system", metavar="SYSTEM.toml|SYSTEM.ssp|MODEL|S.toml",
                        help="the system description: a system file (TOML, docs/system-toml.md) or an SSP (an .ssp "
                             "archive or an .ssd file, docs/ssp.md); with --scenario, the model (or its FMU); or a "
                             "scenario that names its model (docs/scenarios.md)")
    parser.add_argument("--stop", type=_number, help="stop time (overrides [experiment] stop)")
    parser.add_argument("--step", type=_number, help="communication step (overrides [experiment] step)")
    parser.add_argument("-o", "--output", default=str(DEFAULT_OUTPUT),
                        help=f"results file: CSV, or Parquet if it ends in .parquet (default: {DEFAULT_OUTPUT}, "
                             "under the working directory)")
    parser.add_argument("--events", help="write the events log (JSON lines) here")
    parser.add_argument("--realtime", nargs="?", const=1.0, type=_factor, metavar="FACTOR",
                        help="pace the run against the wall clock (FACTOR x real time, default 1)")
    parser.add_argument("--isolate", action="store_true",
                        help="run every FMU instance in a worker process of its own: a crash becomes an error "
                             "and every row is kept (costs a process round trip per FMI call)")
    parser.add_argument("--trace", action="store_true", help="print every FMI call on stderr")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar even on a terminal")


def run(args: argparse.Namespace) -> int:
    from robogen.cosim import simulate_system
    from robogen.cosim.signals import Interrupted, interruptible

    trace = (lambda line: print(line, file=sys.stderr)) if args.trace else None
    try:
        with interruptible(STOP_SIGNALS):
            result = simulate_system(args.system, stop=args.stop, step=args.step, output=args.output, events=args.events,
                                     realtime=args.realtime, progress=False if args.no_progress or args.trace else None,
                                     trace=trace, keep_rows=False, isolate=args.isolate, watch=True)
    except RobogenError as exc:
        print(render_all(exc.diagnostics, SourceMap()), file=sys.stderr)
        say_where_results_are("stopped", getattr(exc, "results", None))
        return 1
    except Interrupted as exc:
        say_where_results_are(f"interrupted ({exc.name})", exc.results)
        return exc.exit_status
    _report(args, result.stats)
    return EXIT_TERMINATED if result.stats.terminated_by else 0


def say_where_results_are(what: str, results: Path | None) -> None:
    kept = f"; results recorded so far are in {results}" if results is not None else "; no results were written"
    print(f"robogen simulate: {what}{kept}", file=sys.stderr)


def _report(args: argparse.Namespace, s) -> None:
    from robogen.cosim.recorder import OVERRUN_SECONDS

    print(f"simulated {args.system} to t={s.end_time!r}: {s.steps} steps, {s.event_iterations} event iterations, "
          f"{s.instants} super-dense instants, {s.early_returns} early returns -> {args.output}", file=sys.stderr)
    if s.terminated_by:
        print(f"robogen simulate: stopped at t={s.end_time!r} before the stop time: {s.terminated_by}; "
              f"results recorded so far are in {args.output}", file=sys.stderr)
    if s.realtime:
        r = s.realtime
        print(f"real time x{r['factor']:g}: mean lag {1000 * r['mean_lag']:.3f} ms, worst lag {1000 * r['worst_lag']:.3f} ms, "
              f"{r['overruns']} overruns (> {1000 * OVERRUN_SECONDS:.0f} ms late) in {r['points']} communication points", file=sys.stderr)
