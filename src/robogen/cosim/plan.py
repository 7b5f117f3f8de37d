"""The plan of a run: what assembling a system produces, read by both loops and never changed.

:func:`make_plan` derives it once from the instances (in dependency order), the resolved
connections and the record list: the grid and the stop time, the DoStep order, the instances in
Event Mode, the value links and their exchange (one Get call per FMU and type, one Set call per
target FMU and type, :mod:`robogen.cosim.wiring`), the clock routes with the clocked values each
carries (one Get call per source type, one Set call per target type), the record columns, the
clocked values the events log shows, and the instances' clock schedules. The master's Python loop
(:mod:`robogen.cosim.master`, the executable reference) runs it as it is; the engine
(:mod:`robogen.cosim.engine`) runs the same plan in C, flattened to the arrays of ``rg_plan``
(``engine.h``, the schema of that flat form and of every enumeration the two share) by
:mod:`robogen.cosim.flat`.
"""

from __future__ import annotations

from dataclasses import dataclass

from robogen.cosim.instances import FmuInstance
from robogen.cosim.system import Link
from robogen.cosim.wiring import CLOCKED, ValueExchange, Wiring, wire
from robogen.fmu.fmi import tolerance
from robogen.fmu.modeldesc import Variable


@dataclass(frozen=True)
class Plan:
    start: float
    step: float
    stop: float
    stop_limit: float  # a point at or after this is the stop time
    resolution: float | None  # the time resolution (robogen.fmu.fmi.time_resolution): caps the time tolerance
    max_iterations: int  # super-dense instants of one event iteration
    instances: tuple[FmuInstance, ...]  # in dependency order
    step_order: tuple[FmuInstance, ...]  # the early returners first
    event_instances: tuple[FmuInstance, ...]  # those in Event Mode
    early: bool  # an instance may return early: every step a general one
    rollback: bool  # several may: those ahead of an early return roll back with FMU state
    wiring: Wiring
    values: ValueExchange
    routes: dict[tuple[str, int], list[tuple]]  # by (source instance, output clock)
    #: by (instance, clock): (source, target, target clock or None, the source variables, batches)
    domain_routes: dict[tuple[str, int], list[tuple]]
    clocked_columns: list[tuple[FmuInstance, list[tuple[int, Variable, frozenset[int]]]]]
    event_values: dict[str, dict[int, list[Variable]]] | None  # None: no events log

    @property
    def by_name(self) -> dict[str, FmuInstance]:
        return {u.name: u for u in self.instances}

    def timed(self) -> list[FmuInstance]:
        """The instances with time-based input clocks (known once their clocks are scheduled)."""
        return [u for u in self.instances if u.periodic or u.aperiodic]


def make_plan(instances: list[FmuInstance], links: list[Link], record: list[tuple[FmuInstance, Variable]], *,
              start: float, step: float, stop: float, max_iterations: int, events_logged: bool,
              resolution: float | None = None) -> Plan:
    """The plan of a run of ``instances`` (in dependency order); sets up their readers and watched clocks."""
    wiring = wire(instances, links, record)
    early = [u for u in instances if u.early]
    return Plan(start, step, stop, stop - tolerance(stop, resolution), resolution, max_iterations, tuple(instances),
                tuple(early + [u for u in instances if not u.early]), tuple(u for u in instances if u.event_mode),
                bool(early), len(early) > 1, wiring, ValueExchange(wiring.value_links), _routes(wiring),
                _domain_routes(wiring),
                _clocked_columns(wiring), _event_values(instances) if events_logged else None)


def _routes(wiring: Wiring) -> dict[tuple[str, int], list[tuple]]:
    """Each clock route as (target, target clock, the source variables it carries, and per type
    (type, target value references, indices into the sources, the values' scales or None))."""
    plans: dict[tuple[str, int], list[tuple]] = {}
    for key, routes in wiring.clock_routes.items():
        for route in routes:
            sources = [value.source for value in route.values]
            plans.setdefault(key, []).append((route.target, route.target_clock, sources, _batches(route.values)))
    return plans


def _batches(values) -> list[tuple]:
    """(type, target value references, indices into the values, the values' scales or None) per
    target type: one Set call each."""
    by_type: dict[str, tuple[list[int], list[int], list]] = {}
    for i, value in enumerate(values):
        vrs, indices, scales = by_type.setdefault(value.target.type, ([], [], []))
        vrs.append(value.target.value_reference)
        indices.append(i)
        scales.append(value.scale)
    return [(fmi_type, vrs, indices, scales) for fmi_type, (vrs, indices, scales) in by_type.items()]


def _domain_routes(wiring: Wiring) -> dict[tuple[str, int], list[tuple]]:
    return {key: [(r.source, r.target, r.target_clock, [v.source for v in r.values], _batches(r.values)) for r in routes]
            for key, routes in wiring.domain_routes.items()}


def _clocked_columns(wiring: Wiring) -> list[tuple[FmuInstance, list[tuple[int, Variable, frozenset[int]]]]]:
    """The recorded clocked variables per instance: (row position, variable, its clocks)."""
    by_instance: dict[str, tuple[FmuInstance, list]] = {}
    for i, column in enumerate(wiring.columns):
        if column.kind == CLOCKED:
            cells = by_instance.setdefault(column.instance.name, (column.instance, []))[1]
            cells.append((2 + i, column.variable, frozenset(column.variable.clocks)))
    return list(by_instance.values())


def _event_values(instances: list[FmuInstance]) -> dict[str, dict[int, list[Variable]]]:
    """Per instance and clock: the clocked inputs and outputs the events log shows with it (scalars:
    the master carries no FMI arrays; a set's or sequence's size is shown)."""
    return {u.name: {c.value_reference: [v for v in u.md.variables if c.value_reference in v.clocks and not v.is_clock
                                         and v.causality in ("input", "output") and not v.dimensions]
                     for c in u.md.variables if c.is_clock}
            for u in instances}
