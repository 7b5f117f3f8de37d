"""Who reads what, and which clock goes where: the wiring of a system, derived once per run.

From the resolved connections and the record list, :func:`wire` derives

- the value links (:class:`ValueLink`): non-clocked outputs forwarded to inputs, per source
  instance, and the :class:`ValueExchange` that forwards them;
- the clock routes (:class:`ClockRoute`): an output clock to the input clocks it drives, with the
  clocked values that ride on it;
- the routes between clock domains (:class:`DomainRoute`), keyed by an instance's clock: a clocked
  output into an input that is not clocked, forwarded at each tick of the output's clock and held
  until the next (sample and hold); an output that is not clocked into a clocked input, sampled
  when the input's clock ticks;
- the recorded columns (:class:`Column`);

and tells every instance which outputs to read after a step (its readers) and which output
clocks to watch.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

from robogen.cosim.instances import FmuInstance, Reader
from robogen.cosim.system import Link, fits
from robogen.cosim.units import apply
from robogen.fmu.modeldesc import Variable

#: Column kinds: a non-clocked value, a clock (1 while active, else 0), a clocked value (empty
#: while its clock is inactive).
VALUE, CLOCK, CLOCKED = "value", "clock", "clocked"


class Column(NamedTuple):
    """One recorded column; a VALUE column's value is ``reader.values[index]`` after a read."""

    kind: str
    instance: FmuInstance
    variable: Variable
    reader: Reader | None
    index: int


def plain(records: list[tuple]) -> list[tuple]:
    """Named-tuple records as plain tuples of their fields, for loops that unpack them at every
    step: CPython specialises the unpacking of exact tuples only (a named tuple costs twice as much)."""
    return [tuple(r) for r in records]


class ValueLink(NamedTuple):
    """A connected non-clocked output (of the instance the link is filed under) and its input."""

    source_vr: int
    target: FmuInstance
    target_variable: Variable
    scale: tuple[float, float] | None = None  # a linear conversion on the way (Link.scale)


class ClockedValue(NamedTuple):
    source: Variable
    target: Variable
    scale: tuple[float, float] | None = None  # a linear conversion on the way (Link.scale)


@dataclass
class ClockRoute:
    """Forward one output clock: set the target clock, then copy the clocked values."""

    target: FmuInstance
    target_clock: int
    values: list[ClockedValue] = field(default_factory=list)


@dataclass
class DomainRoute:
    """A value crossing clock domains, forwarded while the clock it is keyed by is active: from
    ``source`` to ``target``'s input; ``target_clock`` is the clocked input's clock (sampling, the
    clock it is keyed by) or None (sample and hold into an input that is not clocked)."""

    source: FmuInstance
    target: FmuInstance
    target_clock: int | None
    values: list[ClockedValue] = field(default_factory=list)


@dataclass
class Wiring:
    value_links: dict[str, list[ValueLink]]  # by source instance
    clock_routes: dict[tuple[str, int], list[ClockRoute]]  # by (source instance, output clock)
    domain_routes: dict[tuple[str, int], list[DomainRoute]]  # by (instance, the clock whose ticks forward them)
    columns: list[Column]
    record_reads: list[FmuInstance]  # recorded instances that no value link reads: read to record


def wire(instances: list[FmuInstance], links: list[Link], record: list[tuple[FmuInstance, Variable]]) -> Wiring:
    """The wiring of ``instances`` (in dependency order); sets up their readers and watched clocks."""
    observe: dict[str, list[Variable]] = {u.name: [] for u in instances}
    watch: dict[str, list[int]] = {u.name: [] for u in instances}
    value_links, clock_routes = _routes(instances, links, observe, watch)
    domain_routes = _domain_routes(instances, links, watch)
    kinds = [_column_kind(u, var, observe, watch) for u, var in record]
    for u in instances:
        u.observe(observe[u.name])
        u.watch_clocks(watch[u.name])
    columns = [Column(kind, u, var, reader, index + k)
               for kind, (u, var) in zip(kinds, record)
               for reader, index in [u.reader_of.get(var.value_reference, (None, 0))]
               for k in range(u.md.element_count(var) if kind == VALUE else 1)]
    recorded = {c.instance.name for c in columns if c.kind == VALUE}
    record_reads = [u for u in instances if u.name in recorded and not value_links[u.name]]
    return Wiring(value_links, clock_routes, domain_routes, columns, record_reads)


def _routes(instances, links, observe, watch):
    by_name = {u.name: u for u in instances}
    value_links: dict[str, list[ValueLink]] = {u.name: [] for u in instances}
    clock_routes: dict[tuple[str, int], list[ClockRoute]] = {}
    for link in links:
        source, target = by_name[link.source], by_name[link.target]
        if link.src.is_clock:
            watch[source.name].append(link.src.value_reference)
            clock_routes.setdefault((source.name, link.src.value_reference), []).append(
                ClockRoute(target, link.dst.value_reference))
        elif not link.src.is_clocked:
            observe[source.name].append(link.src)
            value_links[source.name].append(ValueLink(link.src.value_reference, target, link.dst, link.scale))
    for link in links:  # clocked values ride on their clock's route
        if link.src.is_clocked and not link.src.is_clock:
            for route in (r for c in link.src.clocks for r in clock_routes.get((link.source, c), [])):
                if route.target.name == link.target and route.target_clock in link.dst.clocks:
                    route.values.append(ClockedValue(link.src, link.dst, link.scale))
    return value_links, clock_routes


def _domain_routes(instances, links, watch) -> dict[tuple[str, int], list[DomainRoute]]:
    """The connections between a clocked and a non-clocked variable, keyed by the clock whose
    ticks forward them: the source's clocks (sample and hold; an output clock is watched) or the
    target's (sampling)."""
    by_name = {u.name: u for u in instances}
    routes: dict[tuple[str, int], list[DomainRoute]] = {}
    crossing = [k for k in links if not k.src.is_clock and k.src.is_clocked != k.dst.is_clocked]
    for link in crossing:  # sampling first: what an instance puts out at a tick follows what it sampled
        if not link.src.is_clocked:
            for c in link.dst.clocks:
                routes.setdefault((link.target, c), []).append(
                    DomainRoute(by_name[link.source], by_name[link.target], c, [ClockedValue(link.src, link.dst, link.scale)]))
    for link in crossing:  # sample and hold
        if link.src.is_clocked:
            source = by_name[link.source]
            for c in link.src.clocks:
                if c in source.by_vr and source.by_vr[c].causality == "output":
                    watch[source.name].append(c)
                routes.setdefault((source.name, c), []).append(
                    DomainRoute(source, by_name[link.target], None, [ClockedValue(link.src, link.dst, link.scale)]))
    return routes


def _column_kind(u: FmuInstance, var: Variable, observe, watch) -> str:
    """The kind of a recorded variable; notes what recording it needs read or watched."""
    if var.is_clock:
        if var.causality == "output":
            watch[u.name].append(var.value_reference)
        return CLOCK
    if var.is_clocked:
        watch[u.name] += [c for c in var.clocks if c in u.by_vr and u.by_vr[c].causality == "output"]
        return CLOCKED
    observe[u.name].append(var)
    return VALUE


class ValueExchange:
    """Forwards connected non-clocked values: read a source's outputs, set each connected input
    whose value changed since it was last set (an FMU sees a Set only when its input changes)."""

    def __init__(self, value_links: dict[str, list[ValueLink]]):
        self.links = value_links
        self.connected = any(value_links.values())
        self._links = {name: plain(links) for name, links in value_links.items()}
        #: the value each connected input was last set to, by (target instance, value reference); the
        #: engine (robogen.cosim.engine) takes it over for its run and hands it back
        self.last_set: dict[tuple[str, int], object] = {}

    def forward(self, u: FmuInstance) -> set[str]:
        """Read u's observed outputs and set the changed connected inputs; the names of the targets set."""
        links = self._links[u.name]
        if not links:
            return set()  # nothing to forward: recording reads what it records
        u.read_outputs()
        woken = set()
        for vr, target, variable, scale in links:
            value = apply(scale, u.value(vr))  # as the engine converts it
            key = (target.name, variable.value_reference)
            if self.last_set.get(key, UNSET) != value:
                if not fits(variable.type, value):
                    raise Narrowing(key, value)
                self.last_set[key] = value
                target.set_values(variable.type, [variable.value_reference], [value])
                woken.add(target.name)
        return woken

    def exchange(self, instances: list[FmuInstance]) -> bool:
        """Forward every instance's values, in dependency order; True if an input changed."""
        changed = False
        for u in instances:
            if self.forward(u):
                changed = True
        return changed


UNSET = object()  # an input not set yet


class Narrowing(Exception):
    """A connected value that does not fit its input's type: the input (target instance, value
    reference) and the value."""

    def __init__(self, key: tuple[str, int], value):
        super().__init__(key, value)
        self.key, self.value = key, value


def find_cycle(edges: dict[str, set[str]]) -> list[str]:
    """A cycle of the directed graph ``edges`` as the path around it, ``[a, b, ..., a]`` (a
    self-loop is ``[a, a]``); empty if it has none. Nodes are tried in sorted order, so the
    answer is the same for the same graph."""
    state: dict[str, str] = {}
    path: list[str] = []

    def visit(v: str) -> list[str]:
        state[v] = "open"
        path.append(v)
        for w in sorted(edges.get(v, ())):
            if state.get(w) == "open":
                return path[path.index(w):] + [w]
            if w not in state and (found := visit(w)):
                return found
        path.pop()
        state[v] = "done"
        return []

    for v in sorted(edges):
        if v not in state and (found := visit(v)):
            return found
    return []

