"""The engine: the master's algorithm in C, run on a run's plan (engine.h, engine_*.c).

:class:`Engine` runs a :class:`~robogen.cosim.master.Master`'s run after setup: the plan
(:mod:`robogen.cosim.plan`) flattened to ``rg_plan`` (:mod:`robogen.cosim.flat`), the engine's
state made by ``rg_engine_new``, then ``rg_engine_run`` called until the run ends. Every system
runs here: instances in a worker process or traced are called through adapters
(:mod:`robogen.cosim.adapters`) behind the same C function pointers. ``rg_engine_run`` returns to
Python with a reason (:class:`End`, the header's ``enum rg_end``): a chunk of rows to hand to the
recorder (at most :data:`CHUNK`, or the recorder's next flush, :data:`~robogen.cosim.recorder.FLUSH_SECONDS`
of wall time away), an event iteration whose rows are to be flushed, a paced point to wait for,
a general step of FMUs that roll back (the master steps them: :meth:`Master.step_with_early_returns`),
a failure, the end. Every enumeration and the layout of the plan come from ``engine.h`` (cffi reads
it): this module has no copy of them.

The library is compiled once with the system C compiler and cached under ``$XDG_CACHE_HOME/robogen``
(or ``~/.cache/robogen``), named by the hash of its source; where there is no compiler,
:func:`load` returns None and the master runs its Python loop, the engine's executable reference.
"""

from __future__ import annotations

import functools
import os
import struct
import time
from pathlib import Path

import numpy as np

from robogen.cosim.cbuild import cached_library, package_source
from robogen.cosim.fmi3 import FUNCTIONS
from robogen.cosim.flat import flatten
from robogen.cosim.recorder import FLUSH_SECONDS
from robogen.cosim.schema import SIGNED, SLOT_FORMAT, By, ColumnKind, End, Kind, Store, ffi, package_file
from robogen.cosim.wiring import UNSET

#: The engine's C files, compiled as one unit in this order (the first includes the header).
SOURCES = ("engine_values.c", "engine_run.c", "engine_events.c")

#: Rows the engine stores before it hands them to the recorder.
CHUNK = 4096
_SIZE = struct.Struct("N")
_SLOT_TYPES = {"d": np.float64, "q": np.int64, "Q": np.uint64}  # a slot's NumPy type, by its SLOT_FORMAT  # the length before each copy in the arena (size_t)


def load():
    """The compiled engine, or None where no C compiler is at hand (checked once per process)."""
    return _library()


def source() -> bytes:
    """The engine's C source: its files, each from its own line 1 for the compiler's messages,
    with the header in place of its #include line."""
    return package_source(SOURCES, package_file)


@functools.cache
def _library():
    def compile_to(c_file: Path, so: Path) -> None:
        from robogen import toolchain

        toolchain.compile_shared([c_file], so, libs=(), what="the master's C engine")

    try:
        return ffi.dlopen(str(cached_library("engine", source(), compile_to)))
    except Exception:  # no compiler, no folder to write, ...: the reference loop does the same work
        return None


class Engine:
    """One run of a master's plan in C (see the module's docstring)."""

    name = "C"

    def __init__(self, lib, master):
        self.lib, self.master = lib, master
        self.flat = flatten(master.plan, master, ffi, store=_store(master.recorder))
        engine = lib.rg_engine_new(self.flat.plan)
        if engine == ffi.NULL:
            raise MemoryError("no memory left for the engine")
        self.e = ffi.gc(engine, lib.rg_engine_free)
        self._status = ffi.new("int *")

    # -- the run ---------------------------------------------------------------------------------
    def run(self, progress) -> float:
        """The run from the end of setup to its end; the time reached."""
        self._start()
        try:
            return self._run(progress)
        finally:
            self._take_inputs_back()

    def _start(self) -> None:
        """The state the run starts from: the instances' times, their clocks' schedules, the
        values last set to the connected inputs (in Initialization Mode)."""
        e, plan, flat = self.e, self.master.plan, self.flat
        for i, u in enumerate(plan.instances):
            e.time[i] = u.time
        for i, p in enumerate(flat.periodic):
            e.p_k[i] = p.k
        for i, a in enumerate(flat.aperiodic):
            e.a_next[i] = a.next_time()
        last_set = plan.values.last_set
        for k, (key, slot_kind) in enumerate(flat.inputs):
            value = last_set.get(key, UNSET)
            e.last_valid[k] = value is not UNSET
            if value is UNSET:
                continue
            if slot_kind in (Kind.F64, Kind.F32):
                e.last[k].d = value
            elif slot_kind in (Kind.STRING, Kind.BINARY):
                data = value.encode() if isinstance(value, str) else bytes(value)
                if self.lib.rg_keep_last(e, k, data, len(data)) != 0:
                    raise MemoryError("no memory left for the connected Strings and Binaries")
            elif slot_kind in SIGNED:
                e.last[k].i = value
            else:
                e.last[k].u = int(value)

    def _take_inputs_back(self) -> None:
        """The values the engine set to the connected inputs, back to the exchange (as the
        reference keeps them)."""
        e, last_set = self.e, self.master.plan.values.last_set
        for k, (key, slot_kind) in enumerate(self.flat.inputs):
            if not e.last_valid[k]:
                continue
            if slot_kind in (Kind.F64, Kind.F32):
                last_set[key] = e.last[k].d
            elif slot_kind in (Kind.STRING, Kind.BINARY):
                data = ffi.unpack(e.last_bytes[k], e.last_size[k])
                last_set[key] = data.decode("utf-8", "replace") if slot_kind == Kind.STRING else data
            elif slot_kind in SIGNED:
                last_set[key] = e.last[k].i
            else:
                last_set[key] = bool(e.last[k].u) if slot_kind == Kind.BOOL else e.last[k].u

    def _run(self, progress) -> float:
        m, e, recorder = self.master, self.e, self.master.recorder
        pacer = m.start_pacing() if self.flat.plan.paced else None
        while True:
            if self.flat.plan.fd >= 0:
                recorder.flush()  # the lines Python wrote first
            deadline = min(time.monotonic() + FLUSH_SECONDS, recorder.flush_due)
            e.written = 0
            try:
                end = End(self.lib.rg_engine_run(e, CHUNK, deadline, self._status))
            finally:  # a signal is raised as the call returns: the rows it wrote to the file count
                recorder.wrote_rows(e.written)
            self._record(e.rows.rows - e.written)
            self._sync()
            if e.event_ended:
                e.event_ended = False
                recorder.flush()
            if end == End.PAUSE:
                if progress.enabled:
                    progress.update(e.t)
            elif end == End.PACE:
                pacer.wait(e.t)
            elif end == End.STEP:
                self._step_in_python(pacer)
            else:
                self._raise_failure(end)
                if e.term_who >= 0:
                    by = "fmi3DoStep" if e.term_by == By.DO_STEP else "fmi3UpdateDiscreteStates"
                    m.terminated(m.instances[e.term_who], by, e.term_t)
                return e.t

    def _step_in_python(self, pacer) -> None:
        """A general step of FMUs that roll back, from e.t to e.step_to: the master's."""
        m, e = self.master, self.e
        before = m.stats.early_returns
        t, event, terminating = m.step_with_early_returns(e.t, e.step_to)
        e.early_returns += m.stats.early_returns - before
        index = {u.name: i for i, u in enumerate(m.instances)}
        for i, u in enumerate(m.instances):
            e.time[i] = u.time
        for u, when in terminating:
            if e.term_who < 0:
                e.term_who, e.term_by, e.term_t = index[u.name], By.DO_STEP, when
        if pacer is not None:
            pacer.wait(t)
        self.lib.rg_engine_stepped(e, t, event)

    def _raise_failure(self, end: End) -> None:
        m, e = self.master, self.e
        if end == End.FAILED:
            self.flat.raise_adapter_failure()
            code = m.notes.call[0]
            u = m.by_name[m.notes.instances[code >> 8]]
            raise u.binding.error(FUNCTIONS[code & 255], self._status[0])
        if end == End.ZENO:
            index = {u.name: i for i, u in enumerate(m.instances)}
            needs = [u for u in m.plan.event_instances if e.needs[index[u.name]]]
            ticked = {u.name: {vr for vr in self.flat.clocks[i] if e.ticked[self.flat.clock_index[u.name, vr]]}
                      for i, u in enumerate(m.instances)}
            m.zeno(e.t, e.zeno_k, needs, ticked)
        if end == End.NO_MEMORY:
            raise MemoryError("no memory left for the recorded Strings and Binaries")
        if end == End.WRITE:
            raise OSError(f"cannot write the results file: {os.strerror(ffi.errno)}")
        if end == End.RANGE:
            kind_ = Kind(e.range_kind)
            value = e.range_value.d if kind_ in (Kind.F64, Kind.F32) else e.range_value.i if kind_ in SIGNED else e.range_value.u
            raise m.narrowing((m.instances[e.range_target].name, e.range_vr), value)
        if end == End.LOOP:
            names = [u.name for u in m.instances]
            woke = {(names[a], names[b]): e.woke[k] for (a, b), k in self.flat.edges.items() if e.woke[k] > 0}
            raise m.algebraic_loop(e.t, woke)

    def _sync(self) -> None:
        """The statistics, the instances' times and their clocks' schedules, as the reference keeps them."""
        m, e = self.master, self.e
        stats = m.stats
        stats.steps, stats.event_iterations, stats.instants = e.steps, e.event_iterations, e.instants
        stats.early_returns = e.early_returns
        for i, u in enumerate(m.instances):
            u.time = e.time[i]
        for i, p in enumerate(self.flat.periodic):
            p.k = e.p_k[i]
        for i, a in enumerate(self.flat.aperiodic):
            a.next = None if e.a_next[i] == float("inf") else e.a_next[i]

    # -- rows ------------------------------------------------------------------------------------
    def _record(self, count: int) -> None:
        """The call's rows to the recorder, as the plan stored them."""
        recorder, store = self.master.recorder, Store(self.flat.plan.store)
        if count <= 0:
            return
        if store == Store.NONE:  # counted: an events log with rows recorded is kept
            recorder.wrote_rows(count)
            return
        if store == Store.TEXT:
            recorder.append_text(ffi.buffer(self.e.text.data, self.e.text.used)[:].decode("utf-8", "replace"), count)
            return
        columns, valid = self._columns(count)
        if recorder.every is None:
            recorder.append_chunk(columns, valid, count, lambda: _as_rows(columns, valid, count))
            return
        for row, event in zip(_as_rows(columns, valid, count), ffi.unpack(self.e.rows.event, count)):
            if event:
                recorder.append_event_row(row)
            else:
                recorder.append_row(row)

    def _columns(self, count: int) -> tuple[list, list]:
        """The first ``count`` stored rows as columns ([times, indices, values...]: arrays that
        view the engine's chunk, lists of Strings and Binaries), and per column where its cells
        have a value (None: everywhere)."""
        out, columns_of = self.e.rows, self.flat.columns
        width, capacity = len(columns_of), out.capacity  # the engine stores the chunk by column
        slots = np.frombuffer(ffi.buffer(out.slots, capacity * width * 8), np.uint64).reshape(width, capacity)[:, :count]
        present = np.frombuffer(ffi.buffer(out.present, capacity * width), np.bool_).reshape(width, capacity)[:, :count]
        columns: list = [np.frombuffer(ffi.buffer(out.times, count * 8), np.float64),
                         np.frombuffer(ffi.buffer(out.index, count * 4), np.int32)]
        valid: list = [None, None]
        for c, (column_kind, slot_kind) in enumerate(columns_of):
            values = slots[c]
            ok = present[c] if column_kind == ColumnKind.CLOCKED else None
            if column_kind != ColumnKind.CLOCK:
                values = values.view(_SLOT_TYPES[SLOT_FORMAT[slot_kind]])
            if slot_kind in (Kind.STRING, Kind.BINARY) and column_kind != ColumnKind.CLOCK:
                shown = values.tolist() if ok is None else [v if p else None for v, p in zip(values.tolist(), ok.tolist())]
                copies = iter(self._copies([v for v in shown if v is not None], slot_kind == Kind.STRING))
                values = [v if v is None else next(copies) for v in shown]
            elif slot_kind == Kind.BOOL and column_kind != ColumnKind.CLOCK:
                values = values != 0
            columns.append(values)
            valid.append(ok)
        return columns, valid

    def _copies(self, offsets: list[int], text: bool) -> list:
        """The Strings (``text``) or Binaries at these offsets of the arena."""
        arena = ffi.buffer(self.e.arena.data, self.e.arena.used)
        out = []
        for offset in offsets:
            start = offset + _SIZE.size
            data = arena[start:start + _SIZE.unpack_from(arena, offset)[0]]
            out.append(data.decode("utf-8", "replace") if text else data)
        return out


def _as_rows(columns: list, valid: list, count: int) -> list[list]:
    """The rows of a chunk of columns (Engine._columns) as lists, None for an empty cell."""
    values = []
    for column, ok in zip(columns, valid):
        cells = column.tolist() if isinstance(column, np.ndarray) else column
        if ok is not None:
            cells = [v if p else None for v, p in zip(cells, ok.tolist())]
        values.append(cells)
    return list(map(list, zip(*values)))


def _store(recorder) -> Store:
    if recorder.takes_text:
        return Store.TEXT
    return Store.NONE if recorder.discards else Store.SLOTS
