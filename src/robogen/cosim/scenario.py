"""Scenario files: timed input events and values for one FMU instance (docs/scenarios.md).

A scenario is TOML. :func:`load_scenario` checks its schema (keys, types) and keeps every element's
place in the file; :func:`timeline` checks it against the FMU's model description (the events are
input clocks, their values fit the clocked inputs, no time before the start) and expands it into
a :class:`Timeline`: the occurrences of input events, in time order, each with the FMI variables
and values it sets, and the piecewise-linear course of each input value. Every problem is reported
at its line and column, all together.

The master applies a timeline through an instance of its own, :mod:`robogen.cosim.player`.
Expectations (``[[expect]]``) and the model to build (``model``, ``[options]``) are read by
:mod:`robogen.scenario`; this module keeps them as located raw tables.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field, replace
from pathlib import Path

from robogen.cosim.tomlspan import SpanIndex, read_toml
from robogen.diagnostics import DiagnosticSink, Note, Span, did_you_mean
from robogen.fmu.fmi import same_time, tolerance
from robogen.fmu.modeldesc import ModelDescription, Variable

TOP_KEYS = ("model", "options", "stop", "step", "parameters", "events", "inputs", "expect", "description")
EVENT_KEYS = ("at", "event", "value", "every", "until")
INPUT_KEYS = ("at", "input", "value", "ramp", "until")
_PARAMETER = re.compile(r"^\$\{([A-Za-z_][A-Za-z0-9_]*)\}$")
_INT_BITS = {"Int8": 8, "Int16": 16, "Int32": 32, "Int64": 64, "UInt8": 8, "UInt16": 16, "UInt32": 32, "UInt64": 64}
#: Repeats that would make more occurrences than this are refused (a typo such as every = 1e-9).
MAX_OCCURRENCES = 1_000_000


@dataclass
class Scenario:
    """A scenario file, schema-checked: raw entries with their places (``where`` paths into ``spans``)."""

    path: Path
    text: str
    spans: SpanIndex
    data: dict
    parameters: dict[str, object]  # name -> default value (number, boolean or string)

    def span(self, *where) -> Span:
        return self.spans.span(*where)

    @property
    def events(self) -> list[dict]:
        return self.data.get("events", [])

    @property
    def inputs(self) -> list[dict]:
        return self.data.get("inputs", [])

    @property
    def expectations(self) -> list[dict]:
        return self.data.get("expect", [])

    def number(self, key: str) -> float | None:
        value = self.data.get(key)
        return None if value is None else float(value)


@dataclass(frozen=True)
class Occurrence:
    """One tick of an input clock: at ``time``, with the clocked inputs it sets (scalars by
    variable; arrays, which no connection carries, with their elements)."""

    time: float
    clock: Variable
    values: tuple[tuple[Variable, object], ...]
    span: Span

    @property
    def scalars(self) -> list[tuple[Variable, object]]:
        return [(v, x) for v, x in self.values if not v.dimensions]

    @property
    def arrays(self) -> list[tuple[Variable, list]]:
        return [(v, x) for v, x in self.values if v.dimensions]


@dataclass(frozen=True)
class Segment:
    """An input value from ``start`` on: ``first`` rising linearly to ``last`` at ``end`` (a step:
    ``end == start``), then held."""

    start: float
    end: float
    first: object
    last: object

    def value(self, t: float):
        if t >= self.end or self.end <= self.start:
            return self.last
        return self.first + (self.last - self.first) * (t - self.start) / (self.end - self.start)


@dataclass
class Timeline:
    occurrences: list[Occurrence]
    courses: dict[str, tuple[Variable, list[Segment]]] = field(default_factory=dict)  # input name -> course

    def clocks(self) -> list[Variable]:
        return list({o.clock.name: o.clock for o in self.occurrences}.values())

    def scalars(self, clock: Variable) -> list[Variable]:
        return list({v.name: v for o in self.occurrences if o.clock is clock for v, _x in o.scalars}.values())


# ----------------------------------------------------------------------------------- loading


def load_scenario(path: str | Path) -> Scenario:
    path = Path(path)
    text, data = read_toml(path, "scenario file")
    spans = SpanIndex(text, str(path))
    sink = DiagnosticSink()
    _schema(data, spans, sink)
    sink.raise_if_errors()
    return Scenario(path, text, spans, data, dict(data.get("parameters", {})))


def _schema(data: dict, spans: SpanIndex, sink: DiagnosticSink) -> None:
    for key in data:
        if key not in TOP_KEYS:
            sink.error(f"unknown key '{key}'{did_you_mean(key, TOP_KEYS)}", spans.span(key),
                       Note("a scenario has events, inputs, expect, parameters, stop, step, model, options, description"))
    for key in ("stop", "step"):
        value = data.get(key)
        if value is not None and (isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value)
                                  or (key == "step" and value <= 0)):
            sink.error(f"'{key}' must be a {'positive' if key == 'step' else 'finite'} number", spans.span(key))
    if "model" in data and not isinstance(data["model"], str):
        sink.error("'model' must be the path of the model (a file or folder), relative to this file", spans.span("model"))
    for key in ("options", "parameters"):
        if key in data and not isinstance(data[key], dict):
            sink.error(f"'{key}' must be a table", spans.span(key))
    for name, value in data.get("parameters", {}).items() if isinstance(data.get("parameters"), dict) else ():
        if isinstance(value, (dict, list)):
            sink.error(f"parameter '{name}' must be a number, boolean or string", spans.span("parameters", name))
    for key, allowed, needs in (("events", EVENT_KEYS, ("at", "event")), ("inputs", INPUT_KEYS, ("at", "input")),
                                ("expect", None, ())):
        entries = data.get(key, [])
        if not isinstance(entries, list) or not all(isinstance(e, dict) for e in entries):
            sink.error(f"'{key}' must be a list of tables ([[{key}]] or {key} = [{{ ... }}, ...])", spans.span(key))
            data[key] = []
            continue
        for i, entry in enumerate(entries):
            for k in entry if allowed else ():
                if k not in allowed:
                    sink.error(f"unknown key '{k}' in {key}{did_you_mean(k, allowed)}", spans.span(key, i, k),
                               Note(f"an entry of '{key}' has the keys {', '.join(allowed)}"))
            for k in needs:
                if k not in entry:
                    sink.error(f"this entry of '{key}' needs '{k}'", spans.span(key, i))


# --------------------------------------------------------------------------------- parameters


def substitute(value, parameters: dict[str, object], span: Span, sink: DiagnosticSink):
    """``value`` with every string ``"${name}"`` replaced by the parameter's value (lists and
    tables walked); an unknown parameter is an error at ``span``."""
    if isinstance(value, str):
        m = _PARAMETER.match(value)
        if m is None:
            if "${" in value:
                sink.error(f"'{value}': a parameter is written alone in its string, \"${{name}}\"", span)
            return value
        name = m.group(1)
        if name not in parameters:
            sink.error(f"unknown parameter '{name}'{did_you_mean(name, parameters)}", span,
                       Note("parameters are declared in [parameters]"))
            return None
        return parameters[name]
    if isinstance(value, list):
        return [substitute(v, parameters, span, sink) for v in value]
    if isinstance(value, dict):
        return {k: substitute(v, parameters, span, sink) for k, v in value.items()}
    return value


# ---------------------------------------------------------------------------------- timeline


def input_clocks(md: ModelDescription) -> dict[str, Variable]:
    return {v.name: v for v in md.variables if v.is_clock and v.causality == "input"}


def input_values(md: ModelDescription) -> dict[str, Variable]:
    return {v.name: v for v in md.variables if v.causality == "input" and not v.is_clock and not v.is_clocked}


def timeline(scenario: Scenario, md: ModelDescription, start: float, stop: float,
             parameters: dict[str, object] | None = None) -> Timeline:
    """The scenario's occurrences and input courses from ``start`` to ``stop`` for an FMU of
    model description ``md``; every problem located, all together (RobogenError)."""
    params = {**scenario.parameters, **(parameters or {})}
    sink = DiagnosticSink()
    clocks, values = input_clocks(md), input_values(md)
    occurrences: list[Occurrence] = []
    for i, entry in enumerate(scenario.events):
        occurrences += _event(scenario, md, i, entry, clocks, params, start, stop, sink)
    if len(occurrences) > MAX_OCCURRENCES:
        sink.error(f"the events make {len(occurrences)} occurrences, more than {MAX_OCCURRENCES}", scenario.span("events"))
    occurrences.sort(key=lambda o: o.time)
    _same_instant(occurrences, sink)
    courses: dict[str, tuple[Variable, list[Segment]]] = {}
    for i, entry in enumerate(scenario.inputs):
        found = _input(scenario, i, entry, values, params, start, sink)
        if found is not None:
            var, segment = found
            courses.setdefault(var.name, (var, []))[1].append(segment)
    for name, (_var, segments) in courses.items():
        segments.sort(key=lambda s: s.start)
    sink.raise_if_errors()
    return Timeline(occurrences, courses)


def _time(value, what: str, span: Span, sink: DiagnosticSink) -> float | None:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        if value is not None:
            sink.error(f"'{what}' must be a time in seconds (a finite number), not {value!r}", span)
        return None
    return float(value)


def _event(scenario: Scenario, md: ModelDescription, i: int, entry: dict, clocks: dict[str, Variable],
           params: dict, start: float, stop: float, sink: DiagnosticSink) -> list[Occurrence]:
    where = ("events", i)
    name = entry.get("event")
    span = scenario.span(*where, "event")
    if not isinstance(name, str):
        sink.error("'event' must be the name of an input event (a string)", span)
        return []
    clock = clocks.get(name)
    if clock is None:
        sink.error(f"the FMU has no input event '{name}'{did_you_mean(name, clocks)}", span,
                   Note(f"its input events: {', '.join(sorted(c for c, v in clocks.items() if _triggered(v))) or 'none'}"))
        return []
    if not _triggered(clock):
        sink.error(f"'{name}' is a {clock.interval_variability} clock: it ticks on its own, a scenario ticks only "
                   "triggered input clocks (events)", span)
        return []
    at = _time(substitute(entry.get("at"), params, scenario.span(*where, "at"), sink), "at", scenario.span(*where, "at"), sink)
    every = _time(substitute(entry.get("every"), params, scenario.span(*where, "every"), sink), "every",
                  scenario.span(*where, "every"), sink)
    until = _time(substitute(entry.get("until"), params, scenario.span(*where, "until"), sink), "until",
                  scenario.span(*where, "until"), sink)
    value_span = scenario.span(*where, "value") if "value" in entry else span
    assigned = payload(md, clock, substitute(entry["value"], params, value_span, sink), value_span, sink) \
        if "value" in entry else payload(md, clock, _NO_VALUE, span, sink)
    if at is None or assigned is None:
        return []
    if assigned and all(v.dimensions for v, _x in assigned):
        sink.error(f"event '{name}' carries only an FMI array (a vector or matrix): a scenario cannot drive it, the "
                   "master carries no arrays and the event has no scalar to go with it", value_span)
        return []
    if at < start and not same_time(at, start):
        sink.error(f"event '{name}' at t={at:g} is before the start of the run (t={start:g})", scenario.span(*where, "at"))
        return []
    times = [at]
    if every is not None:
        if every <= tolerance(at):
            sink.error(f"'every' must be a positive time, not {every!r}", scenario.span(*where, "every"))
            return []
        last = stop if until is None else min(until, stop)
        count = math.floor((last - at) / every + 1e-9) + 1 if last >= at else 1
        if count > MAX_OCCURRENCES:
            sink.error(f"'every = {every:g}' repeats event '{name}' {count} times", scenario.span(*where, "every"))
            return []
        times = [at + k * every for k in range(max(count, 1))]
    elif until is not None:
        sink.error("'until' ends a repeat: give 'every' too", scenario.span(*where, "until"))
    return [Occurrence(t, clock, assigned, scenario.span(*where)) for t in times]


def _triggered(clock: Variable) -> bool:
    return clock.interval_variability in (None, "triggered")


def _same_instant(occurrences: list[Occurrence], sink: DiagnosticSink) -> None:
    last: dict[str, Occurrence] = {}
    for o in occurrences:
        before = last.get(o.clock.name)
        if before is not None and same_time(before.time, o.time):
            sink.error(f"event '{o.clock.name}' occurs twice at t={o.time:g}: an input clock ticks once per instant",
                       o.span, Note("the other occurrence", before.span))
        last[o.clock.name] = o


def _input(scenario: Scenario, i: int, entry: dict, values: dict[str, Variable], params: dict, start: float,
           sink: DiagnosticSink) -> tuple[Variable, Segment] | None:
    where = ("inputs", i)
    name = entry.get("input")
    span = scenario.span(*where, "input")
    var = values.get(name) if isinstance(name, str) else None
    if var is None:
        sink.error(f"the FMU has no input value '{name}'{did_you_mean(str(name), values)}", span,
                   Note(f"its input values: {', '.join(sorted(values)) or 'none'}"))
        return None
    at_span = scenario.span(*where, "at")
    at = _time(substitute(entry.get("at"), params, at_span, sink), "at", at_span, sink)
    if at is not None and at < start and not same_time(at, start):
        sink.error(f"input '{name}' changes at t={at:g}, before the start of the run (t={start:g})", at_span)
        return None
    if "ramp" in entry:
        return _ramp(scenario, where, entry, var, at, params, sink)
    if "value" not in entry:
        sink.error(f"give the value of '{name}' from t = at: value = ..., or ramp = [FROM, TO] with until", span)
        return None
    value = convert(var, substitute(entry["value"], params, scenario.span(*where, "value"), sink),
                    scenario.span(*where, "value"), sink, md_types=None)
    if "until" in entry:
        sink.error("'until' ends a ramp: give ramp = [FROM, TO]", scenario.span(*where, "until"))
    return None if at is None or value is BAD else (var, Segment(at, at, value, value))


def _ramp(scenario: Scenario, where: tuple, entry: dict, var: Variable, at: float | None, params: dict,
          sink: DiagnosticSink) -> tuple[Variable, Segment] | None:
    span = scenario.span(*where, "ramp")
    if var.type not in ("Float64", "Float32"):
        sink.error(f"a ramp needs a Float64 input; '{var.name}' is {var.type} (give value = ... for a step)", span)
        return None
    ramp = substitute(entry["ramp"], params, span, sink)
    if (not isinstance(ramp, list) or len(ramp) != 2
            or not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in ramp)):
        sink.error("'ramp' must be [FROM, TO], two numbers", span)
        return None
    until_span = scenario.span(*where, "until")
    until = _time(substitute(entry.get("until"), params, until_span, sink), "until", until_span, sink)
    if until is None:
        sink.error("a ramp needs 'until', the time it reaches its last value", span)
        return None
    if at is None:
        return None
    if until <= at:
        sink.error(f"the ramp ends at t={until:g}, not after it starts (t={at:g})", until_span)
        return None
    return var, Segment(at, until, float(ramp[0]), float(ramp[1]))


# ----------------------------------------------------------------------------------- payloads


class _Bad:
    def __repr__(self) -> str:
        return "<bad value>"


#: What :func:`convert` returns for a value that does not fit its variable (the error is in the sink).
BAD = _Bad()


_NO_VALUE = object()


def clocked_variables(md: ModelDescription, clock: Variable) -> dict[str, Variable]:
    """The clocked variables of ``clock`` of its own causality (an input clock's inputs, an
    output clock's outputs), by name."""
    return {v.name: v for v in md.variables
            if clock.value_reference in v.clocks and not v.is_clock and v.causality == clock.causality}


def payload(md: ModelDescription, clock: Variable, value, span: Span, sink: DiagnosticSink,
            complete: bool = True) -> tuple[tuple[Variable, object], ...] | None:
    """The clocked variables an occurrence of ``clock`` carries, with their values, from a TOML
    ``value`` (a number, a table for a record, an array for a set or sequence); ``complete``:
    every one of them must be given (an input event's), else only those given (an expectation)."""
    carried = clocked_variables(md, clock)
    if value is _NO_VALUE:
        if carried and complete:
            sink.error(f"event '{clock.name}' carries a value: give value = ... ({_shape(carried, clock.name)})", span)
            return None
        return ()
    if not carried:
        sink.error(f"event '{clock.name}' carries no value", span)
        return None
    base = f"{clock.name}.value" if any(n == f"{clock.name}.value" or n.startswith(f"{clock.name}.value.") for n in carried) \
        else clock.name
    out: dict[str, tuple[Variable, object]] = {}
    if not _assign(md, carried, base, value, span, sink, out):
        return None
    missing = sorted(set(carried) - set(out))
    if missing and complete:
        sink.error(f"the value of event '{clock.name}' leaves out {', '.join(missing)}", span,
                   Note(f"the event carries {_shape(carried, clock.name)}"))
        return None
    return tuple(out.values())


def example(md: ModelDescription, clock: Variable):
    """An example ``value`` of an occurrence of ``clock`` (the shape :func:`payload` reads: a
    number, a table for a record, an array for a set or sequence), or None when it carries none."""
    carried = clocked_variables(md, clock)
    if not carried:
        return None
    base = f"{clock.name}.value" if any(n == f"{clock.name}.value" or n.startswith(f"{clock.name}.value.") for n in carried) \
        else clock.name
    return _example(md, carried, base)


def _example(md: ModelDescription, carried: dict[str, Variable], base: str):
    if base in carried:
        var = carried[base]
        one = _example_scalar(md, var)
        return [one] * _length(var) if var.dimensions else one
    if f"{base}.size" in carried:
        if f"{base}.elements" in carried:
            return [_example_scalar(md, carried[f"{base}.elements"])]
        fields = {n[len(base) + len(".elements") + 1:]: v for n, v in carried.items() if n.startswith(f"{base}.elements.")}
        return [_nest({k: _example_scalar(md, v) for k, v in fields.items()})]
    fields = sorted({n[len(base) + 1:].split(".")[0] for n in carried if n.startswith(base + ".")})
    return {f: _example(md, carried, f"{base}.{f}") for f in fields}


def _nest(flat: dict[str, object]) -> dict:
    out: dict = {}
    for path, value in flat.items():
        *parents, last = path.split(".")
        here = out
        for p in parents:
            here = here.setdefault(p, {})
        here[last] = value
    return out


def _example_scalar(md: ModelDescription, var: Variable):
    if var.type == "Enumeration":
        items = next((e.items for e in md.type_definitions if e.name == var.declared_type), ())
        return items[0].name.rpartition(".")[2] if items else 0
    return _zero(var)


def _shape(carried: dict[str, Variable], event: str) -> str:
    return ", ".join(f"{n} ({v.type}{'[' + str(_length(v)) + ']' if v.dimensions else ''})" for n, v in carried.items())


def _length(var: Variable) -> int:
    return math.prod(d.start or 0 for d in var.dimensions)


def _assign(md: ModelDescription, carried: dict[str, Variable], base: str, value, span: Span, sink: DiagnosticSink,
            out: dict) -> bool:
    """Map ``value`` onto the clocked inputs named ``base`` or below it (records as tables, sets
    and sequences as arrays: ``base.elements`` and ``base.size``, or one array per record field)."""
    if base in carried:
        var = carried[base]
        converted = convert(var, value, span, sink, md.type_definitions)
        if converted is BAD:
            return False
        out[base] = (var, converted)
        return True
    if f"{base}.size" in carried:
        return _collection(md, carried, base, value, span, sink, out)
    fields = sorted({n[len(base) + 1:].split(".")[0] for n in carried if n.startswith(base + ".")})
    if not fields:
        sink.error(f"no input '{base}'", span)
        return False
    if not isinstance(value, dict):
        sink.error(f"'{base}' is a record: give a table {{ {', '.join(f + ' = ...' for f in fields)} }}, not {value!r}", span)
        return False
    ok = True
    for key, item in value.items():
        if key not in fields:
            sink.error(f"'{base}' has no field '{key}'{did_you_mean(key, fields)}", span,
                       Note(f"its fields: {', '.join(fields)}"))
            ok = False
        else:
            ok = _assign(md, carried, f"{base}.{key}", item, span, sink, out) and ok
    return ok


def _collection(md: ModelDescription, carried: dict[str, Variable], base: str, value, span: Span,
                sink: DiagnosticSink, out: dict) -> bool:
    size = carried[f"{base}.size"]
    if not isinstance(value, list):
        sink.error(f"'{base}' is a set or sequence: give an array [ ... ], not {value!r}", span)
        return False
    arrays = {n: v for n, v in carried.items() if n == f"{base}.elements" or n.startswith(f"{base}.elements.")}
    capacity = min((_length(v) for v in arrays.values()), default=0)
    if len(value) > capacity:
        sink.error(f"'{base}' holds at most {capacity} elements (--capacity), not {len(value)}", span)
        return False
    out[size.name] = (size, len(value))
    ok = True
    for name, var in arrays.items():
        path = name[len(f"{base}.elements"):].lstrip(".").split(".") if name != f"{base}.elements" else []
        items = []
        for item in value:
            for key in path:
                if not isinstance(item, dict) or key not in item:
                    sink.error(f"each element of '{base}' is a record with field '{'.'.join(path)}'", span)
                    return False
                item = item[key]
            converted = convert(replace(var, dimensions=()), item, span, sink, md.type_definitions)
            ok = ok and converted is not BAD
            items.append(converted)
        if ok:
            out[name] = (var, items + [_zero(var)] * (_length(var) - len(items)))
    return ok


def _zero(var: Variable):
    return {"Boolean": False, "String": "", "Float64": 0.0, "Float32": 0.0}.get(var.type, 0)


def convert(var: Variable, value, span: Span, sink: DiagnosticSink, md_types=None):
    """``value`` (from TOML) as a value of ``var``'s FMI type, or BAD with an error at ``span``.
    An array variable takes a list of its length; an Enumeration an item's name or number."""
    if var.dimensions:
        n = _length(var)
        if not isinstance(value, list) or len(value) != n:
            sink.error(f"'{var.name}' is an array of {n} {var.type} values: give [ ... ] with {n} elements, not {value!r}", span)
            return BAD
        items = [convert(replace(var, dimensions=()), x, span, sink, md_types) for x in value]
        return BAD if any(x is BAD for x in items) else items
    t = var.type
    if value is None:
        return BAD
    if t in ("Float64", "Float32"):
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            return float(value)
    elif t == "Boolean":
        if isinstance(value, bool):
            return value
    elif t == "String":
        if isinstance(value, str):
            return value
    elif t == "Enumeration":
        return _enumeration(var, value, span, sink, md_types)
    elif t in _INT_BITS:
        if isinstance(value, int) and not isinstance(value, bool):
            bits = _INT_BITS[t]
            low, high = (0, 2**bits) if t.startswith("U") else (-(2 ** (bits - 1)), 2 ** (bits - 1))
            if low <= value < high:
                return value
            sink.error(f"{value} is out of range for '{var.name}' ({t})", span)
            return BAD
    sink.error(f"'{var.name}' is {_type_words(t)}, not {value!r}", span)
    return BAD


def _type_words(t: str) -> str:
    if t in ("Float64", "Float32"):
        return f"a {t} (a number)"
    if t == "Boolean":
        return "a Boolean (true or false)"
    if t == "String":
        return "a String (a text in quotes)"
    if t == "Binary":
        return "a Binary, which a scenario cannot give"
    return f"{'a' if t.startswith('U') else 'an'} {t} (an integer)"


def _enumeration(var: Variable, value, span: Span, sink: DiagnosticSink, md_types) -> object:
    items = next((e.items for e in md_types or () if e.name == var.declared_type), ())
    if isinstance(value, int) and not isinstance(value, bool):
        return value
    if isinstance(value, str):
        names = {item.name: item.value for item in items}
        short = {item.name.rpartition(".")[2]: item.value for item in items}
        if value in names or value in short:
            return names.get(value, short.get(value))
        sink.error(f"'{var.name}' has no literal '{value}'{did_you_mean(value, list(short))}", span,
                   Note(f"its literals: {', '.join(short) or 'none'}"))
        return BAD
    sink.error(f"'{var.name}' is an Enumeration: give a literal's name, not {value!r}", span)
    return BAD
