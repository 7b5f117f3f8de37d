"""``robogen simulate SYSTEM.toml [--stop T] [--step H] [-o RESULTS.csv] [--events E.jsonl] [--realtime[=FACTOR]]``."""

from __future__ import annotations

import argparse
import sys

from robogen.diagnostics import RobogenError, SourceMap, render_all

#: Exit status when an FMU asked to terminate before the stop time (its results are on disk).
EXIT_TERMINATED = 4


def _factor(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from None
    if not value > 0:
        raise argparse.ArgumentTypeError("the real-time factor must be positive")
    return value


def _positive(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from None


def configure(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("system", help="the system description (TOML, see docs/system-toml.md)")
    parser.add_argument("--stop", type=_positive, help="stop time (overrides [experiment] stop)")
    parser.add_argument("--step", type=_positive, help="communication step (overrides [experiment] step)")
    parser.add_argument("-o", "--output", default="results.csv", help="results CSV (default: results.csv)")
    parser.add_argument("--events", help="write the events log (JSON lines) here")
    parser.add_argument("--realtime", nargs="?", const=1.0, type=_factor, metavar="FACTOR",
                        help="pace the run against the wall clock (FACTOR x real time, default 1)")
    parser.add_argument("--trace", action="store_true", help="print every FMI call on stderr")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar even on a terminal")


def run(args: argparse.Namespace) -> int:
    from robogen.cosim import simulate_system
    from robogen.cosim.recorder import OVERRUN_SECONDS

    trace = (lambda line: print(line, file=sys.stderr)) if args.trace else None
    try:
        result = simulate_system(args.system, stop=args.stop, step=args.step, output=args.output, events=args.events,
                                 realtime=args.realtime, progress=False if args.no_progress or args.trace else None,
                                 trace=trace, keep_rows=False)
    except RobogenError as exc:
        print(render_all(exc.diagnostics, SourceMap()), file=sys.stderr)
        print(f"robogen simulate: stopped; results recorded so far are in {args.output}", file=sys.stderr)
        return 1
    s = result.stats
    print(f"simulated {args.system} to t={s.end_time!r}: {s.steps} steps, {s.event_iterations} event iterations, "
          f"{s.instants} super-dense instants, {s.early_returns} early returns -> {args.output}", file=sys.stderr)
    if s.terminated_by:
        print(f"robogen simulate: stopped at t={s.end_time!r} before the stop time: {s.terminated_by}; "
              f"results recorded so far are in {args.output}", file=sys.stderr)
    if s.realtime:
        r = s.realtime
        print(f"real time x{r['factor']:g}: mean lag {1000 * r['mean_lag']:.3f} ms, worst lag {1000 * r['worst_lag']:.3f} ms, "
              f"{r['overruns']} overruns (> {1000 * OVERRUN_SECONDS:.0f} ms late) in {r['points']} communication points", file=sys.stderr)
    return EXIT_TERMINATED if s.terminated_by else 0
