"""``robogen simulate``: a system file (robogen.cosim.cli), or a model driven by a scenario.

``robogen simulate MODEL --scenario S.toml [--semantics ...] [-o RESULTS.csv] [--events E.jsonl]
[--plot TRACE.png]`` packages the model (cached by content: robogen.scenarios.build), runs the
scenario on it (robogen.scenarios.run), writes the results and the events log, and, with
``--plot``, a figure of the trace: the model's events as stems, each machine's state as a step line
named by its states. ``robogen simulate S.toml`` alone runs the scenario's own ``model``.
The options of ``robogen package`` given here override the scenario's ``[options]``.
Exit status as for a system file: 0, 1 (a problem in the input or a failing FMU), 4 (an FMU asked
to terminate), 128 + n after signal n.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from robogen.codegen.cli import add_model_options
from robogen.cosim import cli as system_cli
from robogen.diagnostics import RobogenError, SourceMap, Span, error, render_all
from robogen.scenarios.build import MODEL_SUFFIXES, parse_options


def configure(parser: argparse.ArgumentParser) -> None:
    system_cli.configure(parser)
    parser.add_argument("--scenario", metavar="S.toml",
                        help="drive the model given in place of SYSTEM with this scenario (docs/scenarios.md)")
    parser.add_argument("--plot", metavar="TRACE.png", help="with a scenario: draw the trace (events, states)")
    parser.add_argument("--reference", action="store_true",
                        help="with a scenario: run the model on the reference interpreter (robogen.ir.interp), not its FMU")
    group = parser.add_argument_group("model options (with --scenario: those of 'robogen package')")
    add_model_options(group)
    # a model option left out is None, so that those given override the scenario's [options]
    parser.set_defaults(**{key: None for key in vars(parse_options([], None))})


def _is_scenario_alone(args: argparse.Namespace) -> bool:
    """SYSTEM is a scenario file (it has no [instances] but events, inputs, expect or a model)."""
    import tomllib

    try:
        data = tomllib.loads(Path(args.system).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
        return False  # the system file's own checks report it
    return "instances" not in data and any(k in data for k in ("events", "inputs", "expect", "model"))


def run(args: argparse.Namespace) -> int:
    if args.scenario is None and not _is_scenario_alone(args):
        target = Path(args.system)
        if target.suffix in MODEL_SUFFIXES + (".fmu",) or target.is_dir():
            print(render_all([error(f"{target} is a model: drive it with a scenario, --scenario S.toml "
                                    f"(robogen scenario --template {target} -o S.toml writes one)",
                                    Span.of_path(str(target)))], SourceMap()), file=sys.stderr)
            return 1
        return system_cli.run(args)
    from robogen.cosim.signals import Interrupted, interruptible

    scenario, model = (args.scenario, [args.system]) if args.scenario else (args.system, None)
    given = argparse.Namespace(**{k: v for k, v in vars(args).items() if k in vars(parse_options([], None)) and v is not None})
    try:
        with interruptible(system_cli.STOP_SIGNALS):
            done = _run(args, scenario, model, given)
    except RobogenError as exc:
        print(render_all(exc.diagnostics, SourceMap()), file=sys.stderr)
        system_cli.say_where_results_are("stopped", getattr(exc, "results", None))
        return 1
    except Interrupted as exc:
        system_cli.say_where_results_are(f"interrupted ({exc.name})", exc.results)
        return exc.exit_status
    return system_cli.EXIT_TERMINATED if done.result.stats.terminated_by else 0


def _run(args: argparse.Namespace, scenario: str, model: list[str] | None, given: argparse.Namespace):
    from robogen.scenarios.run import run_scenario

    def built(b) -> None:
        if b.given:
            return
        how = f"built the FMU in {b.seconds:.2f} s" if b.compiled else f"the FMU is unchanged: from the cache in {b.seconds:.3f} s"
        print(f"robogen simulate: {how} ({b.fmu})", file=sys.stderr)

    events = args.events or str(Path(args.output).with_suffix(".events.jsonl"))
    done = run_scenario(scenario, model, given, stop=args.stop, step=args.step, output=args.output, events=events,
                        progress=False if args.no_progress else None, keep_rows=False, on_built=built,
                        reference=args.reference)
    s = done.result.stats
    print(f"simulated {scenario} to t={s.end_time!r}: {s.steps} steps, {s.event_iterations} event iterations, "
          f"{s.instants} super-dense instants -> {args.output}, events log {events}", file=sys.stderr)
    if s.terminated_by:
        print(f"robogen simulate: stopped at t={s.end_time!r} before the stop time: {s.terminated_by}", file=sys.stderr)
    if args.plot:
        from robogen.scenarios.trace import plot_trace

        print(f"wrote {plot_trace(Path(args.output), Path(args.plot), done.md)}", file=sys.stderr)
    return done
