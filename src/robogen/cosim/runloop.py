"""The whole run in C (runloop.c): :class:`CRun`, the master's loop after setup, event iterations
included, for the systems it covers; the master's Python loop computes the same results.

It covers a system whose instances the C stretch (:mod:`robogen.cosim.stepper`) can step and read
(FMUs in this process, no trace, recorded types it reads), run without pacing, where at most one
FMU may return early (no rollback) and the time-based input clocks are periodic ones of FMUs in
Event Mode; each FMU has at most 64 clocks; the clocked variables carried by clock connections are
set as the type they were read as, and those the events log shows are numbers or Booleans.
Anything else runs in the master's Python loop (``ROBOGEN_NO_C_STEPPER`` switches the C loops
off). :meth:`CRun.for_master` says which.

Python is entered once per chunk of rows (at most :data:`~robogen.cosim.stepper.CHUNK`, or the
recorder's next flush, :data:`~robogen.cosim.recorder.FLUSH_SECONDS` of wall time away): the rows go
to the recorder, the progress bar moves. An event iteration's rows are on disk when it ends, as the
Python loop's flush puts them: where the rows only go to a CSV file, the loop writes its CSV lines
to the file itself (:meth:`~robogen.cosim.recorder.Recorder.text_file`); where they are also kept,
it returns after every event iteration and Python flushes them.
The run also returns when it ends (the first instance that asked to terminate is reported), when an
FMI call fails (the master's call notes name the instance and the function), and when an event
iteration does not settle (the master reports it, with the clocks active in its last instant) or
the connected values of an instant do not (an algebraic loop, named by how often each connection
set its target's inputs).
"""

from __future__ import annotations

import json
import math
import os
import time
from enum import IntEnum
from itertools import accumulate

from robogen.cosim import stepper
from robogen.cosim.fmi3 import ACCESSOR, FUNCTIONS
from robogen.cosim.recorder import FLUSH_SECONDS
from robogen.cosim.stepper import CHUNK, CStretch, Mode, _FORMAT, kind
from robogen.cosim.stretch import StretchPlan
from robogen.cosim.wiring import CLOCK, CLOCKED, VALUE

ffi = stepper.ffi
ffi.cdef(
    stepper.package_file("runloop.h")
    + """
    int rg_run_system(rg_run *r, long max_rows, double deadline, rg_rows *out, int *status);
    void rg_run_release(rg_run *r);
    """
)

#: The most super-dense instants the C loop takes (a chunk has room for one event iteration).
MAX_ITERATIONS = 100_000
_COLUMN_KINDS = {VALUE: 0, CLOCK: 1, CLOCKED: 2}
_MODE_FUNCTIONS = ("fmi3DoStep", "fmi3EnterEventMode", "fmi3EnterStepMode", "fmi3UpdateDiscreteStates",
                   "fmi3GetClock", "fmi3SetClock")


class End(IntEnum):
    """Why rg_run_system returned (runloop.c's RUN_*)."""

    PAUSE = 0
    DONE = 1
    FAILED = 2
    ZENO = 3
    NO_MEMORY = 4
    LOOP = 5  # connected values that do not settle in an instant
    WRITE = 6  # the results file cannot be written


def _starts(counts: list[int]) -> list[int]:
    """Where each of consecutive runs of these lengths starts, and where the last ends."""
    return [0, *accumulate(counts)]


def _clocks(u) -> list[int]:
    return sorted(v.value_reference for v in u.md.variables if v.is_clock)


def _batch_types(master):
    """The FMI types of the clocked variables the C loop reads (recorded, carried by a clock
    connection, shown in the events log) and sets (their targets), with the instance of each, and
    whether it may be a String or a Binary (not in the events log)."""
    for u, cells in master._clocked_columns:
        for _position, var, _clocks_of in cells:
            yield u, var.type, "fmi3Get", True
    for (source, _vr), routes in master._routes.items():
        for target, _clock, sources, batches in routes:
            for var in sources:
                yield master.by_name[source], var.type, "fmi3Get", True
            for fmi_type, _vrs, _indices in batches:
                yield target, fmi_type, "fmi3Set", True
    if master._events_logged:
        for u in master.instances:
            for variables in master._event_values[u.name].values():
                for var in variables:
                    yield u, var.type, "fmi3Get", False


def _covered(master) -> bool:
    """Whether the C loop covers this run (see the module's docstring)."""
    if master.options.realtime:
        return False
    if sum(u.early for u in master.instances) > 1 or master._aperiodic or master.system.max_event_iterations > MAX_ITERATIONS:
        return False
    if any(not u.event_mode for u in master._timed) or any(len(_clocks(u)) > 64 for u in master.instances):
        return False
    if any(u.binding.raw(f) is None for u in master.instances for f in _MODE_FUNCTIONS):
        return False
    for u, fmi_type, function, bytes_too in _batch_types(master):
        if kind(fmi_type) is None or u.binding.raw(function + ACCESSOR[fmi_type]) is None:
            return False
        if fmi_type in ("String", "Binary") and not bytes_too:
            return False
    for link in master.links:  # a clocked value is set as it was read
        if link.src.is_clocked and not link.src.is_clock and kind(link.src.type) != kind(link.dst.type):
            return False
    return True


class CRun:
    """The master's loop after setup, in C, bound to one run."""

    name = "C"

    @classmethod
    def for_master(cls, master, plan: StretchPlan) -> CRun | None:
        """The C loop for this run, or None where it does not cover it."""
        if not _covered(master):
            return None
        stretch = CStretch.for_plan(plan)
        return cls(master, stretch) if stretch is not None else None

    def __init__(self, master, stretch: CStretch):
        self.master, self.stretch = master, stretch
        self._keep: list = []
        self.r = self._struct(master, stretch)
        self.width = len(master.wiring.columns)
        capacity = CHUNK + master.system.max_event_iterations + 2
        self.out = ffi.new("rg_rows *")
        self.times = self.out.times = ffi.new("double[]", capacity)
        self.index = self.out.index = ffi.new("int32_t[]", capacity)
        self.event = self.out.event = ffi.new("uint8_t[]", capacity)
        slots = capacity * self.width if stretch.mode == Mode.SLOTS else 1
        self.slots = self.out.slots = ffi.new("uint64_t[]", max(1, slots))
        self.present = self.out.present = ffi.new("uint8_t[]", max(1, slots))
        self._status = ffi.new("int *")
        self.columns = [(c.kind, kind(c.variable.type) if c.kind != CLOCK else None) for c in master.wiring.columns]

    def _array(self, ctype: str, values):
        a = ffi.new(ctype, values)
        self._keep.append(a)
        return a

    def _functions(self, ctype: str, name: str):
        return self.stretch._pointers(ctype, [u.binding.raw(name) for u in self.master.instances])

    def _notes(self, name: str):
        return self._array("int32_t[]", [u.binding.note_code(name) for u in self.master.instances] or [0])

    def _struct(self, m, stretch: CStretch):
        r = self._array("rg_run *", None)
        instances = m.instances
        self.number = index = {u.name: i for i, u in enumerate(instances)}
        n = len(instances)
        r.s = stretch.s
        opt = m.options
        r.start, r.step, r.stop, r.stop_limit = opt.start, opt.step, opt.stop, m._stop_limit
        r.max_iterations = m.system.max_event_iterations
        r.early = m.any_early
        r.n_event = len(m.event_instances)
        r.event_instance = self._array("int[]", [index[u.name] for u in m.event_instances] or [0])
        r.step_order = self._array("int[]", [index[u.name] for u in m.step_order] or [0])
        r.enter_event = self._functions("rg_mode_fn[]", "fmi3EnterEventMode")
        r.enter_step = self._functions("rg_mode_fn[]", "fmi3EnterStepMode")
        r.update = self._functions("rg_update_fn[]", "fmi3UpdateDiscreteStates")
        r.get_clock = self._functions("rg_get_clock_fn[]", "fmi3GetClock")
        r.set_clock = self._functions("rg_set_clock_fn[]", "fmi3SetClock")
        r.enter_event_note, r.enter_step_note = self._notes("fmi3EnterEventMode"), self._notes("fmi3EnterStepMode")
        r.update_note, r.get_clock_note = self._notes("fmi3UpdateDiscreteStates"), self._notes("fmi3GetClock")
        r.set_clock_note = self._notes("fmi3SetClock")
        r.time = self._array("double[]", [u.time for u in instances] or [0.0])
        r.has_next = self._array("bool[]", max(1, n))
        r.next_event = self._array("double[]", max(1, n))
        r.needs = self._array("bool[]", max(1, n))
        self.deps: list[int] = []
        self._clock_arrays(r, instances)
        self._cells(r, m, index)
        self._connections(r, m, stretch, index)
        r.dep_vr = self._array("uint32_t[]", self.deps or [0])
        self._events(r, m)
        r.term_who = -1
        r.next_time = m._next_event
        # a CSV file: on disk after every event iteration (written by the loop, or flushed by Python)
        # (not with String columns: Python writes them, as UTF-8 decoded with replacement characters)
        strings = any(c.variable.type == "String" for c in m.wiring.columns)
        r.fd = m.recorder.text_file() if stretch.mode == Mode.TEXT and not strings else -1
        r.pause_at_events = r.fd < 0 and m.recorder.flush_due != math.inf
        r.events_fd = m.recorder.events_file()
        return ffi.gc(r, lambda pointer, _keep=self._keep, _lib=stretch.lib: _lib.rg_run_release(pointer))

    def _dependencies(self, u, vrs: list[int]) -> tuple[list[int], list[int]]:
        """(first, count) in dep_vr of each output's dependencies (count -1: every input)."""
        first, count = [], []
        for vr in vrs:
            d = u.depends.get(vr)
            first.append(len(self.deps))
            count.append(-1 if d is None else len(d))
            self.deps += sorted(d or ())
        return first, count

    def _clock_arrays(self, r, instances) -> None:
        clocks = [_clocks(u) for u in instances]
        first = _starts([len(c) for c in clocks])
        self.clock_index = {(u.name, vr): first[i] + j for i, u in enumerate(instances) for j, vr in enumerate(clocks[i])}
        total = first[-1]
        r.clock_first = self._array("int[]", first)
        r.clock_count = self._array("int[]", [len(c) for c in clocks] or [0])
        r.clock_vr = self._array("uint32_t[]", [vr for c in clocks for vr in c] or [0])
        r.active, r.ticked = self._array("bool[]", max(1, total)), self._array("bool[]", max(1, total))
        outs = [u.out_clocks for u in instances]
        self.out_first = _starts([len(o) for o in outs])
        r.out_first = self._array("int[]", self.out_first)
        r.out_count = self._array("int[]", [len(o) for o in outs] or [0])
        r.out_vr = self._array("uint32_t[]", [vr for o in outs for vr in o] or [0])
        r.out_clock = self._array("int[]", [self.clock_index[u.name, vr] for u in instances for vr in u.out_clocks] or [0])
        r.out_on = self._array("bool[]", max(1, self.out_first[-1]))
        r.out_fresh = self._array("bool[]", max(1, self.out_first[-1]))
        dep_first, dep_count = [], []
        for u in instances:
            f, c = self._dependencies(u, u.out_clocks)
            dep_first += f
            dep_count += c
        r.out_dep_first, r.out_dep_count = self._array("int[]", dep_first or [0]), self._array("int[]", dep_count or [0])
        periodic = [(i, p) for i, u in enumerate(instances) for p in u.periodic]
        r.n_periodic = len(periodic)
        r.p_instance = self._array("int[]", [i for i, _p in periodic] or [0])
        r.p_clock = self._array("int[]", [self.clock_index[instances[i].name, p.var.value_reference] for i, p in periodic] or [0])
        r.p_start = self._array("double[]", [p.start for _i, p in periodic] or [0.0])
        r.p_shift = self._array("double[]", [p.shift for _i, p in periodic] or [0.0])
        r.p_interval = self._array("double[]", [p.interval for _i, p in periodic] or [0.0])
        r.p_k = self._array("int64_t[]", [p.k for _i, p in periodic] or [0])
        self._periodic = [p for _i, p in periodic]
        r.clock_scratch = self._array("uint32_t[]", max(1, total))
        r.on = self._array("bool[]", [True] * max(1, total))

    def _cell(self, u, var) -> int:
        """The cell of a clocked variable (one per variable: what was read of it is shared)."""
        key = (u.name, var.value_reference)
        if key not in self.cell_of:
            self.cell_of[key] = len(self.cells)
            self.cells.append((u, var))
        return self.cell_of[key]

    def _cells(self, r, m, index) -> None:
        """The recorded columns, the clocked variables read (cells) and the recorded ones grouped by instance."""
        self.cells, self.cell_of = [], {}
        groups, column_cell = [], {}
        for u, of_u in m._clocked_columns:
            groups.append([self._cell(u, var) for _position, var, _clocks_of in of_u])
            for position, var, _clocks_of in of_u:
                column_cell[position - 2] = self._cell(u, var)
        for (source, _vr), routes in m._routes.items():
            for _target, _clock, sources, _batches in routes:
                for var in sources:
                    self._cell(m.by_name[source], var)
        for u in m.instances if m._events_logged else ():
            for variables in m._event_values[u.name].values():
                for var in variables:
                    self._cell(u, var)
        cells = self.cells
        types: dict[str, int] = {}
        r.n_columns = len(m.wiring.columns)
        r.column_kind = self._array("int[]", [_COLUMN_KINDS[c.kind] for c in m.wiring.columns] or [0])
        r.column_ref = self._array("int[]", [self.clock_index.get((c.instance.name, c.variable.value_reference), -1)
                                             if c.kind == CLOCK else column_cell.get(i, 0)
                                             for i, c in enumerate(m.wiring.columns)] or [0])
        getters = ["fmi3Get" + ACCESSOR[var.type] for _u, var in cells]
        r.n_cells = len(cells)
        r.cell_instance = self._array("int[]", [index[u.name] for u, _v in cells] or [0])
        r.cell_vr = self._array("uint32_t[]", [var.value_reference for _u, var in cells] or [0])
        r.cell_kind = self._array("int[]", [kind(var.type) for _u, var in cells] or [0])
        r.cell_type = self._array("int[]", [types.setdefault(var.type, len(types)) for _u, var in cells] or [0])
        binary = [var.type == "Binary" for _u, var in cells]
        raw = [u.binding.raw(g) for (u, _v), g in zip(cells, getters)]
        r.cell_get = self.stretch._pointers("rg_get_fn[]", [ffi.NULL if b else f for f, b in zip(raw, binary)])
        r.cell_get_binary = self.stretch._pointers("rg_get_binary_fn[]", [f if b else ffi.NULL for f, b in zip(raw, binary)])
        r.get_sizes = self._array("size_t[]", max(1, len(cells)))
        r.cell_note = self._array("int32_t[]", [u.binding.note_code(g) for (u, _v), g in zip(cells, getters)] or [0])
        r.cell_output = self._array("bool[]", [var.causality == "output" for _u, var in cells] or [False])
        masks = [sum(1 << _clocks(u).index(c) for c in set(var.clocks) if c in _clocks(u)) for u, var in cells]
        r.cell_mask = self._array("uint64_t[]", masks or [0])
        dep_first, dep_count = [], []
        for u, var in cells:
            f, c = self._dependencies(u, [var.value_reference])
            dep_first += f
            dep_count += c
        r.cell_dep_first, r.cell_dep_count = self._array("int[]", dep_first or [0]), self._array("int[]", dep_count or [0])
        size = max(1, len(cells))
        r.cell_raw, r.get_buffer = self._array("uint64_t[]", size), self._array("uint64_t[]", size)
        r.cell_fresh, r.cell_live, r.cell_need = (self._array("bool[]", size) for _ in range(3))
        r.get_vrs, r.get_cells, r.route_scratch = (self._array("uint32_t[]", size), self._array("int[]", size),
                                                   self._array("int[]", size))
        r.n_groups = len(groups)
        r.group_first = self._array("int[]", _starts([len(g) for g in groups])[:-1] or [0])
        r.group_count = self._array("int[]", [len(g) for g in groups] or [0])
        r.group_cell = self._array("int[]", [c for g in groups for c in g] or [0])

    def _events(self, r, m) -> None:
        """Per clock, what its events in the events log show: the JSON of its instance and name,
        and the cells and names of its clocked variables."""
        heads, first, count, cells, keys = [], [], [], [], []
        for u in m.instances:
            for vr in _clocks(u):
                variables = m._event_values[u.name].get(vr, []) if m._events_logged else []
                heads.append(f', "fmu": {json.dumps(u.name)}, "clock": {json.dumps(u.by_vr[vr].name)}, "values": {{')
                first.append(len(cells))
                count.append(len(variables))
                cells += [self.cell_of[u.name, var.value_reference] for var in variables]
                keys += [f"{json.dumps(var.name)}: " for var in variables]
        r.event_first, r.event_count = self._array("int[]", first or [0]), self._array("int[]", count or [0])
        r.event_cell = self._array("int[]", cells or [0])
        r.event_head = self._array("char *[]", [self._array("char[]", h.encode()) for h in heads] or [ffi.NULL])
        r.event_key = self._array("char *[]", [self._array("char[]", k.encode()) for k in keys] or [ffi.NULL])

    def _edge(self, source: int, target: int) -> int:
        return self.edges.setdefault((source, target), len(self.edges))

    def _connections(self, r, m, stretch: CStretch, index) -> None:
        """The value links (the stretch's operations, by instance) and the clock routes."""
        self.edges: dict[tuple[int, int], int] = {}
        layout, instances = stretch.layout, m.instances
        r.connected = bool(m._routes) or m.values.connected
        by_binding = {id(u.binding): i for i, u in enumerate(instances)}
        owner_of_read = [by_binding[id(rd.binding)] for rd in layout.reads]
        r.n_exchange_ops = n_exchange = len(layout.ops) - len(stretch.plan.reads)
        owners = [owner_of_read[op] if op >= 0 else owner_of_read[layout.groups[-1 - op].links[0][0]]
                  for op in layout.ops[:n_exchange]]
        op_first, op_count = [0] * len(instances), [0] * len(instances)
        for k, owner in reversed(list(enumerate(owners))):  # an instance's operations are consecutive
            op_first[owner] = k
            op_count[owner] += 1
        r.op_first, r.op_count = self._array("int[]", op_first or [0]), self._array("int[]", op_count or [0])
        group_owner = {-1 - op: owner for op, owner in zip(layout.ops, owners) if op < 0}
        r.set_target = self._array("int[]", [index[g.target.name] for g in layout.groups] or [0])
        r.set_edge = self._array("int[]", [self._edge(group_owner[i], index[g.target.name])
                                           for i, g in enumerate(layout.groups)] or [0])
        routes = [(index[u.name], route) for u in instances for vr in u.out_clocks for route in m._routes.get((u.name, vr), ())]
        counts = [len(m._routes.get((u.name, vr), ())) for u in instances for vr in u.out_clocks]
        r.route_first = self._array("int[]", _starts(counts)[:-1] or [0])
        r.route_count = self._array("int[]", counts or [0])
        r.route_target = self._array("int[]", [index[t.name] for _u, (t, _c, _s, _b) in routes] or [0])
        r.route_clock = self._array("int[]", [self.clock_index[t.name, c] for _u, (t, c, _s, _b) in routes] or [0])
        r.route_edge = self._array("int[]", [self._edge(u, index[t.name]) for u, (t, _c, _s, _b) in routes] or [0])
        sources = [[self.cell_of[instances[u].name, v.value_reference] for v in s] for u, (_t, _c, s, _b) in routes]
        r.route_source_first = self._array("int[]", _starts([len(x) for x in sources])[:-1] or [0])
        r.route_source_count = self._array("int[]", [len(x) for x in sources] or [0])
        r.route_source = self._array("int[]", [c for x in sources for c in x] or [0])
        batches = [(t, b, cells) for (_u, (t, _c, _s, bs)), cells in zip(routes, sources) for b in bs]
        per_route = [len(bs) for _u, (_t, _c, _s, bs) in routes]
        r.route_batch_first = self._array("int[]", _starts(per_route)[:-1] or [0])
        r.route_batch_count = self._array("int[]", per_route or [0])
        setters = ["fmi3Set" + ACCESSOR[fmi_type] for _t, (fmi_type, _v, _i), _c in batches]
        raw = [t.binding.raw(f) for (t, _b, _c), f in zip(batches, setters)]
        binary = [fmi_type == "Binary" for _t, (fmi_type, _v, _i), _c in batches]
        r.batch_set = stretch._pointers("rg_set_fn[]", [ffi.NULL if b else f for f, b in zip(raw, binary)])
        r.batch_set_binary = stretch._pointers("rg_set_binary_fn[]", [f if b else ffi.NULL for f, b in zip(raw, binary)])
        r.batch_note = self._array("int32_t[]", [t.binding.note_code(f) for (t, _b, _c), f in zip(batches, setters)] or [0])
        r.batch_kind = self._array("int[]", [kind(fmi_type) for _t, (fmi_type, _v, _i), _c in batches] or [0])
        sizes = [len(vrs) for _t, (_f, vrs, _i), _c in batches]
        r.batch_first = self._array("int[]", _starts(sizes)[:-1] or [0])
        r.batch_count = self._array("int[]", sizes or [0])
        r.batch_cell = self._array("int[]", [cells[i] for _t, (_f, _v, indices), cells in batches for i in indices] or [0])
        r.batch_vr = self._array("uint32_t[]", [vr for _t, (_f, vrs, _i), _c in batches for vr in vrs] or [0])
        r.set_scratch = self._array("uint64_t[]", max([1, *sizes]))
        r.forwarded = self._array("bool[]", max(1, self.out_first[-1]))
        n = max(1, len(instances))
        r.queued, r.woken, r.woken_edge = self._array("bool[]", n), self._array("bool[]", n), self._array("int[]", n)
        r.n_edges = len(self.edges)
        r.woke = self._array("long[]", max(1, len(self.edges)))

    # -- the run ---------------------------------------------------------------------------------
    def run(self, progress) -> float:
        """The run from the end of setup to its end; the time reached."""
        self.stretch._lend_inputs()
        try:
            return self._run(progress)
        finally:
            self.stretch._take_inputs_back()

    def _run(self, progress) -> float:
        m, r = self.master, self.r
        recorder = m.recorder
        while True:
            if r.fd >= 0:
                recorder.flush()  # the lines Python wrote first
            deadline = min(time.monotonic() + FLUSH_SECONDS, recorder.flush_due)
            end = End(self.stretch.lib.rg_run_system(r, CHUNK, deadline, self.out, self._status))
            recorder.wrote_rows(r.written)
            self._record(self.out.rows - r.written)
            self._sync()
            if r.event_ended:
                r.event_ended = False
                recorder.flush()
            if end == End.PAUSE:
                if progress.enabled:
                    progress.update(r.t)
                continue
            if end == End.FAILED:
                code = m.notes.call[0]
                u = m.by_name[m.notes.instances[code >> 8]]
                raise u.binding.error(FUNCTIONS[code & 255], self._status[0])
            if end == End.ZENO:
                self._zeno()
            if end == End.NO_MEMORY:
                raise MemoryError("no memory left for the recorded Strings and Binaries")
            if end == End.WRITE:
                raise OSError(f"cannot write the results file: {os.strerror(ffi.errno)}")
            if end == End.LOOP:
                names = [u.name for u in m.instances]
                woke = {(names[a], names[b]): r.woke[e] for (a, b), e in self.edges.items() if r.woke[e] > 0}
                raise m._algebraic_loop(r.t, woke)
            if r.term_who >= 0:
                by = "fmi3DoStep" if r.term_by == 0 else "fmi3UpdateDiscreteStates"
                m._terminated(m.instances[r.term_who], by, r.term_t)
            return r.t

    def _sync(self) -> None:
        """The statistics, the instances' times and their clocks' schedules, as the Python loop keeps them."""
        m, r = self.master, self.r
        stats = m.stats
        stats.steps, stats.event_iterations, stats.instants = r.steps, r.event_iterations, r.instants
        stats.early_returns = r.early_returns
        for i, u in enumerate(m.instances):
            u.time = r.time[i]
        for p, k in zip(self._periodic, ffi.unpack(r.p_k, len(self._periodic))):
            p.k = k

    def _zeno(self) -> None:
        m, r = self.master, self.r
        index = {u.name: i for i, u in enumerate(m.instances)}
        needs = [u for u in m.event_instances if r.needs[index[u.name]]]
        ticked = {u.name: {vr for vr in _clocks(u) if r.ticked[self.clock_index[u.name, vr]]} for u in m.instances}
        m._zeno(r.t, r.zeno_k, needs, ticked)

    def _record(self, count: int) -> None:
        """The chunk's rows to the recorder, as the mode stored them."""
        recorder, mode = self.master.recorder, self.stretch.mode
        if count <= 0:
            return
        if mode == Mode.NONE:  # counted: an events log with rows recorded is kept
            recorder.wrote_rows(count)
            return
        if mode == Mode.TEXT:
            s = self.stretch.s
            recorder.append_text(ffi.buffer(s.text.data, s.text.used)[:].decode("utf-8", "replace"), count)
            return
        rows = self._rows(count)
        if recorder.every is None:
            recorder.append_rows(rows)
            return
        for row, event in zip(rows, ffi.unpack(self.event, count)):
            if event:
                recorder.append_event_row(row)
            else:
                recorder.append_row(row)

    def _rows(self, count: int) -> list[list]:
        """The first ``count`` stored rows as result rows: [t, k, values...]."""
        width = self.width
        raw = memoryview(ffi.buffer(self.slots, count * width * 8))
        views = {f: raw.cast(f) for f in ("d", "q", "Q")}
        present = ffi.buffer(self.present, count * width)[:]
        columns = [ffi.unpack(self.times, count), ffi.unpack(self.index, count)]
        for c, (column_kind, slot_kind) in enumerate(self.columns):
            if column_kind == CLOCK:
                columns.append(views["Q"][c:count * width:width].tolist())
                continue
            values = views[_FORMAT[slot_kind]][c:count * width:width].tolist()
            if column_kind == CLOCKED:  # an empty cell's slot holds nothing
                values = [v if p else None for v, p in zip(values, present[c::width])]
            if slot_kind == stepper._BOOL:
                values = [v if v is None else bool(v) for v in values]
            elif slot_kind in (stepper._STRING, stepper._BINARY):
                shown = [v for v in values if v is not None]
                copies = iter(self.stretch._copies(shown, slot_kind == stepper._STRING))
                values = [v if v is None else next(copies) for v in values]
            columns.append(values)
        return list(map(list, zip(*columns)))
