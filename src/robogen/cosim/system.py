"""The system description: a TOML file naming FMU instances, connections and the experiment.

Loading happens in two passes, each collecting every problem before failing:

1. :func:`load_system` checks the file against the schema (keys, types, ranges) and returns a
   :class:`System` whose every element carries its :class:`Span` in the TOML file.
2. :func:`resolve` checks it against the FMUs' model descriptions: value references are unique,
   endpoints exist, causality and types match, clocks connect only to clocks, a clocked
   variable's clock is connected to the clock of its target, the FMUs offer FMI 3.0
   Co-Simulation, ``hasEventMode`` wherever clocks are connected, every recorded name or pattern
   names something. The format is documented in docs/system-toml.md.

Names in ``[record]`` and in ``robogen plot --vars`` are matched by one rule, :func:`matching`.
"""

from __future__ import annotations

import fnmatch
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

from robogen.diagnostics import DiagnosticSink, Note, Span, did_you_mean
from robogen.fmu.modeldesc import ModelDescription, Variable
from robogen.cosim.tomlspan import PathSpans, SpanIndex, read_toml

_ARROW = re.compile(r"^\s*(\S+)\s*->\s*(\S+)\s*$")
TOP_KEYS = ("experiment", "instances", "connections", "record")
EXPERIMENT_KEYS = ("start", "stop", "step", "tolerance", "max_event_iterations", "order")
INSTANCE_KEYS = ("fmu", "start", "clocks", "isolate", "scenario", "scenario_parameters", "interface", "solver",
                 "solver_step")
#: The interfaces an instance may use its FMU through ([instances.X] interface) ...
INTERFACES = ("co-simulation", "model-exchange", "scheduled-execution")
#: ... and the integrators of a Model Exchange FMU ([instances.X] solver).
SOLVERS = ("cvode", "euler")
CLOCK_KEYS = ("interval", "shift")
RECORD_KEYS = ("variables", "every")
#: [experiment] max_event_iterations unless given: super-dense instants of one event iteration
MAX_EVENT_ITERATIONS = 1000
#: A connection written as a table: { from = "a.y", to = "b.u", factor = 1000.0, offset = 0.0 }
CONNECTION_KEYS = ("from", "to", "factor", "offset")


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
    #: a linear conversion of a real value on its way, target = factor * source + offset (a
    #: connection table's factor and offset, an SSP file's units and LinearTransformation); None: none
    scale: tuple[float, float] | None = None


@dataclass
class InstanceSpec:
    name: str
    fmu: Path
    span: Span
    fmu_span: Span
    start: dict[str, tuple[object, Span]] = field(default_factory=dict)
    clocks: dict[str, tuple[dict, Span]] = field(default_factory=dict)
    isolate: bool = False  # run the instance in a worker process of its own (robogen.cosim.proxy)
    scenario: Path | None = None  # a scenario file that drives it (robogen.cosim.scenario, .player)
    scenario_span: Span | None = None
    player_of: str | None = None  # this instance plays the scenario of that one (no FMU file)
    interface: str | None = None  # None: co-simulation where the FMU offers it, else the first it offers
    solver: str = "cvode"  # Model Exchange: the integrator
    solver_step: float | None = None  # Euler's step (None: the communication step)


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
    spans: PathSpans  # where its parts are in its file (a SpanIndex of a TOML file)
    record_every: float | None = None  # [record] every: plain rows at most this often (event rows all kept)

    def span(self, *path) -> Span:
        return self.spans.span(*path)


def split_name(text: str) -> tuple[str, str] | None:
    """'inst.var.with.dots' -> ('inst', 'var.with.dots'): only the first dot separates."""
    inst, dot, var = text.partition(".")
    return (inst, var) if dot and inst and var else None


def matching(pattern: str, names: list[str]) -> list[str]:
    """The names that a ``[record]`` entry or a ``robogen plot --vars`` pattern selects: the name
    itself if it is one (FMI names may contain ``[``), else those the pattern matches as a
    shell-style glob (``*``, ``?``, ``[seq]``; case-sensitive), in the order of ``names``."""
    if pattern in names:
        return [pattern]
    return [n for n in names if fnmatch.fnmatchcase(n, pattern)]


def load_system(path: str | Path) -> System:
    path = Path(path)
    text, data = read_toml(path, "system file")
    check = _SchemaCheck(SpanIndex(text, str(path)))
    check.unknown_keys(data, TOP_KEYS)
    exp = check.table(data, "experiment", "'experiment' must be a table")
    start, stop, step, tol, max_iter = _experiment(exp, check)
    raw_instances = data.get("instances", {})
    if not isinstance(raw_instances, dict) or not raw_instances:
        check.error("the system needs at least one FMU instance: [instances.NAME] with fmu = \"PATH.fmu\"", "instances")
        raw_instances = {}
    instances = {}
    for name, spec in raw_instances.items():
        inst = _instance(name, spec, path, check)
        if inst is not None:
            if inst.scenario is not None:
                _player(inst, raw_instances, instances, check)
            instances[name] = inst
    connections = _connections(data, check)
    order = _order(exp, raw_instances, check)
    record, every = _record(data, check)
    check.sink.raise_if_errors()
    return System(path, text, start, stop, step, tol, max_iter, order, instances, connections, record, check.idx, every)


class _SchemaCheck:
    """Collects the schema errors of one system file, each located at its key."""

    def __init__(self, idx: SpanIndex):
        self.idx, self.sink = idx, DiagnosticSink()

    def error(self, message: str, *where) -> None:
        self.sink.error(message, self.idx.span(*where))

    def unknown_keys(self, table: dict, allowed, *where) -> None:
        for key in table:
            if key not in allowed:
                hint = did_you_mean(key, allowed)
                if key == "connections" and where:
                    hint += "; 'connections' belongs at the top level, before the first [table]"
                self.error(f"unknown key '{key}'{hint}", *where, key)

    def table(self, data: dict, key: str, message: str) -> dict:
        """data[key] if it is a table (an absent key is an empty one)."""
        value = data.get(key, {})
        if not isinstance(value, dict):
            self.error(message, key)
            return {}
        return value

    def number(self, value, *where, positive=False, nonneg=False) -> float | None:
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            self.error(f"'{where[-1]}' must be a finite number", *where)
            return None
        if positive and value <= 0:
            self.error(f"'{where[-1]}' must be positive", *where)
            return None
        if nonneg and value < 0:
            self.error(f"'{where[-1]}' must not be negative", *where)
            return None
        return float(value)


def _experiment(exp: dict, check: _SchemaCheck) -> tuple[float, float | None, float | None, float | None, int]:
    """[experiment]: start, stop, step, tolerance, max_event_iterations (``order`` is read last)."""
    check.unknown_keys(exp, EXPERIMENT_KEYS, "experiment")
    start = check.number(exp.get("start", 0.0), "experiment", "start") or 0.0
    stop = check.number(exp["stop"], "experiment", "stop") if "stop" in exp else None
    step = check.number(exp["step"], "experiment", "step", positive=True) if "step" in exp else None
    tol = check.number(exp["tolerance"], "experiment", "tolerance", positive=True) if "tolerance" in exp else None
    if stop is not None and stop < start:
        check.error(f"stop time {stop} is before the start time {start}", "experiment", "stop")
    max_iter = exp.get("max_event_iterations", MAX_EVENT_ITERATIONS)
    if isinstance(max_iter, bool) or not isinstance(max_iter, int) or max_iter < 1:
        check.error("'max_event_iterations' must be a positive integer", "experiment", "max_event_iterations")
        max_iter = MAX_EVENT_ITERATIONS
    return start, stop, step, tol, max_iter


def _instance(name: str, spec, path: Path, check: _SchemaCheck) -> InstanceSpec | None:
    """[instances.NAME]: the FMU (relative to the system file), start values, clock timing."""
    where = ("instances", name)
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
        check.error(f"instance name '{name}' must be an identifier (letters, digits, '_'; no dots)", *where)
        return None
    if not isinstance(spec, dict):
        check.error(f"instance '{name}' must be a table", *where)
        return None
    check.unknown_keys(spec, INSTANCE_KEYS, *where)
    fmu = spec.get("fmu")
    if not isinstance(fmu, str) or not fmu:
        check.error(f"instance '{name}' needs fmu = \"PATH.fmu\"", *where, "fmu")
        return None
    inst = InstanceSpec(name, (path.parent / fmu), check.idx.span(*where), check.idx.span(*where, "fmu"))
    isolate = spec.get("isolate", False)
    if not isinstance(isolate, bool):
        check.error("'isolate' must be true or false", *where, "isolate")
    inst.isolate = isolate is True
    scenario = spec.get("scenario")
    if scenario is None and "scenario_parameters" in spec:
        check.error("'scenario_parameters' sets parameters of a scenario: give scenario = \"S.toml\" too", *where,
                    "scenario_parameters")
    if scenario is not None:
        if not isinstance(scenario, str) or not scenario:
            check.error("'scenario' must be the path of a scenario file (TOML)", *where, "scenario")
        else:
            inst.scenario, inst.scenario_span = path.parent / scenario, check.idx.span(*where, "scenario")
    _interface(spec, inst, where, check)
    starts = spec.get("start", {})
    if not isinstance(starts, dict):
        check.error("'start' must be a table of variable = value", *where, "start")
        starts = {}
    for var, value in starts.items():
        if isinstance(value, (dict, list)) and not (isinstance(value, list) and all(isinstance(x, (int, float)) for x in value)):
            check.error(f"start value of '{var}' must be a number, boolean or string", *where, "start", var)
            continue
        inst.start[var] = (value, check.idx.span(*where, "start", var))
    clocks = spec.get("clocks", {})
    if not isinstance(clocks, dict):
        check.error("'clocks' must be a table of clock = { interval = ..., shift = ... }", *where, "clocks")
        clocks = {}
    for clock, timing in clocks.items():
        checked = _clock_timing(timing, (*where, "clocks", clock), check)
        if checked is not None:
            inst.clocks[clock] = (checked, check.idx.span(*where, "clocks", clock))
    return inst


def _player(inst: InstanceSpec, raw_instances: dict, instances: dict[str, InstanceSpec], check: _SchemaCheck) -> None:
    """The instance that plays ``inst``'s scenario, ``<name>_scenario``, declared just before it
    (robogen.cosim.player); its "FMU" is the scenario file."""
    name = f"{inst.name}_scenario"
    if name in raw_instances:
        check.error(f"instance '{name}' plays the scenario of '{inst.name}': choose another name for it",
                    "instances", name)
        return
    player = InstanceSpec(name, inst.scenario, inst.scenario_span, inst.scenario_span, player_of=inst.name)
    values = raw_instances[inst.name].get("scenario_parameters", {})
    where = ("instances", inst.name, "scenario_parameters")
    if not isinstance(values, dict):
        check.error("'scenario_parameters' must be a table of parameter = value", *where)
        values = {}
    for key, value in values.items():
        if isinstance(value, (dict, list)):
            check.error(f"scenario parameter '{key}' must be a number, boolean or string", *where, key)
        else:
            player.start[key] = (value, check.idx.span(*where, key))
    instances[name] = player
def _interface(spec: dict, inst: InstanceSpec, where: tuple, check: _SchemaCheck) -> None:
    """[instances.NAME] interface, solver and solver_step."""
    for key, allowed in (("interface", INTERFACES), ("solver", SOLVERS)):
        if key not in spec:
            continue
        value = spec[key]
        if value not in allowed:
            check.error(f"'{key}' must be one of {', '.join(repr(a) for a in allowed)}, not {value!r}"
                        f"{did_you_mean(str(value), allowed)}", *where, key)
        else:
            setattr(inst, key, value)
    if "solver_step" in spec:
        inst.solver_step = check.number(spec["solver_step"], *where, "solver_step", positive=True)


def _clock_timing(timing, where: tuple, check: _SchemaCheck) -> dict | None:
    if not isinstance(timing, dict):
        check.error(f"clock '{where[-1]}' must be a table {{ interval = ..., shift = ... }}", *where)
        return None
    check.unknown_keys(timing, CLOCK_KEYS, *where)
    checked = {}
    if "interval" in timing:
        checked["interval"] = check.number(timing["interval"], *where, "interval", positive=True)
    if "shift" in timing:
        checked["shift"] = check.number(timing["shift"], *where, "shift", nonneg=True)
    return checked


def _connections(data: dict, check: _SchemaCheck) -> list[Connection]:
    connections: list[Connection] = []
    raw_conn = data.get("connections", [])
    if not isinstance(raw_conn, list):
        check.error('\'connections\' must be a list of strings "a.y -> b.u"', "connections")
        raw_conn = []
    for i, item in enumerate(raw_conn):
        span = check.idx.span("connections", i)
        if isinstance(item, dict):
            connections += _connection_table(item, i, check)
            continue
        m = _ARROW.match(item) if isinstance(item, str) else None
        ends = (split_name(m.group(1)), split_name(m.group(2))) if m else (None, None)
        if not m or None in ends:
            check.sink.error('a connection is written "instance.variable -> instance.variable"', span)
            continue
        (si, sv), (ti, tv) = ends
        connections.append(Connection(Endpoint(si, sv, span), Endpoint(ti, tv, span), span))
    return connections


def _connection_table(item: dict, i: int, check: _SchemaCheck) -> list[Connection]:
    """{ from = "a.y", to = "b.u", factor = F, offset = O }: a connection converting a real value
    on its way (target = F * source + O; factor 1 and offset 0 unless given)."""
    where = ("connections", i)
    check.unknown_keys(item, CONNECTION_KEYS, *where)
    ends = [split_name(item[k]) if isinstance(item.get(k), str) else None for k in ("from", "to")]
    for key, end in zip(("from", "to"), ends):
        if end is None:
            check.error(f"'{key}' must be \"instance.variable\"", *where, key)
    factor = check.number(item.get("factor", 1.0), *where, "factor")
    offset = check.number(item.get("offset", 0.0), *where, "offset")
    if None in ends or factor is None or offset is None:
        return []
    span = check.idx.span(*where)
    (si, sv), (ti, tv) = ends
    scale = None if (factor, offset) == (1.0, 0.0) else (factor, offset)
    return [Connection(Endpoint(si, sv, span), Endpoint(ti, tv, span), span, scale)]


def _order(exp: dict, raw_instances: dict, check: _SchemaCheck) -> list[str]:
    order = exp.get("order", [])
    if not isinstance(order, list) or not all(isinstance(o, str) for o in order):
        check.error("'order' must be a list of instance names", "experiment", "order")
        order = []
    for i, o in enumerate(order):
        if o not in raw_instances:
            check.error(f"unknown instance '{o}' in order{did_you_mean(o, raw_instances)}", "experiment", "order", i)
    if len(set(order)) != len(order):
        check.error("an instance appears twice in 'order'", "experiment", "order")
    return order


def _record(data: dict, check: _SchemaCheck) -> tuple[list[tuple[str, Span]] | None, float | None]:
    """The [record] table: the names to record (None: the default, every output and input clock)
    and ``every``, the decimation interval (None: every row)."""
    rec = data.get("record")
    if rec is None:
        return None, None
    if not isinstance(rec, dict):
        check.error("'record' must be a table with variables = [...] and/or every = SECONDS", "record")
        return None, None
    check.unknown_keys(rec, RECORD_KEYS, "record")
    every = check.number(rec["every"], "record", "every", positive=True) if "every" in rec else None
    if "variables" not in rec:
        return None, every
    names = rec["variables"]
    if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
        check.error('\'variables\' must be a list of "instance.variable" (or "instance.*")', "record", "variables")
        return None, every
    return [(n, check.idx.span("record", "variables", i)) for i, n in enumerate(names)], every


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
    scale: tuple[float, float] | None = None  # target = factor * source + offset (Connection.scale)


def resolve(system: System, models: dict[str, ModelDescription]) -> list[Link]:
    """Check every connection, start value and recorded name against the FMUs; collect all problems."""
    check = _ModelCheck(system, models)
    for name in models:
        if system.instances[name].player_of is None:
            check.instance(name)
    links = [link for c in system.connections if (link := check.connection(c)) is not None]
    for link in links:
        check.clocks_connected(link, links)
    for name, span in system.record or ():
        check.recorded(name, span)
    check.sink.raise_if_errors()
    return links


class _ModelCheck:
    """Checks a system against its FMUs' model descriptions, collecting every problem."""

    def __init__(self, system: System, models: dict[str, ModelDescription]):
        self.system, self.models, self.sink = system, models, DiagnosticSink()
        self.names = {n: m.by_name() for n, m in models.items()}
        self.targets: dict[tuple[str, str], Span] = {}  # connected inputs: where first connected
        self.recordable = [f"{n}.{v.name}" for n, v in recordable(models)]

    def lookup(self, end: Endpoint, span: Span) -> Variable | None:
        if end.instance not in self.models:
            self.sink.error(f"unknown instance '{end.instance}'{did_you_mean(end.instance, self.models)}", span)
            return None
        var = self.names[end.instance].get(end.variable)
        if var is None:
            self.sink.error(f"FMU instance '{end.instance}' has no variable '{end.variable}'{did_you_mean(end.variable, self.names[end.instance])}",
                            span, Note(f"variables are declared in {self.models[end.instance].path}"))
        return var

    def instance(self, name: str) -> None:
        """The FMU offers Co-Simulation; start values and clock timings name what they can set."""
        md, inst, names, sink = self.models[name], self.system.instances[name], self.names[name], self.sink
        if md.co_simulation is None:
            sink.error(f"FMU of instance '{name}' has no FMI 3.0 Co-Simulation interface (<CoSimulation> is missing)", inst.fmu_span)
        first: dict[int, Variable] = {}
        for var in md.variables:
            other = first.setdefault(var.value_reference, var)
            if other is not var:
                sink.error(f"the FMU of instance '{name}' gives value reference {var.value_reference} to both "
                           f"'{other.name}' and '{var.name}' (value references must be unique)", md.span(var.line),
                           Note(f"the FMU is used by instance '{name}'", inst.fmu_span))
        for var_name, (value, span) in inst.start.items():
            var = names.get(var_name)
            if var is None:
                sink.error(f"FMU instance '{name}' has no variable '{var_name}'{did_you_mean(var_name, names)}", span)
            elif var.causality not in ("parameter", "input") and var.initial not in ("exact", "approx"):
                sink.error(f"cannot set a start value for '{var_name}' (causality {var.causality}, initial {var.initial or 'calculated'})", span)
            elif var.is_clock:
                sink.error(f"'{var_name}' is a clock; clocks have no start value", span)
            elif value_problem(var, value):
                sink.error(f"start value for '{var_name}': {value_problem(var, value)}", span)
        for clock_name, (_timing, span) in inst.clocks.items():
            var = names.get(clock_name)
            if var is None or not var.is_clock:
                sink.error(f"FMU instance '{name}' has no clock '{clock_name}'{did_you_mean(clock_name, [v.name for v in md.variables if v.is_clock])}", span)
            elif var.interval_variability not in ("fixed", "tunable"):
                sink.error(f"clock '{clock_name}' is {var.interval_variability}: only fixed and tunable clocks take an interval or shift here", span)

    def connection(self, c: Connection) -> Link | None:
        """The connection as a link if its ends exist and the input is connected once."""
        src, dst = self.lookup(c.source, c.span), self.lookup(c.target, c.span)
        if src is None or dst is None:
            return None
        key = (c.target.instance, c.target.variable)
        if key in self.targets:
            self.sink.error(f"'{c.target}' is connected twice", c.span, Note("first connected here", self.targets[key]))
            return None
        self.targets[key] = c.span
        if not self.compatible(c, src, dst):
            return None
        if c.scale is not None and not (src.type in ("Float32", "Float64") and dst.type in ("Float32", "Float64")):
            self.sink.error(f"'{c.source} -> {c.target}' converts its value (factor and offset), which only a real "
                            f"(Float32, Float64) can be: '{c.source}' is {_kind(src)}", c.span)
        return Link(c.source.instance, src, c.target.instance, dst, c.span, c.scale)

    def compatible(self, c: Connection, src: Variable, dst: Variable) -> bool:
        """Causalities, types, clocks and Event Mode fit (False only where the link makes no sense)."""
        sink = self.sink
        if src.causality != "output":
            sink.error(f"'{c.source}' is not an output (causality {src.causality})", c.span)
        if dst.causality != "input":
            sink.error(f"'{c.target}' is not an input (causality {dst.causality})", c.span)
        if src.dimensions or dst.dimensions:
            sink.error(f"'{c.source if src.dimensions else c.target}' is an array: the master records arrays, element "
                       "by element, but does not connect them", c.span)
            return False
        if src.is_clock != dst.is_clock:
            sink.error(f"a clock connects only to a clock: '{c.source}' is {_kind(src)}, '{c.target}' is {_kind(dst)}", c.span)
            return False
        if _base_type(src) != _base_type(dst) and not convertible(src.type, dst.type):
            sink.error(f"type mismatch: '{c.source}' is {src.type}, '{c.target}' is {dst.type}", c.span)
        for inst_name, var in ((c.source.instance, src), (c.target.instance, dst)):
            cs = self.models[inst_name].co_simulation
            if (var.is_clock or var.is_clocked) and cs is not None and not cs.has_event_mode:
                sink.error(f"instance '{inst_name}' connects clocks but its FMU lacks hasEventMode=\"true\"", c.span)
        return True

    def clocks_connected(self, link: Link, links: list[Link]) -> None:
        """A clocked connection needs a clock of its source connected to a clock of its target."""
        if not (link.src.is_clocked and link.dst.is_clocked and not link.src.is_clock):
            return
        clock_links = {(k.source, k.src.value_reference, k.target, k.dst.value_reference) for k in links if k.src.is_clock}
        if any((link.source, a, link.target, b) in clock_links for a in link.src.clocks for b in link.dst.clocks):
            return
        by_vr_s, by_vr_d = self.models[link.source].by_vr(), self.models[link.target].by_vr()
        sc = " or ".join(f"{link.source}.{by_vr_s[a].name}" if a in by_vr_s else str(a) for a in link.src.clocks)
        dc = " or ".join(f"{link.target}.{by_vr_d[b].name}" if b in by_vr_d else str(b) for b in link.dst.clocks)
        self.sink.error(f"'{link.source}.{link.src.name}' is clocked by {sc} and '{link.target}.{link.dst.name}' by {dc}: "
                        "a clocked value crosses only to a clock it drives", link.span,
                        Note(f"connect the clocks (\"{sc.split(' or ')[0]} -> {dc.split(' or ')[0]}\"), or connect the "
                             "value to an input that is not clocked (sample and hold)"))

    def recorded(self, name: str, span: Span) -> None:
        """A [record] entry: an exact variable name (any causality), or a pattern that matches
        at least one output or input clock."""
        parts = split_name(name)
        if parts is not None and parts[0] in self.models and parts[1] in self.names[parts[0]]:
            return
        if parts is not None and not is_pattern(parts[0]) and parts[0] not in self.models:
            self.sink.error(f"unknown instance '{parts[0]}'{did_you_mean(parts[0], self.models)}", span)
        elif is_pattern(name):
            if not matching(name, self.recordable):
                self.sink.error(f"no output or input clock matches '{name}'", span)
        elif parts is None:
            self.sink.error(f"recorded name '{name}' must be \"instance.variable\" or a pattern such as \"instance.*\"", span)
        else:
            inst, var = parts
            self.sink.error(f"FMU instance '{inst}' has no variable '{var}'{did_you_mean(var, self.names[inst])}", span)


def is_pattern(name: str) -> bool:
    return any(c in name for c in "*?[")


def recordable(models: dict[str, ModelDescription]) -> list[tuple[str, Variable]]:
    """What is recorded by default, and what patterns select from: every output and input clock
    of every instance, in declaration order."""
    return [(n, v) for n, md in models.items() for v in md.variables
            if v.causality == "output" or (v.is_clock and v.causality == "input")]


def record_list(system: System, models: dict[str, ModelDescription]) -> list[tuple[str, Variable]]:
    """(instance, variable) to record, each once, in the order of [record] (checked by
    :func:`resolve`); without [record], :func:`recordable`."""
    default = recordable(models)
    if system.record is None:
        return default
    names = [f"{n}.{v.name}" for n, v in default]
    by_name = dict(zip(names, default))
    chosen: dict[str, tuple[str, Variable]] = {}
    for entry, _span in system.record:
        parts = split_name(entry)
        if parts is not None and parts[0] in models and parts[1] in models[parts[0]].by_name():
            chosen.setdefault(entry, (parts[0], models[parts[0]].by_name()[parts[1]]))
        else:
            for name in matching(entry, names):
                chosen.setdefault(name, by_name[name])
    return list(chosen.values())


def _kind(v: Variable) -> str:
    return "a clock" if v.is_clock else f"a variable of type {v.type}"


#: The types a connected value is converted between (FMI 2.0's Integer is Int32, its Enumeration
#: Int64): the master converts a value between two integer types or two real types, and stops the
#: run with an error naming the connection where a value does not fit its input's type.
INTEGER_TYPES = ("Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32", "Int64", "UInt64", "Enumeration")
REAL_TYPES = ("Float32", "Float64")


def convertible(source: str, target: str) -> bool:
    return (source in INTEGER_TYPES and target in INTEGER_TYPES) or (source in REAL_TYPES and target in REAL_TYPES)


def fits(fmi_type: str, value) -> bool:
    """Whether a value converted to ``fmi_type`` keeps its value (a finite real within Float32's range)."""
    if fmi_type == "Float32":
        return not math.isfinite(value) or abs(value) <= 3.4028234663852886e38
    if fmi_type not in INTEGER_TYPES or isinstance(value, bool):
        return True
    if fmi_type.startswith("UInt"):
        return 0 <= value < 2 ** int(fmi_type[4:])
    bits = _INT_RANGES.get(fmi_type, 64)
    return -(2 ** (bits - 1)) <= value < 2 ** (bits - 1)


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
