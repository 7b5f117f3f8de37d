"""The system description: a TOML file naming FMU instances, connections and the experiment.

Loading happens in two passes, each collecting every problem before failing:

1. :func:`load_system` checks the file against the schema (keys, types, ranges) and returns a
   :class:`System` whose every element carries its :class:`Span` in the TOML file.
2. :func:`resolve` checks it against the FMUs' model descriptions: endpoints exist, causality
   and types match, clocks connect only to clocks, a clocked variable's clock is connected to
   the clock of its target, the FMUs offer FMI 3.0 Co-Simulation, ``hasEventMode`` wherever
   clocks are connected. The format is documented in docs/system-toml.md.
"""

from __future__ import annotations

import math
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from robogen.diagnostics import DiagnosticSink, Note, RobogenError, Span, did_you_mean
from robogen.fmu.modeldesc import ModelDescription, Variable
from robogen.cosim.tomlspan import SpanIndex

_ARROW = re.compile(r"^\s*(\S+)\s*->\s*(\S+)\s*$")
TOP_KEYS = ("experiment", "instances", "connections", "record")
EXPERIMENT_KEYS = ("start", "stop", "step", "tolerance", "max_event_iterations", "order")
INSTANCE_KEYS = ("fmu", "start", "clocks")
CLOCK_KEYS = ("interval", "shift")
RECORD_KEYS = ("variables",)


@dataclass(frozen=True)
class Endpoint:
    instance: str
    variable: str
    span: Span

    def __str__(self) -> str:
        return f"{self.instance}.{self.variable}"


@dataclass(frozen=True)
class Connection:
    source: Endpoint
    target: Endpoint
    span: Span


@dataclass
class InstanceSpec:
    name: str
    fmu: Path
    span: Span
    fmu_span: Span
    start: dict[str, tuple[object, Span]] = field(default_factory=dict)
    clocks: dict[str, tuple[dict, Span]] = field(default_factory=dict)


@dataclass
class System:
    path: Path
    text: str
    start: float
    stop: float | None
    step: float | None
    tolerance: float | None
    max_event_iterations: int
    order: list[str]
    instances: dict[str, InstanceSpec]
    connections: list[Connection]
    record: list[tuple[str, Span]] | None
    spans: SpanIndex

    def span(self, *path) -> Span:
        return self.spans.span(*path)


def split_name(text: str) -> tuple[str, str] | None:
    """'inst.var.with.dots' -> ('inst', 'var.with.dots'): only the first dot separates."""
    inst, dot, var = text.partition(".")
    return (inst, var) if dot and inst and var else None


def load_system(path: str | Path) -> System:
    path = Path(path)
    display = str(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise RobogenError.at(f"cannot read system file: {exc.strerror}", Span.whole_file(display)) from None
    except UnicodeDecodeError:
        raise RobogenError.at("system file is not UTF-8 text", Span.whole_file(display)) from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        m = re.search(r"\(at line (\d+), column (\d+)\)", str(exc))
        msg = re.sub(r"\s*\(at line \d+, column \d+\)", "", str(exc))
        span = Span.point(display, int(m.group(1)), int(m.group(2))) if m else Span.whole_file(display)
        raise RobogenError.at(f"invalid TOML: {msg}", span) from None
    idx = SpanIndex(text, display)
    sink = DiagnosticSink()

    def unknown_keys(table: dict, allowed, *where) -> None:
        for key in table:
            if key not in allowed:
                hint = did_you_mean(key, allowed)
                if key == "connections" and where:
                    hint += "; 'connections' belongs at the top level, before the first [table]"
                sink.error(f"unknown key '{key}'{hint}", idx.span(*where, key))

    def number(value, *where, positive=False, nonneg=False) -> float | None:
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            sink.error(f"'{where[-1]}' must be a finite number", idx.span(*where))
            return None
        if positive and value <= 0:
            sink.error(f"'{where[-1]}' must be positive", idx.span(*where))
            return None
        if nonneg and value < 0:
            sink.error(f"'{where[-1]}' must not be negative", idx.span(*where))
            return None
        return float(value)

    unknown_keys(data, TOP_KEYS)
    exp = data.get("experiment", {})
    if not isinstance(exp, dict):
        sink.error("'experiment' must be a table", idx.span("experiment"))
        exp = {}
    unknown_keys(exp, EXPERIMENT_KEYS, "experiment")
    start = number(exp.get("start", 0.0), "experiment", "start") or 0.0
    stop = number(exp["stop"], "experiment", "stop") if "stop" in exp else None
    step = number(exp["step"], "experiment", "step", positive=True) if "step" in exp else None
    tol = number(exp["tolerance"], "experiment", "tolerance", positive=True) if "tolerance" in exp else None
    if stop is not None and stop < start:
        sink.error(f"stop time {stop} is before the start time {start}", idx.span("experiment", "stop"))
    max_iter = exp.get("max_event_iterations", 1000)
    if isinstance(max_iter, bool) or not isinstance(max_iter, int) or max_iter < 1:
        sink.error("'max_event_iterations' must be a positive integer", idx.span("experiment", "max_event_iterations"))
        max_iter = 1000

    instances: dict[str, InstanceSpec] = {}
    raw_instances = data.get("instances", {})
    if not isinstance(raw_instances, dict) or not raw_instances:
        sink.error("the system needs at least one FMU instance: [instances.NAME] with fmu = \"PATH.fmu\"", idx.span("instances"))
        raw_instances = {}
    for name, spec in raw_instances.items():
        where = ("instances", name)
        if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
            sink.error(f"instance name '{name}' must be an identifier (letters, digits, '_'; no dots)", idx.span(*where))
            continue
        if not isinstance(spec, dict):
            sink.error(f"instance '{name}' must be a table", idx.span(*where))
            continue
        unknown_keys(spec, INSTANCE_KEYS, *where)
        fmu = spec.get("fmu")
        if not isinstance(fmu, str) or not fmu:
            sink.error(f"instance '{name}' needs fmu = \"PATH.fmu\"", idx.span(*where, "fmu"))
            continue
        inst = InstanceSpec(name, (path.parent / fmu), idx.span(*where), idx.span(*where, "fmu"))
        starts = spec.get("start", {})
        if not isinstance(starts, dict):
            sink.error("'start' must be a table of variable = value", idx.span(*where, "start"))
            starts = {}
        for var, value in starts.items():
            if isinstance(value, (dict, list)) and not (isinstance(value, list) and all(isinstance(x, (int, float)) for x in value)):
                sink.error(f"start value of '{var}' must be a number, boolean or string", idx.span(*where, "start", var))
                continue
            inst.start[var] = (value, idx.span(*where, "start", var))
        clocks = spec.get("clocks", {})
        if not isinstance(clocks, dict):
            sink.error("'clocks' must be a table of clock = { interval = ..., shift = ... }", idx.span(*where, "clocks"))
            clocks = {}
        for clock, timing in clocks.items():
            cw = (*where, "clocks", clock)
            if not isinstance(timing, dict):
                sink.error(f"clock '{clock}' must be a table {{ interval = ..., shift = ... }}", idx.span(*cw))
                continue
            unknown_keys(timing, CLOCK_KEYS, *cw)
            checked = {}
            if "interval" in timing:
                checked["interval"] = number(timing["interval"], *cw, "interval", positive=True)
            if "shift" in timing:
                checked["shift"] = number(timing["shift"], *cw, "shift", nonneg=True)
            inst.clocks[clock] = (checked, idx.span(*cw))
        instances[name] = inst

    connections: list[Connection] = []
    raw_conn = data.get("connections", [])
    if not isinstance(raw_conn, list):
        sink.error('\'connections\' must be a list of strings "a.y -> b.u"', idx.span("connections"))
        raw_conn = []
    for i, item in enumerate(raw_conn):
        span = idx.span("connections", i)
        m = _ARROW.match(item) if isinstance(item, str) else None
        ends = (split_name(m.group(1)), split_name(m.group(2))) if m else (None, None)
        if not m or None in ends:
            sink.error('a connection is written "instance.variable -> instance.variable"', span)
            continue
        (si, sv), (ti, tv) = ends
        connections.append(Connection(Endpoint(si, sv, span), Endpoint(ti, tv, span), span))

    order = exp.get("order", [])
    if not isinstance(order, list) or not all(isinstance(o, str) for o in order):
        sink.error("'order' must be a list of instance names", idx.span("experiment", "order"))
        order = []
    for i, o in enumerate(order):
        if o not in raw_instances:
            sink.error(f"unknown instance '{o}' in order{did_you_mean(o, raw_instances)}", idx.span("experiment", "order", i))
    if len(set(order)) != len(order):
        sink.error("an instance appears twice in 'order'", idx.span("experiment", "order"))

    record = None
    rec = data.get("record")
    if rec is not None:
        if not isinstance(rec, dict):
            sink.error("'record' must be a table with variables = [...]", idx.span("record"))
        else:
            unknown_keys(rec, RECORD_KEYS, "record")
            names = rec.get("variables", [])
            if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
                sink.error('\'variables\' must be a list of "instance.variable" (or "instance.*")', idx.span("record", "variables"))
            else:
                record = [(n, idx.span("record", "variables", i)) for i, n in enumerate(names)]

    sink.raise_if_errors()
    return System(path, text, start, stop, step, tol, max_iter, order, instances, connections, record, idx)


# ----------------------------------------------------------------------------------------
# Checks against the model descriptions


@dataclass(frozen=True)
class Link:
    """A resolved connection."""

    source: str
    src: Variable
    target: str
    dst: Variable
    span: Span


def resolve(system: System, models: dict[str, ModelDescription]) -> list[Link]:
    """Check every connection, start value and recorded name against the FMUs; collect all problems."""
    sink = DiagnosticSink()
    names = {n: m.by_name() for n, m in models.items()}

    def lookup(end: Endpoint, span: Span) -> Variable | None:
        if end.instance not in models:
            sink.error(f"unknown instance '{end.instance}'{did_you_mean(end.instance, models)}", span)
            return None
        var = names[end.instance].get(end.variable)
        if var is None:
            sink.error(f"FMU instance '{end.instance}' has no variable '{end.variable}'{did_you_mean(end.variable, names[end.instance])}", span,
                       Note(f"variables are declared in {models[end.instance].path}"))
        return var

    for name, md in models.items():
        inst = system.instances[name]
        if md.co_simulation is None:
            sink.error(f"FMU of instance '{name}' has no FMI 3.0 Co-Simulation interface (<CoSimulation> is missing)", inst.fmu_span)
        for var_name, (value, span) in inst.start.items():
            var = names[name].get(var_name)
            if var is None:
                sink.error(f"FMU instance '{name}' has no variable '{var_name}'{did_you_mean(var_name, names[name])}", span)
            elif var.causality not in ("parameter", "input") and var.initial not in ("exact", "approx"):
                sink.error(f"cannot set a start value for '{var_name}' (causality {var.causality}, initial {var.initial or 'calculated'})", span)
            elif var.is_clock:
                sink.error(f"'{var_name}' is a clock; clocks have no start value", span)
            elif value_problem(var, value):
                sink.error(f"start value for '{var_name}': {value_problem(var, value)}", span)
        for clock_name, (timing, span) in inst.clocks.items():
            var = names[name].get(clock_name)
            if var is None or not var.is_clock:
                sink.error(f"FMU instance '{name}' has no clock '{clock_name}'{did_you_mean(clock_name, [v.name for v in md.variables if v.is_clock])}", span)
            elif var.interval_variability not in ("fixed", "tunable"):
                sink.error(f"clock '{clock_name}' is {var.interval_variability}: only fixed and tunable clocks take an interval or shift here", span)

    links: list[Link] = []
    targets: dict[tuple[str, str], Span] = {}
    for c in system.connections:
        src, dst = lookup(c.source, c.span), lookup(c.target, c.span)
        if src is None or dst is None:
            continue
        key = (c.target.instance, c.target.variable)
        if key in targets:
            sink.error(f"'{c.target}' is connected twice", c.span, Note("first connected here", targets[key]))
            continue
        targets[key] = c.span
        if c.source.instance == c.target.instance:
            sink.error("a connection must join two different instances", c.span)
            continue
        if src.causality != "output":
            sink.error(f"'{c.source}' is not an output (causality {src.causality})", c.span)
        if dst.causality != "input":
            sink.error(f"'{c.target}' is not an input (causality {dst.causality})", c.span)
        if src.is_clock != dst.is_clock:
            sink.error(f"a clock connects only to a clock: '{c.source}' is {_kind(src)}, '{c.target}' is {_kind(dst)}", c.span)
            continue
        if _base_type(src) != _base_type(dst):
            sink.error(f"type mismatch: '{c.source}' is {src.type}, '{c.target}' is {dst.type}", c.span)
        if src.is_clocked != dst.is_clocked:
            sink.error(f"'{c.source}' is {'clocked' if src.is_clocked else 'not clocked'} but '{c.target}' is {'clocked' if dst.is_clocked else 'not clocked'}", c.span)
        for inst_name, var in ((c.source.instance, src), (c.target.instance, dst)):
            cs = models[inst_name].co_simulation
            if (var.is_clock or var.is_clocked) and cs is not None and not cs.has_event_mode:
                sink.error(f"instance '{inst_name}' connects clocks but its FMU lacks hasEventMode=\"true\"", c.span)
        links.append(Link(c.source.instance, src, c.target.instance, dst, c.span))

    # a clocked connection needs its clocks connected to each other
    clock_links = {(l.source, l.src.value_reference, l.target, l.dst.value_reference) for l in links if l.src.is_clock}
    for l in links:
        if l.src.is_clocked and l.dst.is_clocked and not l.src.is_clock:
            by_vr_s, by_vr_d = models[l.source].by_vr(), models[l.target].by_vr()
            if not any((l.source, a, l.target, b) in clock_links for a in l.src.clocks for b in l.dst.clocks):
                sc = " or ".join(f"{l.source}.{by_vr_s[a].name}" if a in by_vr_s else str(a) for a in l.src.clocks)
                dc = " or ".join(f"{l.target}.{by_vr_d[b].name}" if b in by_vr_d else str(b) for b in l.dst.clocks)
                sink.error(f"clocked connection '{l.source}.{l.src.name} -> {l.target}.{l.dst.name}' needs its clocks connected: add \"{sc} -> {dc}\"", l.span)

    if system.record is not None:
        for name, span in system.record:
            parts = split_name(name)
            if parts is None:
                sink.error(f"recorded name '{name}' must be \"instance.variable\" or \"instance.*\"", span)
                continue
            inst, var = parts
            if inst not in models:
                sink.error(f"unknown instance '{inst}'{did_you_mean(inst, models)}", span)
            elif var != "*" and var not in names[inst]:
                sink.error(f"FMU instance '{inst}' has no variable '{var}'{did_you_mean(var, names[inst])}", span)
    sink.raise_if_errors()
    return links


def _kind(v: Variable) -> str:
    return "a clock" if v.is_clock else f"a variable of type {v.type}"


def _base_type(v: Variable) -> str:
    return "Int64" if v.type == "Enumeration" else v.type


_INT_RANGES = {"Int8": 8, "Int16": 16, "Int32": 32, "Int64": 64}


def value_problem(var: Variable, value) -> str | None:
    t = var.type
    if t in ("Float32", "Float64"):
        return None if isinstance(value, (int, float)) and not isinstance(value, bool) else f"{t} needs a number"
    if t == "Boolean":
        return None if isinstance(value, bool) else "Boolean needs true or false"
    if t == "String":
        return None if isinstance(value, str) else "String needs a string"
    if t in ("Binary", "Clock"):
        return f"{t} variables cannot be given a start value here"
    if isinstance(value, bool) or not isinstance(value, int):
        return f"{t} needs an integer"
    if t.startswith("UInt"):
        bits = int(t[4:])
        return None if 0 <= value < 2**bits else f"{value} is out of range for {t}"
    bits = _INT_RANGES.get(t, 64)
    return None if -(2 ** (bits - 1)) <= value < 2 ** (bits - 1) else f"{value} is out of range for {t}"
