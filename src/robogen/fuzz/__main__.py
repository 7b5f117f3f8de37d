"""``python -m robogen.fuzz``: the model fuzzer (see docs/fuzzing.md).

    python -m robogen.fuzz --count 2000 --seed 1            # the table, then the summary line
    python -m robogen.fuzz --print 1.17                      # the text of model 17 of seed 1
    python -m robogen.fuzz --model 1.17 --sanitize           # check that one model, and say why it fails

Exit status 1 when a model fails a property, 0 otherwise, 2 for a wrong command line; 130 for a
run stopped by SIGINT or SIGTERM (the table and the summary line count the models checked).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from robogen.fuzz.features import FEATURES, features
from robogen.fuzz.properties import Budget


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m robogen.fuzz", description="Generate random RoboChart and RoboSim models "
                                "and check that each prints, checks, packages and runs as the reference interpreter does.")
    p.add_argument("--seed", default="1", help="the run's seed (model i is generated from SEED.i)")
    p.add_argument("--count", "-n", type=int, default=100, help="how many models")
    p.add_argument("--jobs", "-j", type=int, default=2, help="worker processes")
    p.add_argument("--with", dest="with_", action="append", default=[], metavar="FEATURE", help="switch a feature on")
    p.add_argument("--without", action="append", default=[], metavar="FEATURE", help="switch a feature off")
    p.add_argument("--features", action="store_true", help="list the features and exit")
    p.add_argument("--scenarios", type=int, default=6, help="random scenarios per model and semantics")
    p.add_argument("--instants", type=int, default=16, help="time instants per scenario")
    p.add_argument("--sanitize-every", type=int, default=20, help="run the sanitizers on one model in this many (0: never)")
    p.add_argument("--sanitize", action="store_true", help="run the sanitizers on every model")
    p.add_argument("--no-validate", action="store_true", help="do not validate the FMUs (faster)")
    p.add_argument("--optimise-all", action="store_true", help="build both semantics' FMUs with the product's -O2 "
                   "(by default one of them, in turn, the other at -O0)")
    p.add_argument("--optimise-every", type=int, default=1, metavar="K",
                   help="build with the product's -O2 and validate on one model in K only (the others: both "
                   "semantics at -O0 with the same warning flags; faster)")
    p.add_argument("--shrink-seconds", type=float, default=300.0, help="time to shrink a failure (0: do not shrink)")
    p.add_argument("--regressions", type=Path, default=Path("fuzz-regressions"),
                   help="where shrunk failures are written (make fuzz: the repository's regression tests)")
    p.add_argument("--work", type=Path, default=None, help="where models are built (default: a temporary folder)")
    p.add_argument("--print", dest="print_seed", metavar="SEED.I", help="print the text of one model and exit")
    p.add_argument("--model", metavar="SEED.I", help="check one model and exit")
    p.add_argument("--quiet", "-q", action="store_true", help="no line per model while running")
    return p


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    if args.features:
        for f in FEATURES:
            print(f"{'on ' if f.default else 'off'}  {f.name:<24} {f.what}" + (f"\n     {'':<24} off: {f.why_off}" if f.why_off else ""))
        return 0
    try:
        on = features(args.with_, args.without)
    except ValueError as exc:
        print(f"python -m robogen.fuzz: {exc}", file=sys.stderr)
        return 2
    budget = Budget(args.scenarios, args.instants, args.sanitize, not args.no_validate)
    if args.print_seed:
        from robogen.fuzz.model import generate

        print(generate(args.print_seed, on).text(), end="")
        return 0
    from robogen.fuzz.runner import Settings, check_one, run

    settings = Settings(args.seed, args.count, on, args.jobs, args.sanitize_every, args.sanitize, args.shrink_seconds,
                        args.regressions, budget=budget, work=args.work, optimise_all=args.optimise_all,
                        optimise_every=args.optimise_every)
    if args.model:
        outcome = check_one(args.model, settings, budget)
        print(f"model {args.model} ({outcome.language}): passed {', '.join(outcome.passed) or 'nothing'}"
              + (f"; not supported: {outcome.unsupported}" if outcome.unsupported else ""))
        if outcome.failure is not None:
            print(f"{outcome.failure.prop} ({outcome.failure.kind}): {outcome.failure.message}")
        return 1 if outcome.failure is not None else 0
    report = run(settings, sys.stdout, None if args.quiet else lambda line: print(line, file=sys.stderr, flush=True))
    if report.failed:
        return 1
    return 130 if report.interrupted else 0  # (an interrupted run passed only as far as it went)


if __name__ == "__main__":
    sys.exit(main())
