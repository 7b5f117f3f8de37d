"""A plan flattened for the engine: :func:`flatten` fills ``rg_plan`` (``engine.h``) from a
:class:`~robogen.cosim.plan.Plan`.

Everything becomes indices and arrays: the instances (their C functions: the FMU's own through
:meth:`~robogen.cosim.fmi3.Binding.raw`, or an :class:`~robogen.cosim.adapters.Adapter`'s
callbacks), the exchange after a step (each connected instance's reads, then its Set groups, in
dependency order; then the reads of the recorded instances that forward nothing), the clocks and
their schedules, the clocked variables read (cells), the clock routes and their Set batches, the
record columns and the events log's text. The arrays live as long as the :class:`Flat` that holds them.
"""

from __future__ import annotations

import json
import math
from itertools import accumulate
from typing import NamedTuple

from robogen.cosim.adapters import Adapter
from robogen.cosim.schema import ColumnKind, Store, kind
from robogen.cosim.fmi3 import ACCESSOR
from robogen.cosim.fmi3 import ffi as fmi_ffi
from robogen.cosim.instances import FmuInstance, Reader
from robogen.cosim.plan import Plan
from robogen.cosim.wiring import CLOCK, CLOCKED, VALUE
from robogen.fmu.fmi import TIME_TOLERANCE, TIME_ULPS

_COLUMN_KINDS = {VALUE: ColumnKind.VALUE, CLOCK: ColumnKind.CLOCK, CLOCKED: ColumnKind.CLOCKED}


def _starts(counts: list[int]) -> list[int]:
    """Where each of consecutive runs of these lengths starts, and where the last ends."""
    return [0, *accumulate(counts)]


def _clocks(u: FmuInstance) -> list[int]:
    return sorted(v.value_reference for v in u.md.variables if v.is_clock)


class _Group(NamedTuple):
    """The links of one source FMU to one target FMU's inputs of one type: one Set call."""

    target: FmuInstance
    fmi_type: str
    links: list  # (read, index in the read, target value reference, its scale or None) of each link


class _Exchange(NamedTuple):
    """What the engine does after a step, as indices: reads, Set groups, the order of both."""

    reads: list[Reader]
    ops: list[int]  # r >= 0: reads[r]; -1 - g: groups[g]
    groups: list[_Group]
    owners: list[int]  # per operation of a connected instance: that instance


def _exchange(plan: Plan) -> _Exchange:
    """In dependency order, each connected instance's reads then its Set groups; then the reads of
    the recorded instances that forward nothing (the reference's order)."""
    links = plan.values.links
    connected = [(i, u) for i, u in enumerate(plan.instances) if links[u.name]]
    recorded = [r for u in plan.wiring.record_reads for r in u.readers]
    reads = [r for _i, u in connected for r in u.readers] + recorded
    number = {id(r): i for i, r in enumerate(reads)}
    ops: list[int] = []
    owners: list[int] = []
    groups: list[_Group] = []
    for i, u in connected:
        ops += [number[id(r)] for r in u.readers]
        owners += [i] * len(u.readers)
        mine: dict[tuple[str, str], _Group] = {}
        for vr, target, variable, scale in links[u.name]:
            reader, index = u.reader_of[vr]
            key = (target.name, ACCESSOR[variable.type])
            if key not in mine:
                mine[key] = _Group(target, variable.type, [])
                ops.append(-1 - len(groups))
                owners.append(i)
                groups.append(mine[key])
            mine[key].links.append((number[id(reader)], index, variable.value_reference, scale))
    return _Exchange(reads, ops + [number[id(r)] for r in recorded], groups, owners)


class Flat:
    """``rg_plan`` filled from a plan, and the arrays it points into (see the module's docstring)."""

    def __init__(self, plan: Plan, master, ffi, store: int):
        self.ffi, self.source = ffi, plan
        self.keep: list = []
        self.adapters: dict[str, Adapter] = {}
        self.index = {u.name: i for i, u in enumerate(plan.instances)}
        self.plan = p = self.new("rg_plan *", None)
        self._run(p, plan, master, store)
        self._instances(p, plan)
        self.exchange = _exchange(plan)
        self._reads(p, self.exchange.reads)
        self._sets(p, plan, self.exchange)
        self._clock_arrays(p, plan)
        self._cells(p, plan)
        self._routes(p, plan)
        self._columns(p, plan)
        self._events(p, plan)
        p.dep_vr = self.array("uint32_t[]", self.deps)
        p.n_edges = len(self.edges)
        #: per recorded column: (its kind, how its slot is read back)
        self.columns = [(_COLUMN_KINDS[c.kind], kind(c.variable.type) if c.kind != CLOCK else None)
                        for c in plan.wiring.columns]
        #: per link: the exchange's key of its input and its kind
        self.inputs = [((g.target.name, vr), kind(g.fmi_type)) for g in self.exchange.groups for _r, _i, vr, _s in g.links]

    # -- arrays ---------------------------------------------------------------------------------
    def new(self, ctype: str, init):
        made = self.ffi.new(ctype, init)
        self.keep.append(made)
        return made

    def array(self, ctype: str, values):
        """A C array of these values (one element at least: C has no empty arrays)."""
        if isinstance(values, int):
            return self.new(ctype, max(1, values))
        values = list(values)
        return self.new(ctype, values) if values else self.new(ctype, 1)  # zeroed

    def pointers(self, ctype: str, cdata: list):
        """An array of ``ctype`` holding these C pointers (of any FFI), as addresses."""
        item = ctype[:-2]
        return self.array(ctype, [self.ffi.cast(item, int(fmi_ffi.cast("uintptr_t", c))) for c in cdata])

    def function(self, u: FmuInstance, name: str):
        """The C function the engine calls for ``name`` on instance u: the FMU's own, or its adapter's."""
        raw = u.binding.raw(name)
        if raw is not None:
            return raw
        return self.adapter(u).function(name)

    def handle(self, u: FmuInstance):
        """What u's functions take first: its fmi3Instance, or its adapter's handle."""
        return u.binding.handle if u.binding.raw("fmi3DoStep") is not None else self.adapter(u).handle

    def adapter(self, u: FmuInstance) -> Adapter:
        if u.name not in self.adapters:
            self.adapters[u.name] = Adapter(u.binding, self.ffi)
        return self.adapters[u.name]

    def raise_adapter_failure(self) -> None:
        """The exception of an adapter's call that failed (the engine returned its status)."""
        for adapter in self.adapters.values():
            if adapter.failure is not None:
                failure, adapter.failure = adapter.failure, None
                raise failure

    def notes(self, instances, name: str):
        return self.array("int32_t[]", [u.binding.note_code(name) for u in instances])

    # -- the parts of the plan --------------------------------------------------------------------
    def _run(self, p, plan: Plan, master, store: int) -> None:
        recorder = master.recorder
        p.start, p.step, p.stop, p.stop_limit = plan.start, plan.step, plan.stop, plan.stop_limit
        p.time_tolerance, p.resolution, p.time_ulps = TIME_TOLERANCE, plan.resolution or 0.0, TIME_ULPS
        p.max_iterations = plan.max_iterations
        p.early, p.rollback, p.paced = plan.early, plan.rollback, bool(master.options.realtime)
        p.store = store
        # a CSV file: on disk after every event iteration (written by the engine, or flushed by Python)
        # (not with String columns: Python writes them, as UTF-8 decoded with replacement characters)
        strings = any(c.variable.type == "String" for c in plan.wiring.columns)
        p.fd = recorder.text_file() if store == Store.TEXT and not strings else -1
        p.pause_at_events = p.fd < 0 and recorder.flush_due != math.inf
        p.events_fd = recorder.events_file()
        p.note_call = self.ffi.cast("int32_t *", int(fmi_ffi.cast("uintptr_t", master.notes.call)))
        p.note_time = self.ffi.cast("double *", int(fmi_ffi.cast("uintptr_t", master.notes.time)))
        self._json_text = [self.ffi.NULL]  # the last text the callback gave the engine, kept alive here
        self._json = self.ffi.callback("rg_json_string_fn", _json_string(self.ffi, self._json_text))
        p.json_string = self._json

    def _instances(self, p, plan: Plan) -> None:
        instances, index = plan.instances, self.index
        p.n_instances = len(instances)
        p.instance = self.pointers("void *[]", [self.handle(u) for u in instances])
        p.event_mode = self.array("bool[]", [u.event_mode for u in instances])
        p.step_order = self.array("int[]", [index[u.name] for u in plan.step_order])
        p.n_event = len(plan.event_instances)
        p.event_instance = self.array("int[]", [index[u.name] for u in plan.event_instances])
        for field, ctype, name in (("do_step", "rg_do_step_fn[]", "fmi3DoStep"),
                                   ("enter_event", "rg_mode_fn[]", "fmi3EnterEventMode"),
                                   ("enter_step", "rg_mode_fn[]", "fmi3EnterStepMode"),
                                   ("update", "rg_update_fn[]", "fmi3UpdateDiscreteStates"),
                                   ("get_clock", "rg_get_clock_fn[]", "fmi3GetClock"),
                                   ("set_clock", "rg_set_clock_fn[]", "fmi3SetClock")):
            setattr(p, field, self.pointers(ctype, [self.function(u, name) for u in instances]))
            setattr(p, field.replace("do_step", "step") + "_note", self.notes(instances, name))
        intervals = [self.function(u, "fmi3GetIntervalDecimal") if u.aperiodic else fmi_ffi.NULL for u in instances]
        p.get_interval = self.pointers("rg_get_interval_fn[]", intervals)
        p.get_interval_note = self.notes(instances, "fmi3GetIntervalDecimal")

    def _reads(self, p, reads: list[Reader]) -> None:
        owner = {id(r): u for u in self.source.instances for r in u.readers}
        p.n_reads = len(reads)
        functions = [self.function(owner[id(r)], r.function) for r in reads]
        binary = [r.fmi_type == "Binary" for r in reads]
        p.get = self.pointers("rg_get_fn[]", [fmi_ffi.NULL if b else f for f, b in zip(functions, binary)])
        p.get_binary = self.pointers("rg_get_binary_fn[]", [f if b else fmi_ffi.NULL for f, b in zip(functions, binary)])
        p.read_instance = self.pointers("void *[]", [self.handle(owner[id(r)]) for r in reads])
        p.vrs = self.pointers("uint32_t *[]", [r.c_vrs for r in reads])
        p.count = self.array("size_t[]", [r.count for r in reads])
        p.n_values = self.array("size_t[]", [r.n_values for r in reads])
        p.kind = self.array("int[]", [kind(r.fmi_type) for r in reads])
        p.buffer = self.pointers("void *[]", [r.buffer for r in reads])
        p.sizes = self.pointers("size_t *[]", [r.sizes if r.sizes is not None else fmi_ffi.NULL for r in reads])
        p.read_note = self.array("int32_t[]", [r.binding.note_code(r.function) for r in reads])

    def _sets(self, p, plan: Plan, exchange: _Exchange) -> None:
        groups, index = exchange.groups, self.index
        p.n_ops, p.op = len(exchange.ops), self.array("int[]", exchange.ops)
        p.n_exchange_ops = len(exchange.owners)
        first, count = [0] * len(plan.instances), [0] * len(plan.instances)
        for k, owner in reversed(list(enumerate(exchange.owners))):  # an instance's operations are consecutive
            first[owner] = k
            count[owner] += 1
        p.op_first, p.op_count = self.array("int[]", first), self.array("int[]", count)
        functions = ["fmi3Set" + ACCESSOR[g.fmi_type] for g in groups]
        raw = [self.function(g.target, f) for g, f in zip(groups, functions)]
        binary = [g.fmi_type == "Binary" for g in groups]
        p.n_sets = len(groups)
        p.set = self.pointers("rg_set_fn[]", [fmi_ffi.NULL if b else f for f, b in zip(raw, binary)])
        p.set_binary = self.pointers("rg_set_binary_fn[]", [f if b else fmi_ffi.NULL for f, b in zip(raw, binary)])
        p.set_instance = self.pointers("void *[]", [self.handle(g.target) for g in groups])
        p.set_kind = self.array("int[]", [kind(g.fmi_type) for g in groups])
        p.set_note = self.array("int32_t[]", [g.target.binding.note_code(f) for g, f in zip(groups, functions)])
        counts = [len(g.links) for g in groups]
        p.set_first, p.set_count = self.array("int[]", _starts(counts)[:-1]), self.array("int[]", counts)
        group_owner = {-1 - op: owner for op, owner in zip(exchange.ops, exchange.owners) if op < 0}
        self.edges: dict[tuple[int, int], int] = {}
        p.set_target = self.array("int[]", [index[g.target.name] for g in groups])
        p.set_edge = self.array("int[]", [self.edge(group_owner[i], index[g.target.name]) for i, g in enumerate(groups)])
        links = [link for g in groups for link in g.links]
        p.n_links = len(links)
        p.link_read = self.array("int[]", [r for r, _i, _vr, _s in links])
        p.link_index = self.array("int[]", [i for _r, i, _vr, _s in links])
        p.link_vr = self.array("uint32_t[]", [vr for _r, _i, vr, _s in links])
        p.link_scaled, p.link_factor, p.link_offset = self.scales([s for _r, _i, _vr, s in links])
        p.connected = bool(plan.routes) or bool(plan.domain_routes) or plan.values.connected

    def scales(self, scales: list) -> tuple:
        """Whether each value is converted on its way, and its factor and offset (three NULLs
        where none is: the engine then converts nothing)."""
        if not any(scales):
            return self.ffi.NULL, self.ffi.NULL, self.ffi.NULL
        return (self.array("bool[]", [s is not None for s in scales]), self.array("double[]", [(s or (1.0, 0.0))[0] for s in scales]),
                self.array("double[]", [(s or (1.0, 0.0))[1] for s in scales]))

    def edge(self, source: int, target: int) -> int:
        return self.edges.setdefault((source, target), len(self.edges))

    def dependencies(self, u: FmuInstance, vrs: list[int]) -> tuple[list[int], list[int]]:
        """(first, count) in dep_vr of each output's dependencies (count -1: every input)."""
        first, count = [], []
        for vr in vrs:
            d = u.depends.get(vr)
            first.append(len(self.deps))
            count.append(-1 if d is None else len(d))
            self.deps += sorted(d or ())
        return first, count

    def _clock_arrays(self, p, plan: Plan) -> None:
        instances, self.deps = plan.instances, []
        self.clocks = clocks = [_clocks(u) for u in instances]
        first = _starts([len(c) for c in clocks])
        self.clock_index = {(u.name, vr): first[i] + j for i, u in enumerate(instances) for j, vr in enumerate(clocks[i])}
        p.clock_first, p.clock_count = self.array("int[]", first), self.array("int[]", [len(c) for c in clocks])
        p.clock_vr = self.array("uint32_t[]", [vr for c in clocks for vr in c])
        p.on = self.array("bool[]", [True] * max(1, first[-1]))
        outs = [u.out_clocks for u in instances]
        self.out_first = _starts([len(o) for o in outs])
        p.out_first, p.out_count = self.array("int[]", self.out_first), self.array("int[]", [len(o) for o in outs])
        p.out_vr = self.array("uint32_t[]", [vr for o in outs for vr in o])
        p.out_clock = self.array("int[]", [self.clock_index[u.name, vr] for u in instances for vr in u.out_clocks])
        dep_first, dep_count = [], []
        for u in instances:
            f, c = self.dependencies(u, u.out_clocks)
            dep_first += f
            dep_count += c
        p.out_dep_first, p.out_dep_count = self.array("int[]", dep_first), self.array("int[]", dep_count)
        periodic = [(i, c) for i, u in enumerate(instances) for c in u.periodic]
        self.periodic = [c for _i, c in periodic]
        p.n_periodic = len(periodic)
        p.p_instance = self.array("int[]", [i for i, _c in periodic])
        p.p_clock = self.array("int[]", [self.clock_index[instances[i].name, c.var.value_reference] for i, c in periodic])
        p.p_start = self.array("double[]", [c.start for _i, c in periodic])
        p.p_shift = self.array("double[]", [c.shift for _i, c in periodic])
        p.p_interval = self.array("double[]", [c.interval for _i, c in periodic])
        aperiodic = [(i, c) for i, u in enumerate(instances) for c in u.aperiodic]
        self.aperiodic = [c for _i, c in aperiodic]
        p.n_aperiodic = len(aperiodic)
        p.a_instance = self.array("int[]", [i for i, _c in aperiodic])
        p.a_clock = self.array("int[]", [self.clock_index[instances[i].name, c.var.value_reference] for i, c in aperiodic])
        p.a_countdown = self.array("bool[]", [c.var.interval_variability == "countdown" for _i, c in aperiodic])

    def cell(self, u: FmuInstance, var) -> int:
        """The cell of a clocked variable (one per variable: what was read of it is shared)."""
        key = (u.name, var.value_reference)
        if key not in self.cell_of:
            self.cell_of[key] = len(self.cells)
            self.cells.append((u, var))
        return self.cell_of[key]

    def _cells(self, p, plan: Plan) -> None:
        """The clocked variables read: recorded, carried by a clock route, shown in the events log."""
        self.cells, self.cell_of = [], {}
        self.groups, self.column_cell = [], {}
        for u, of_u in plan.clocked_columns:
            self.groups.append([self.cell(u, var) for _position, var, _clocks in of_u])
            for position, var, _clocks in of_u:
                self.column_cell[position - 2] = self.cell(u, var)
        by_name = plan.by_name
        for (source, _vr), routes in plan.routes.items():
            for _target, _clock, sources, _batches in routes:
                for var in sources:
                    self.cell(by_name[source], var)
        for routes in plan.domain_routes.values():
            for source, _target, _clock, sources, _batches in routes:
                for var in sources:
                    self.cell(source, var)
        for u in plan.instances if plan.event_values is not None else ():
            for variables in plan.event_values[u.name].values():
                for var in variables:
                    self.cell(u, var)
        cells, types = self.cells, {}
        getters = ["fmi3Get" + ACCESSOR[var.type] for _u, var in cells]
        p.n_cells = len(cells)
        p.cell_instance = self.array("int[]", [self.index[u.name] for u, _v in cells])
        p.cell_vr = self.array("uint32_t[]", [var.value_reference for _u, var in cells])
        p.cell_kind = self.array("int[]", [kind(var.type) for _u, var in cells])
        p.cell_type = self.array("int[]", [types.setdefault(var.type, len(types)) for _u, var in cells])
        functions = [self.function(u, g) for (u, _v), g in zip(cells, getters)]
        binary = [var.type == "Binary" for _u, var in cells]
        p.cell_get = self.pointers("rg_get_fn[]", [fmi_ffi.NULL if b else f for f, b in zip(functions, binary)])
        p.cell_get_binary = self.pointers("rg_get_binary_fn[]", [f if b else fmi_ffi.NULL for f, b in zip(functions, binary)])
        p.cell_note = self.array("int32_t[]", [u.binding.note_code(g) for (u, _v), g in zip(cells, getters)])
        p.cell_output = self.array("bool[]", [var.causality == "output" for _u, var in cells])
        own = [[self.clock_index[u.name, c] for c in sorted(set(var.clocks)) if (u.name, c) in self.clock_index]
               for u, var in cells]
        p.cell_clock_first = self.array("int[]", _starts([len(c) for c in own])[:-1])
        p.cell_clock_count = self.array("int[]", [len(c) for c in own])
        p.cell_clock = self.array("int[]", [c for of_cell in own for c in of_cell])
        dep_first, dep_count = [], []
        for u, var in cells:
            f, c = self.dependencies(u, [var.value_reference])
            dep_first += f
            dep_count += c
        p.cell_dep_first, p.cell_dep_count = self.array("int[]", dep_first), self.array("int[]", dep_count)
        p.n_groups = len(self.groups)
        p.group_first = self.array("int[]", _starts([len(g) for g in self.groups])[:-1])
        p.group_count = self.array("int[]", [len(g) for g in self.groups])
        p.group_cell = self.array("int[]", [c for g in self.groups for c in g])

    def _routes(self, p, plan: Plan) -> None:
        """The clock routes of each watched output clock, then the routes between clock domains of
        each clock (the target clock -1 where the input is not clocked), and their Set batches."""
        index, instances = self.index, plan.instances
        routes = [(index[u.name], route) for u in instances for vr in u.out_clocks for route in plan.routes.get((u.name, vr), ())]
        counts = [len(plan.routes.get((u.name, vr), ())) for u in instances for vr in u.out_clocks]
        p.route_first, p.route_count = self.array("int[]", _starts(counts)[:-1]), self.array("int[]", counts)
        keys = [(u.name, vr) for i, u in enumerate(instances) for vr in self.clocks[i]]
        domain = [plan.domain_routes.get(key, ()) for key in keys]
        p.croute_first = self.array("int[]", [len(routes) + f for f in _starts([len(d) for d in domain])[:-1]])
        p.croute_count = self.array("int[]", [len(d) for d in domain])
        routes += [(index[source.name], (target, clock, sources, batches))
                   for of_clock in domain for source, target, clock, sources, batches in of_clock]
        p.route_source_instance = self.array("int[]", [u for u, _route in routes])
        p.route_target = self.array("int[]", [index[t.name] for _u, (t, _c, _s, _b) in routes])
        p.route_clock = self.array("int[]", [-1 if c is None else self.clock_index[t.name, c] for _u, (t, c, _s, _b) in routes])
        p.route_edge = self.array("int[]", [self.edge(u, index[t.name]) for u, (t, _c, _s, _b) in routes])
        sources = [[self.cell_of[instances[u].name, v.value_reference] for v in s] for u, (_t, _c, s, _b) in routes]
        p.route_source_first = self.array("int[]", _starts([len(x) for x in sources])[:-1])
        p.route_source_count = self.array("int[]", [len(x) for x in sources])
        p.route_source = self.array("int[]", [c for x in sources for c in x])
        batches = [(t, b, cells) for (_u, (t, _c, _s, bs)), cells in zip(routes, sources) for b in bs]
        per_route = [len(bs) for _u, (_t, _c, _s, bs) in routes]
        p.route_batch_first = self.array("int[]", _starts(per_route)[:-1])
        p.route_batch_count = self.array("int[]", per_route)
        setters = ["fmi3Set" + ACCESSOR[fmi_type] for _t, (fmi_type, _v, _i, _s), _c in batches]
        functions = [self.function(t, f) for (t, _b, _c), f in zip(batches, setters)]
        binary = [fmi_type == "Binary" for _t, (fmi_type, _v, _i, _s), _c in batches]
        p.batch_set = self.pointers("rg_set_fn[]", [fmi_ffi.NULL if b else f for f, b in zip(functions, binary)])
        p.batch_set_binary = self.pointers("rg_set_binary_fn[]", [f if b else fmi_ffi.NULL for f, b in zip(functions, binary)])
        p.batch_note = self.array("int32_t[]", [t.binding.note_code(f) for (t, _b, _c), f in zip(batches, setters)])
        p.batch_kind = self.array("int[]", [kind(fmi_type) for _t, (fmi_type, _v, _i, _s), _c in batches])
        sizes = [len(vrs) for _t, (_f, vrs, _i, _s), _c in batches]
        p.batch_first, p.batch_count = self.array("int[]", _starts(sizes)[:-1]), self.array("int[]", sizes)
        p.batch_cell = self.array("int[]", [cells[i] for _t, (_f, _v, indices, _s), cells in batches for i in indices])
        p.batch_vr = self.array("uint32_t[]", [vr for _t, (_f, vrs, _i, _s), _c in batches for vr in vrs])
        p.batch_scaled, p.batch_factor, p.batch_offset = self.scales([s for _t, (_f, _v, _i, ss), _c in batches for s in ss])

    def _columns(self, p, plan: Plan) -> None:
        """The record slots: per column its kind, its read (a value) or its clock or cell."""
        columns = plan.wiring.columns
        number = {id(r): i for i, r in enumerate(self.exchange.reads)}
        p.n_columns = len(columns)
        p.column_kind = self.array("int[]", [_COLUMN_KINDS[c.kind] for c in columns])
        p.column_read = self.array("int[]", [number[id(c.reader)] if c.kind == VALUE else -1 for c in columns])
        p.column_index = self.array("int[]", [c.index if c.kind == VALUE else 0 for c in columns])
        p.column_ref = self.array("int[]", [self.clock_index.get((c.instance.name, c.variable.value_reference), -1)
                                            if c.kind == CLOCK else self.column_cell.get(i, 0)
                                            for i, c in enumerate(columns)])

    def _events(self, p, plan: Plan) -> None:
        """Per clock, what its events in the events log show: the JSON of its instance and name,
        and the cells and names of its clocked variables."""
        heads, first, count, cells, keys = [], [], [], [], []
        for u in plan.instances:
            for vr in _clocks(u):
                variables = plan.event_values[u.name].get(vr, []) if plan.event_values is not None else []
                heads.append(f', "fmu": {json.dumps(u.name)}, "clock": {json.dumps(u.by_vr[vr].name)}, "values": {{')
                first.append(len(cells))
                count.append(len(variables))
                cells += [self.cell_of[u.name, var.value_reference] for var in variables]
                keys += [f"{json.dumps(var.name)}: " for var in variables]
        p.event_first, p.event_count = self.array("int[]", first), self.array("int[]", count)
        p.event_cell = self.array("int[]", cells)
        p.event_head = self.array("char *[]", [self.new("char[]", h.encode()) for h in heads])
        p.event_key = self.array("char *[]", [self.new("char[]", k.encode()) for k in keys])


def _json_string(ffi, kept: list):
    """The engine's rg_json_string_fn: a string as JSON text, in a buffer ``kept[0]`` holds until
    the next call. The callback holds that list, not the Flat: one bound to the Flat would make a
    reference cycle (Flat -> callback -> Flat) that only Python's cyclic collector frees."""
    def json_string(data, size, out, out_size) -> int:
        try:
            text = json.dumps(ffi.unpack(data, size).decode("utf-8", "replace")).encode()
            kept[0] = ffi.new("char[]", text)
            out[0], out_size[0] = kept[0], len(text)
            return 0
        except Exception:
            return -1
    return json_string


def flatten(plan: Plan, master, ffi, store: int) -> Flat:
    """The plan as ``rg_plan`` (``flat.plan``), for the master's run (its recorder, notes, options)."""
    return Flat(plan, master, ffi, store)


__all__ = ["Flat", "flatten"]
