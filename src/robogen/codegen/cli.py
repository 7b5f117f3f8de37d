"""`robogen compile MODEL...`: write the C sources of an FMI 3.0 FMU generated from a model."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from robogen.codegen.api import compile_model, parse_time_unit
from robogen.codegen.generate import CodegenOptions
from robogen.diagnostics import RobogenError, SourceMap, error, render_all, warning
from robogen.ir.dump import dump
from robogen.ir.lower import LoweringOptions
from robogen.ir.supported import ENUM_DEPTH


def add_model_options(p: argparse.ArgumentParser) -> None:
    """Options shared by `compile` and `package`."""
    which = p.add_mutually_exclusive_group()
    which.add_argument("--module", metavar="NAME", help="the module to compile (default: the only one)")
    which.add_argument("--machine", metavar="NAME", help="compile one state machine (its events and operations are the ports)")
    p.add_argument("--semantics", choices=("exhaustive", "stepwise"), default="exhaustive",
                   help="exhaustive: a whole cycle per event-mode update; stepwise: one transition per update (default: exhaustive)")
    p.add_argument("--trigger", choices=("cycle", "on-input"), default="cycle",
                   help="RoboSim: run a cycle at each tick of 'cycle' (default), or also at any instant an input clock ticks")
    p.add_argument("--time-unit", metavar="SECONDS", default="1",
                   help="seconds per model time unit: the RoboSim period p becomes a clock interval of p x SECONDS; the RoboChart tock period (default 1)")
    p.add_argument("--time", choices=("skip", "tick"), default="skip",
                   help="RoboChart time: skip (default) - the FMU counts its tocks itself and announces as nextEventTime the "
                        "next time unit at which anything can happen, so a master steps over idle time; tick - an input "
                        "clock tock that the master ticks every time unit (RoboSim FMUs always tick their cycle clock)")
    p.add_argument("--set", metavar="NAME=VALUE", action="append", default=[],
                   help="value of a model constant (repeatable); a constant the model leaves without a value is otherwise an FMU "
                        "parameter that starts at its type's default (0, 0.0, false, the first literal), set by the importer")
    p.add_argument("--given-type", choices=("int", "nat", "real"), default="int", help="the scalar type of given types (default int)")
    p.add_argument("--max-transitions", type=int, default=1000, metavar="N",
                   help="transitions per cycle before a runaway cycle is reported (default 1000)")
    p.add_argument("--capacity", default="32", metavar="N[,N...]",
                   help="the most elements a set or sequence holds (default 32); a result with more is a run-time "
                        "fmi3Error naming the expression and its model line. One number for every nesting level of "
                        "collections, or one per level, outermost first, the last for deeper levels (32,8,4: a "
                        "Seq(Seq(int)) holds 32 sequences of at most 8 numbers; docs/collections.md)")
    p.add_argument("--enum-depth", default=str(ENUM_DEPTH), metavar="N",
                   help=f"the levels a value of a recursive enumeration holds (default {ENUM_DEPTH}, at most 16); a deeper "
                        "one is a run-time fmi3Error naming the expression and its model line (docs/collections.md)")
    p.add_argument("--functions", metavar="FILE.c",
                   help="C file implementing the model's functions whose result no postcondition pins, each as static <type> "
                        "rg_user_<name>(...) (a generic one per instantiation: rg_user_<name>__<type>)")
    p.add_argument("--no-line-comments", action="store_true", help="leave the model file:line out of the generated C comments")


def options_from(args: argparse.Namespace) -> LoweringOptions:
    settings = {}
    for item in args.set:
        name, sep, value = item.partition("=")
        if not sep or not name.strip():
            raise RobogenError(error(f"--set expects NAME=VALUE, not {item!r}", None))
        settings[name.strip()] = value
    if args.max_transitions < 1:
        raise RobogenError(error("--max-transitions must be at least 1", None))
    capacities = _bounds("--capacity", args.capacity, 1, 1 << 20, several=True)
    (enum_depth,) = _bounds("--enum-depth", args.enum_depth, 0, 16, several=False)
    return LoweringOptions(
        semantics=args.semantics,
        trigger=args.trigger,
        time_unit=parse_time_unit(args.time_unit),
        settings=settings,
        given=args.given_type,
        max_steps=args.max_transitions,
        capacity=capacities[0],
        capacities=capacities if len(capacities) > 1 else (),
        enum_depth=enum_depth,
        time=args.time,
    )


def _bounds(option: str, text: object, low: int, high: int, several: bool) -> tuple[int, ...]:
    """The bounds of the finite shape of values an option gives (robogen.ir.supported.Shapes):
    ``--capacity N[,N...]`` (one per nesting level: ``several``), ``--enum-depth N``, each
    between ``low`` and ``high``."""
    try:
        values = tuple(int(x) for x in str(text).split(","))
    except ValueError:
        values = ()
    if not values or (len(values) > 1 and not several) or not all(low <= v <= high for v in values):
        levels = ", or one per nesting level separated by commas (32,8,4)" if several else ""
        raise RobogenError(error(f"{option} {text}: give a number between {low} and {high}{levels}", None))
    return values


def codegen_options_from(args: argparse.Namespace) -> CodegenOptions:
    return CodegenOptions(line_comments=not args.no_line_comments, functions=Path(args.functions) if args.functions else None)


def print_warnings(fmu, args: argparse.Namespace) -> None:
    """What lowering warned about, and a --functions file the model has no use for, on stderr
    (the command goes on)."""
    found = list(fmu.warnings)
    if args.functions and not fmu.user_functions:
        found.append(warning(f"--functions {args.functions}: the model calls no user function; the file is not used", None))
    if found:
        print(render_all(found, SourceMap()), file=sys.stderr)


def configure(p: argparse.ArgumentParser) -> None:
    p.add_argument("paths", nargs="+", metavar="MODEL", help="model files and/or directories (one workspace)")
    add_model_options(p)
    p.add_argument("-o", "--output", metavar="DIR", help="output folder (default: build/<ModelIdentifier>)")
    p.add_argument("--dump-ir", action="store_true", help="also print the IR (robogen's canonical text form)")


def run(args: argparse.Namespace) -> int:
    compiled = compile_model(args.paths, args.output, module=args.module, machine=args.machine,
                             options=options_from(args), codegen=codegen_options_from(args))
    print_warnings(compiled.fmu, args)
    if args.dump_ir:
        sys.stdout.write(dump(compiled.fmu))
    n = len(compiled.generated.variables)
    print(f"wrote {compiled.folder}/ ({compiled.fmu.model_identifier}: {len(compiled.fmu.machines)} state machine(s), "
          f"{n} FMI variables, {compiled.fmu.semantics} semantics)", file=sys.stderr)
    return 0
