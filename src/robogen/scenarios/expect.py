"""Expectations of a scenario (``[[expect]]``), checked against the rows of its run.

Four kinds, each an entry of ``[[expect]]`` (docs/scenarios.md):

- ``event = "E"``: output event E occurs (``occurs = false``: does not) within ``within = [T0, T1]``
  (default: the whole run), with ``value`` (a number, a table for a record: only the fields given
  are compared) if given, ``count`` times if given;
- ``state = "S"`` at ``at = T``: the machine (``machine = "M"``, needed when the FMU has several)
  rests in state S at T, after the last super-dense instant of T;
- ``output = "V"`` at ``at = T``: the output V lies in ``range = [LOW, HIGH]`` or equals ``value``;
- and, for every scenario, the run ends without error (reported first, as ``the run``).

Each expectation is checked against the model description before the run (names, types: located
errors) and gives one :class:`Outcome` after it: passed or not, with what was found.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from robogen.cosim import SimulationResult
from robogen.cosim.scenario import BAD, Scenario, convert, payload, substitute
from robogen.diagnostics import DiagnosticSink, Note, Span, did_you_mean
from robogen.fmu.fmi import same_time
from robogen.fmu.modeldesc import ModelDescription, Variable

KINDS = {
    "event": ("event", "occurs", "within", "value", "count"),
    "state": ("state", "machine", "at"),
    "output": ("output", "at", "range", "value"),
}


@dataclass(frozen=True)
class Expectation:
    kind: str
    text: str  # what it says, for the pass/fail line
    span: Span
    name: str  # the FMI variable (event clock, state output, output)
    occurs: bool = True
    window: tuple[float, float] | None = None
    values: tuple[tuple[Variable, object], ...] = ()
    count: int | None = None
    at: float | None = None
    low: object = None
    high: object = None
    literal: int | None = None  # a state's number in the Enumeration


@dataclass(frozen=True)
class Outcome:
    expectation: Expectation | None  # None: the run itself
    passed: bool
    detail: str  # what was found (for a failure: why)
    span: Span
    text: str


def expectations(scenario: Scenario, md: ModelDescription) -> list[Expectation]:
    """The scenario's expectations, checked against the FMU's model description (RobogenError)."""
    sink = DiagnosticSink()
    found = []
    for i, entry in enumerate(scenario.expectations):
        span = scenario.span("expect", i)
        entry = substitute(entry, scenario.parameters, span, sink)
        kinds = [k for k in KINDS if k in entry]
        if len(kinds) != 1:
            sink.error("an expectation names one of event = ..., state = ..., output = ...", span)
            continue
        kind = kinds[0]
        for key in entry:
            if key not in KINDS[kind]:
                sink.error(f"unknown key '{key}' in an expectation of {kind}{did_you_mean(key, KINDS[kind])}",
                           scenario.span("expect", i, key), Note(f"it takes {', '.join(KINDS[kind])}"))
        made = {"event": _event, "state": _state, "output": _output}[kind](entry, md, span, sink)
        if made is not None:
            found.append(made)
    sink.raise_if_errors()
    return found


def _number(value, what: str, span: Span, sink: DiagnosticSink) -> float | None:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        sink.error(f"'{what}' must be a number, not {value!r}", span)
        return None
    return float(value)


def _pair(value, what: str, span: Span, sink: DiagnosticSink) -> tuple[float, float] | None:
    if not isinstance(value, list) or len(value) != 2:
        sink.error(f"'{what}' must be [FROM, TO], two numbers", span)
        return None
    a, b = (_number(x, what, span, sink) for x in value)
    if a is None or b is None:
        return None
    if b < a:
        sink.error(f"'{what}' = [{a:g}, {b:g}] is empty", span)
        return None
    return a, b


def _event(entry: dict, md: ModelDescription, span: Span, sink: DiagnosticSink) -> Expectation | None:
    clocks = {v.name: v for v in md.variables if v.is_clock and v.causality == "output"}
    name = entry["event"]
    clock = clocks.get(name)
    if clock is None:
        sink.error(f"the FMU has no output event '{name}'{did_you_mean(str(name), clocks)}", span,
                   Note(f"its output events: {', '.join(clocks) or 'none'}"))
        return None
    occurs = entry.get("occurs", True)
    if not isinstance(occurs, bool):
        sink.error("'occurs' must be true or false", span)
        return None
    window = _pair(entry["within"], "within", span, sink) if "within" in entry else None
    values = payload(md, clock, entry["value"], span, sink, complete=False) if "value" in entry else ()
    count = entry.get("count")
    if count is not None and (isinstance(count, bool) or not isinstance(count, int) or count < 0):
        sink.error("'count' must be a whole number", span)
        return None
    if values is None or ("within" in entry and window is None):
        return None
    text = (f"event '{name}' {'occurs' if occurs else 'does not occur'}"
            + (f" {count} time{'s' if count != 1 else ''}" if count is not None else "")
            + (f" within [{window[0]:g}, {window[1]:g}]" if window else "")
            + (f" with {_show(values)}" if values else ""))
    return Expectation("event", text, span, name, occurs, window, values, count)


def _state(entry: dict, md: ModelDescription, span: Span, sink: DiagnosticSink) -> Expectation | None:
    outputs = {v.name.removesuffix(".state"): v for v in md.variables
               if v.causality == "output" and v.type == "Enumeration" and v.name.endswith(".state")}
    machine = entry.get("machine")
    if machine is None:
        if len(outputs) != 1:
            sink.error(f"the FMU has {len(outputs)} state machines: say which with machine = \"...\"", span,
                       Note(f"its machines: {', '.join(outputs) or 'none'}"))
            return None
        machine = next(iter(outputs))
    var = outputs.get(machine)
    if var is None:
        sink.error(f"the FMU has no state machine '{machine}'{did_you_mean(str(machine), outputs)}", span)
        return None
    items = next((t.items for t in md.type_definitions if t.name == var.declared_type), ())
    names = {item.name.rpartition(".")[2]: item.value for item in items}
    state = entry["state"]
    at = _number(entry.get("at"), "at", span, sink) if "at" in entry else None
    if "at" not in entry:
        sink.error("a state expectation needs 'at', the time", span)
    if state not in names:
        sink.error(f"machine '{machine}' has no state '{state}'{did_you_mean(str(state), names)}", span,
                   Note(f"its nodes: {', '.join(names)}"))
        return None
    if at is None:
        return None
    return Expectation("state", f"'{machine}' is in state {state} at t={at:g}", span, var.name, at=at, literal=names[state])


def _output(entry: dict, md: ModelDescription, span: Span, sink: DiagnosticSink) -> Expectation | None:
    outputs = {v.name: v for v in md.variables if v.causality == "output" and not v.is_clock and not v.is_clocked
               and not v.dimensions}
    name = entry["output"]
    var = outputs.get(name)
    if var is None:
        sink.error(f"the FMU has no output '{name}'{did_you_mean(str(name), outputs)}", span,
                   Note("an output here is a value output, not clocked (an event's value: event = ..., value = ...)"))
        return None
    at = _number(entry.get("at"), "at", span, sink) if "at" in entry else None
    if "at" not in entry:
        sink.error("an output expectation needs 'at', the time", span)
    if ("range" in entry) == ("value" in entry):
        sink.error("give range = [LOW, HIGH] or value = ...", span)
        return None
    if "range" in entry:
        bounds = _pair(entry["range"], "range", span, sink)
        if bounds is None or at is None:
            return None
        return Expectation("output", f"'{name}' lies in [{bounds[0]:g}, {bounds[1]:g}] at t={at:g}", span, name,
                           at=at, low=bounds[0], high=bounds[1])
    values = payload_of_output(md, var, entry["value"], span, sink)
    if values is None or at is None:
        return None
    return Expectation("output", f"'{name}' = {entry['value']!r} at t={at:g}", span, name, at=at, low=values, high=values)


def payload_of_output(md: ModelDescription, var: Variable, value, span: Span, sink: DiagnosticSink):
    converted = convert(var, value, span, sink, md.type_definitions)
    return None if converted is BAD else converted


def _show(values) -> str:
    return ", ".join(f"{v.name} = {x!r}" for v, x in values)


# -------------------------------------------------------------------------------------- checking


def check(expected: list[Expectation], result: SimulationResult, instance: str) -> list[Outcome]:
    """Each expectation against the rows of the run (columns ``instance.<variable>``)."""
    index = {name: i for i, name in enumerate(result.columns)}
    return [_check(e, result.rows, index, instance) for e in expected]


def _check(e: Expectation, rows: list[list], index: dict[str, int], instance: str) -> Outcome:
    if e.kind == "event":
        return _check_event(e, rows, index, instance)
    column = index.get(f"{instance}.{e.name}")
    if column is None:
        return Outcome(e, False, f"'{e.name}' was not recorded", e.span, e.text)
    at_rows = [r for r in rows if r[0] <= e.at or same_time(r[0], e.at)]
    if not at_rows:
        return Outcome(e, False, f"the run has no row at or before t={e.at:g}", e.span, e.text)
    value = at_rows[-1][column]
    if e.kind == "state":
        return Outcome(e, value == e.literal, f"found node number {value}" if value != e.literal else "", e.span, e.text)
    ok = value is not None and e.low <= value <= e.high
    return Outcome(e, ok, "" if ok else f"found {value!r}", e.span, e.text)


def _check_event(e: Expectation, rows: list[list], index: dict[str, int], instance: str) -> Outcome:
    clock = index.get(f"{instance}.{e.name}")
    if clock is None:
        return Outcome(e, False, f"'{e.name}' was not recorded", e.span, e.text)
    ticks, outside = [], []
    for r in rows:
        if r[clock] == 1 and e.window is not None and not _inside(r[0], e.window):
            outside.append(r[0])
        elif r[clock] == 1:
            ticks.append((r[0], {v.name: r[index[f"{instance}.{v.name}"]] for v, _x in e.values
                                 if f"{instance}.{v.name}" in index}))
    matching = [(t, got) for t, got in ticks if all(_same(got.get(v.name), x) for v, x in e.values)]
    shown = ", ".join(f"t={t:g}" + (f" ({', '.join(f'{k} = {v!r}' for k, v in got.items())})" if got else "")
                      for t, got in ticks[:5]) + (", ..." if len(ticks) > 5 else "")
    found = f"ticks: {shown}" if ticks else "no tick" + (f" (it ticks at {', '.join(f't={t:g}' for t in outside[:5])})"
                                                       if outside else "")
    if not e.occurs:
        return Outcome(e, not matching, "" if not matching else found, e.span, e.text)
    ok = bool(matching) if e.count is None else len(matching) == e.count
    return Outcome(e, ok, "" if ok else found, e.span, e.text)


def _inside(t: float, window: tuple[float, float]) -> bool:
    return (window[0] <= t or same_time(window[0], t)) and (t <= window[1] or same_time(window[1], t))


def _same(got, expected) -> bool:
    if isinstance(expected, float) and isinstance(got, (int, float)):
        return math.isclose(got, expected, rel_tol=1e-12, abs_tol=1e-12)
    return got == expected
