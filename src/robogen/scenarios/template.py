"""``robogen scenario --template MODEL_OR_FMU -o s.toml``: a commented skeleton of a scenario.

The skeleton lists every input event of the FMU (its triggered input clocks) with the type of
its value and an example line, every input value, and, as examples of expectations, its output
events and the states of its machines. It is valid TOML that runs as it is (nothing happens
until an example line is uncommented). Given a model, it also names the model and the options
given, so that ``robogen simulate s.toml``-style runs and ``robogen test`` find it.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from pathlib import Path

from robogen.codegen.cli import add_model_options
from robogen.cosim.scenario import clocked_variables, example, input_clocks, input_values
from robogen.diagnostics import RobogenError, Span
from robogen.fmu.modeldesc import ModelDescription
from robogen.outputs import output_file, write_text


def configure(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--template", metavar="MODEL_OR_FMU", nargs="+", required=True,
                        help="the model (files or folders) or the .fmu whose inputs the skeleton lists")
    parser.add_argument("-o", "--output", metavar="S.toml", required=True, help="the scenario file to write")
    parser.add_argument("--stop", type=float, default=10.0, help="the stop time written in the skeleton (default 10)")
    add_model_options(parser)


def toml(value) -> str:
    """A value as inline TOML (bare keys where they are identifiers)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value) if math.isfinite(value) else ("nan" if math.isnan(value) else ("inf" if value > 0 else "-inf"))
    if isinstance(value, int):
        return str(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + ", ".join(toml(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{ " + ", ".join(f"{k if k.isidentifier() else json.dumps(k)} = {toml(v)}" for k, v in value.items()) + " }"
    raise TypeError(f"no TOML for {value!r}")


def _kind(md: ModelDescription, clock) -> str:
    """What an occurrence of ``clock`` carries, in words: no value, a Float64, a record
    { x: Int64, y: Int64 }, a set or sequence of UInt64 (at most 32)."""
    carried = clocked_variables(md, clock)
    if not carried:
        return "no value"
    value = f"{clock.name}.value"
    base = value if any(n == value or n.startswith(value + ".") for n in carried) else clock.name
    return _describe(md, carried, base)


def _describe(md: ModelDescription, carried: dict, base: str) -> str:
    if base in carried:
        var = carried[base]
        size = math.prod(d.start or 0 for d in var.dimensions)
        return f"{_scalar(md, var)}" + (f" array of {size}" if var.dimensions else "")
    if f"{base}.size" in carried:
        arrays = {n: v for n, v in carried.items() if n.startswith(f"{base}.elements")}
        size = min(math.prod(d.start or 0 for d in v.dimensions) for v in arrays.values())
        if f"{base}.elements" in carried:
            what = _scalar(md, carried[f"{base}.elements"])
        else:
            what = "records { " + ", ".join(f"{n[len(base) + 10:]}: {_scalar(md, v)}" for n, v in arrays.items()) + " }"
        return f"a set or sequence of {what} (at most {size})"
    fields = sorted({n[len(base) + 1:].split(".")[0] for n in carried if n.startswith(base + ".")},
                    key=lambda f: min(v.value_reference for n, v in carried.items() if n.startswith(f"{base}.{f}")))
    return "a record { " + ", ".join(f"{f}: {_describe(md, carried, f'{base}.{f}')}" for f in fields) + " }"


def _scalar(md: ModelDescription, var) -> str:
    if var.type == "Enumeration":
        items = next((e.items for e in md.type_definitions if e.name == var.declared_type), ())
        return "one of " + ", ".join(i.name.rpartition(".")[2] for i in items)
    return var.type


def skeleton(md: ModelDescription, *, model: str | None, options: dict, stop: float) -> str:
    periodic = [v for v in md.variables if v.is_clock and v.causality == "input" and v.interval]
    lines = [f"# A scenario for {md.model_name} (robogen scenario --template; the format: docs/scenarios.md).",
             "# Uncomment and edit the example lines; times are in seconds."]
    if model is not None:
        lines += [f"model = {json.dumps(model)}  # relative to this file"]
        if options:
            lines += [f"options = {toml(options)}  # the options of 'robogen package', without the dashes"]
    lines += [f"stop = {toml(float(stop))}"]
    if periodic:
        clock = min(periodic, key=lambda v: v.interval)
        lines += [f"step = {toml(clock.interval)}  # the period of '{clock.name}'"]
    lines += ["", "# Input events: one entry per occurrence; every = SECONDS (and until = T) repeats it;",
              "# at = \"${name}\" takes a value of [parameters].", "events = ["]
    for clock in input_clocks(md).values():
        if clock.interval_variability not in (None, "triggered"):
            continue
        value = example(md, clock)
        entry = {"at": 1.0, "event": clock.name, **({"value": value} if value is not None else {})}
        lines += [f"  # {clock.name}: {_kind(md, clock)}", f"  # {toml(entry)},"]
    lines += ["]"]
    values = input_values(md)
    if values:
        lines += ["", "# Input values: a step (value) or, for a Float64, a ramp = [FROM, TO] until a time.", "inputs = ["]
        for name, var in values.items():
            lines += [f"  # {name}: {var.type}", f"  # {toml({'at': 1.0, 'input': name, 'value': example_value(var)})},"]
        lines += ["]"]
    lines += ["", "[parameters]", "# t_first = 1.0", ""] + _expect_examples(md)
    return "\n".join(lines) + "\n"


def example_value(var):
    return {"Boolean": False, "String": ""}.get(var.type, 0.0 if var.type.startswith("Float") else 0)


def _expect_examples(md: ModelDescription) -> list[str]:
    lines = ["# Expectations ('robogen test'): an output event occurs (or not: occurs = false) within a window,",
             "# with a value; a machine rests in a state at a time; an output lies in a range at a time."]
    for clock in (v for v in md.variables if v.is_clock and v.causality == "output"):
        value = example(md, clock)
        lines += [f"# output event {clock.name}: {_kind(md, clock)}", "# [[expect]]", f"# event = {json.dumps(clock.name)}",
                  "# within = [0.0, 1.0]"] + ([f"# value = {toml(value)}"] if value is not None else [])
    for var in md.variables:
        if var.causality == "output" and var.type == "Enumeration" and var.name.endswith(".state"):
            items = next((t.items for t in md.type_definitions if t.name == var.declared_type), ())
            names = [i.name.rpartition(".")[2] for i in items]
            lines += [f"# machine {var.name.removesuffix('.state')}: states {', '.join(names)}", "# [[expect]]",
                      f"# state = {json.dumps(names[min(1, len(names) - 1)] if names else '')}", "# at = 1.0"]
            if sum(1 for v in md.variables if v.name.endswith(".state") and v.type == "Enumeration") > 1:
                lines += [f"# machine = {json.dumps(var.name.removesuffix('.state'))}"]
    return lines


def given_options(args: argparse.Namespace) -> dict:
    """The model options that differ from their defaults, as an [options] table."""
    from robogen.scenarios.build import parse_options

    defaults = vars(parse_options([], None))
    out = {}
    for key, default in defaults.items():
        value = getattr(args, key, default)
        if value != default:
            out[key] = {n: v for n, _, v in (s.partition("=") for s in value)} if key == "set" else value
    return out


def run(args: argparse.Namespace) -> int:
    from robogen.scenarios.build import model_fmu
    from robogen.scenarios.run import fmu_description

    paths = args.template
    output = output_file(args.output, inputs=paths)
    if len(paths) == 1 and paths[0].endswith(".fmu"):
        if not Path(paths[0]).is_file():
            raise RobogenError.at(f"FMU not found: {paths[0]}", Span.of_path(paths[0]))
        md, model, options = fmu_description(Path(paths[0])), None, {}
    else:
        if len(paths) > 1:
            raise RobogenError.at("a scenario names one model path (a file or a folder)", Span.of_path(paths[1]))
        md = fmu_description(model_fmu(paths, args).fmu)
        model = os.path.relpath(Path(paths[0]).resolve(), output.resolve().parent)
        options = given_options(args)
    write_text(output, skeleton(md, model=model, options=options, stop=args.stop))
    print(f"wrote {output}", file=sys.stderr)
    return 0
