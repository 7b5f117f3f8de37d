"""One FMU instance as the master sees it: its binding, its clocks' timing, its value buffers.

A :class:`FmuInstance` holds the instance's binding: a :class:`~robogen.cosim.fmi3.Binding` in
this process, or anything with the same methods (a proxy to a worker process would do; a binding
whose :meth:`~robogen.cosim.fmi3.Binding.raw` gives no C functions keeps the master in its
general loop). Beside it: the schedule of its time-based input clocks (:mod:`robogen.cosim.clocks`),
the :class:`Reader` of each type of the outputs the master reads after a step (one cffi buffer and
one Get call per type), the output clocks it watches and the set of its clocks active in the
current super-dense instant.

In Event Mode the master reads clocked values and sets inputs in batches: one Get or Set call per
type for all the variables a clock carries (:meth:`FmuInstance.clocked_values`,
:meth:`FmuInstance.set_values`), through buffers made once per set of value references. A
clocked output or an output clock read in a super-dense instant is not read again in that
instant unless a call since could have changed it. FMI 3.0 lets an output change in Event Mode only through
fmi3UpdateDiscreteStates (which closes the instant) or a Set/SetClock of a known it depends on:
its ``<Output dependencies>`` in the ModelStructure (none given: every known). So a Set or
SetClock forgets the outputs that depend on what it set, and :meth:`FmuInstance.new_instant`
(after fmi3UpdateDiscreteStates and fmi3EnterEventMode) forgets them all.
"""

from __future__ import annotations

import math
from pathlib import Path

from robogen.cosim.clocks import APERIODIC, PERIODIC, Aperiodic, Periodic
from robogen.cosim.fmi3 import (
    ACCESSOR, Binding, FMI3Error, decode_binaries, decode_strings, ffi, size_array, value_array, vr_array,
)
from robogen.diagnostics import Note, RobogenError, Span
from robogen.fmu.fmi import FATAL, INTERVAL_CHANGED, INTERVAL_NOT_YET_KNOWN, WARNING, status_name
from robogen.fmu.modeldesc import ModelDescription, Variable


class Reader:
    """One fmi3Get<Type> call that fills a buffer with several variables of one instance.

    ``values[i]`` is the value of ``vrs[i]`` after :meth:`read`: the cffi buffer itself for
    numbers and Booleans, a list of ``str`` (String) or ``bytes`` (Binary) decoded from it. A
    binding without raw C access (a trace, a worker process) is read through its list API.
    """

    def __init__(self, binding: Binding, fmi_type: str, vrs: list[int], counts: list[int] | None = None):
        self.binding, self.fmi_type, self.vrs = binding, fmi_type, vrs
        counts = counts or [1] * len(vrs)  # the values of each (an array's elements, row-major)
        self.index = dict(zip(vrs, [sum(counts[:i]) for i in range(len(vrs))]))  # where each one's values start
        self.count = len(vrs)
        self.n_values = sum(counts)
        self.c_vrs = vr_array(vrs)
        self.buffer = value_array(fmi_type, self.n_values)
        self.sizes = size_array(self.count) if fmi_type == "Binary" else None
        self.decodes = fmi_type in ("String", "Binary")  # values holds the buffer's contents decoded
        self.function = "fmi3Get" + ACCESSOR[fmi_type]
        self.c_function = binding.raw(self.function)  # None while tracing or out of process
        self.values = [None] * self.n_values if self.decodes or self.c_function is None else self.buffer
        self.note_code = binding.note_code(self.function) if self.c_function is not None else 0

    def read(self) -> None:
        if self.c_function is None:
            arrays = (self.n_values,) if self.n_values != self.count else ()  # a binding's list API takes scalars alone too
            self.values[:] = self.binding.get_values(self.fmi_type, self.vrs, *arrays)
            return
        self.binding.notes.call[0] = self.note_code
        if self.sizes is not None:
            status = self.c_function(self.binding.handle, self.c_vrs, self.count, self.sizes, self.buffer, self.count)
        else:
            status = self.c_function(self.binding.handle, self.c_vrs, self.count, self.buffer, self.n_values)
        if status > WARNING:
            raise self.binding.error(self.function, status)
        if self.sizes is not None:
            self.values[:] = decode_binaries(self.sizes, self.buffer, self.count)
        elif self.decodes:
            self.values[:] = decode_strings(self.buffer, self.count)


class Writer:
    """One fmi3Set<Type> call of several variables of one instance, from a buffer made once
    (numbers and Booleans); Strings and Binaries, and a binding without raw C access, go through
    the binding's list API."""

    def __init__(self, binding: Binding, fmi_type: str, vrs: list[int]):
        self.binding, self.fmi_type, self.vrs = binding, fmi_type, vrs
        self.count = len(vrs)
        self.function = "fmi3Set" + ACCESSOR[fmi_type]
        numeric = fmi_type not in ("String", "Binary")
        self.c_function = binding.raw(self.function) if numeric else None
        if self.c_function is not None:
            self.c_vrs = vr_array(vrs)
            self.buffer = value_array(fmi_type, self.count)
            self.note_code = binding.note_code(self.function)

    def write(self, values: list) -> None:
        if self.c_function is None:
            self.binding.set_values(self.fmi_type, self.vrs, values)
            return
        self.buffer[0:self.count] = values
        self.binding.notes.call[0] = self.note_code
        status = self.c_function(self.binding.handle, self.c_vrs, self.count, self.buffer, self.count)
        if status > WARNING:
            raise self.binding.error(self.function, status)


class ClockSetter:
    """One fmi3SetClock call activating several input clocks, from arrays made once."""

    def __init__(self, binding: Binding, vrs: list[int]):
        self.binding, self.count = binding, len(vrs)
        self.c_vrs = vr_array(vrs)
        self.on = ffi.new("bool[]", [True] * max(self.count, 1))

    def write(self) -> None:
        self.binding.fmi3SetClock(self.c_vrs, self.count, self.on)


class FmuInstance:
    """One instance of an FMU in the system: what the master knows and keeps about it between calls."""

    def __init__(self, name: str, md: ModelDescription, folder: Path, binding: Binding, span: Span):
        self.name, self.md, self.folder, self.span = name, md, folder, span
        cs = md.co_simulation
        self.event_mode = cs.has_event_mode
        self.early = cs.might_return_early
        self.can_state = cs.can_get_and_set_state
        self.binding = binding
        self.vars = md.by_name()
        self.by_vr = md.by_vr()
        self.clock_vrs = sorted(v.value_reference for v in md.variables if v.is_clock)
        self.time = 0.0  # where this instance is: the communication point of its last step
        self.periodic: list[Periodic] = []
        self.aperiodic: list[Aperiodic] = []
        self.next_event_time: float | None = None
        self.active: set[int] = set()  # clock vrs active in the current instant
        self.readers: list[Reader] = []
        self.reader_of: dict[int, tuple[Reader, int]] = {}
        self.out_clocks: list[int] = []
        self.out_clock_buffer = None
        self.failed_status: int | None = None  # set when a call returned Error/Fatal
        #: each output's ModelStructure dependencies (None: every known)
        self.depends = {u.value_reference: None if u.dependencies is None else frozenset(u.dependencies)
                        for u in md.unknowns if u.kind == "Output"}
        self._fresh: dict[int, object] = {}  # clocked outputs read in this instant, unchanged since
        self._batches: dict[tuple, Reader | Writer | ClockSetter] = {}  # by (kind, type, value references)

    # -- life cycle -------------------------------------------------------------------------
    def instantiate(self, start: float) -> None:
        self.time = start
        res = self.folder / "resources"
        resources = str(res.resolve()) + "/" if res.is_dir() else None
        self.binding.fmi3InstantiateCoSimulation(self.md.instantiation_token, resources, False, False,
                                                 eventModeUsed=self.event_mode, earlyReturnAllowed=self.early)

    def set_start_values(self, values: dict[str, tuple[object, Span]]) -> None:
        """The system file's start values, one Set call each (Initialization Mode); a value the
        FMU refuses is reported at its key in the system file."""
        for name, (value, span) in values.items():
            var = self.vars[name]
            try:
                self.set_values(var.type, [var.value_reference], [value])
            except FMI3Error as exc:
                logged = [Note(f"the FMU logged: {exc.message}")] if exc.message else []
                raise RobogenError.at(f"instance '{self.name}' refused the start value {value!r} of '{name}' "
                                      f"({exc.function} returned {status_name(exc.status)})", span, *logged) from None

    def shut_down(self) -> None:
        """fmi3Terminate if healthy, then free; never call an instance again after fmi3Fatal."""
        if self.failed_status == FATAL or not self.binding.instantiated:
            return
        if self.failed_status is None:
            try:
                self.binding.fmi3Terminate()
            except FMI3Error:
                pass
        try:
            self.binding.fmi3FreeInstance()
        except FMI3Error:  # an isolated instance's worker that died meanwhile: nothing left to free
            pass

    # -- time-based input clocks ------------------------------------------------------------
    def schedule_clocks(self, start: float, overrides: dict[str, dict]) -> None:
        """Learn when each time-based input clock ticks (Initialization Mode): periodic ones from
        the system file's interval/shift, the model description or the FMU; aperiodic ones from
        the FMU's first interval."""
        for var in self.md.variables:
            if var.is_clock and var.causality == "input":
                if var.interval_variability in PERIODIC:
                    self.periodic.append(self._periodic(var, start, overrides.get(var.name, {})))
                elif var.interval_variability in APERIODIC:
                    intervals, qualifiers = self.binding.fmi3GetIntervalDecimal(vr_array([var.value_reference]), 1)
                    known = qualifiers[0] != INTERVAL_NOT_YET_KNOWN
                    self.aperiodic.append(Aperiodic(var, start + intervals[0] if known else None))

    def _periodic(self, var: Variable, start: float, override: dict) -> Periodic:
        vr = vr_array([var.value_reference])
        if "interval" in override:
            self.binding.fmi3SetIntervalDecimal(vr, 1, [override["interval"]])
        if "shift" in override:
            self.binding.fmi3SetShiftDecimal(vr, 1, [override["shift"]])
        interval = override.get("interval", var.interval)
        shift = override.get("shift", var.shift)
        if var.interval_variability != "constant":
            if interval is None:
                interval = self.binding.fmi3GetIntervalDecimal(vr, 1)[0][0]
            if shift is None:
                shift = self.binding.fmi3GetShiftDecimal(vr, 1)[0]
        if interval is None or interval <= 0:
            raise RobogenError.at(f"instance '{self.name}': periodic clock '{var.name}' has no positive interval", self.span)
        return Periodic(var, start, float(interval), float(shift or 0.0))

    def activate_due_clocks(self, t: float, close: float) -> None:
        """Set every input clock due by t (a tick within ``close`` of it counting: first instant at
        t) and move it past t."""
        limit = t + close
        due = [p for p in self.periodic if p.next_time() <= limit] + [a for a in self.aperiodic if a.next_time() <= limit]
        if due:
            self.set_clocks(sorted(c.var.value_reference for c in due))
            for c in due:
                c.ticked(t, close)

    def read_intervals(self, t: float, ticked: set[int]) -> None:
        """After an event iteration at t: the next tick of each countdown clock and of each changing
        clock that ticked, as the FMU announces it."""
        for a in self.aperiodic:
            vr = a.var.value_reference
            if a.var.interval_variability == "countdown" or vr in ticked:
                intervals, qualifiers = self.binding.fmi3GetIntervalDecimal(vr_array([vr]), 1)
                if qualifiers[0] == INTERVAL_CHANGED or (qualifiers[0] != INTERVAL_NOT_YET_KNOWN and a.next is None):
                    a.next = t + intervals[0]

    def next_tick(self) -> float:
        return min((c.next_time() for c in (*self.periodic, *self.aperiodic)), default=math.inf)

    # -- values and output clocks -----------------------------------------------------------
    def observe(self, variables: list[Variable]) -> None:
        """Read these non-clocked variables (one call per type) after every step and instant."""
        by_type: dict[str, list[int]] = {}
        for v in variables:
            if not v.is_clock and not v.is_clocked and v.value_reference not in by_type.get(v.type, []):
                if v.dimensions and v.type in ("String", "Binary"):
                    raise RobogenError.at(f"instance '{self.name}': '{v.name}' is an array of {v.type}s, which the master "
                                          "does not read", self.span)
                by_type.setdefault(v.type, []).append(v.value_reference)
        self.readers = [Reader(self.binding, t, vrs, [self.md.element_count(self.by_vr[vr]) for vr in vrs])
                        for t, vrs in sorted(by_type.items())]
        self.reader_of = {vr: (r, i) for r in self.readers for vr, i in r.index.items()}

    def watch_clocks(self, vrs: list[int]) -> None:
        self.out_clocks = sorted(set(vrs))
        self.out_clock_vrs = vr_array(self.out_clocks)
        self.out_clock_buffer = value_array("Clock", len(self.out_clocks))

    def read_outputs(self) -> None:
        for r in self.readers:
            r.read()

    def value(self, vr: int):
        r, i = self.reader_of[vr]
        return r.values[i]

    def read_clocks(self) -> list[int]:
        """Output clocks (of those watched) that read active now: not read again in an instant
        where nothing they depend on was set since (see the module docstring)."""
        n = len(self.out_clocks)
        if not n:
            return []
        fresh = self._fresh
        if all(vr in fresh for vr in self.out_clocks):
            return [vr for vr in self.out_clocks if fresh[vr]]
        buf = self.out_clock_buffer
        self.binding.fmi3GetClock(self.out_clock_vrs, n, buf)
        active = []
        for i, vr in enumerate(self.out_clocks):
            fresh[vr] = on = bool(buf[i])
            if on:
                active.append(vr)
        return active

    def _batch(self, kind: type, fmi_type: str, vrs: tuple[int, ...]):
        """The Reader, Writer or ClockSetter of these value references (made at first use)."""
        key = (kind, fmi_type, vrs)
        batch = self._batches.get(key)
        if batch is None:
            batch = self._batches[key] = (ClockSetter(self.binding, list(vrs)) if kind is ClockSetter
                                          else kind(self.binding, fmi_type, list(vrs)))
        return batch

    def clocked_values(self, variables: list[Variable]) -> list:
        """The values of clocked variables whose clock is active: outputs read already in this
        instant and unchanged since (see the module docstring) from memory, the others with one
        Get call per type."""
        fresh = self._fresh
        missing: dict[str, list[int]] = {}
        for v in variables:
            if v.value_reference not in fresh:
                missing.setdefault(v.type, []).append(v.value_reference)
        if not missing:
            return [fresh[v.value_reference] for v in variables]
        read = dict(fresh)
        for fmi_type, vrs in missing.items():
            reader = self._batch(Reader, fmi_type, tuple(vrs))
            reader.read()
            read.update(zip(vrs, reader.values))
        for v in variables:
            if v.causality == "output":
                fresh[v.value_reference] = read[v.value_reference]
        return [read[v.value_reference] for v in variables]

    def new_instant(self) -> None:
        """A new super-dense instant (or Event Mode): every output may have changed."""
        self._fresh.clear()

    def _inputs_changed(self, vrs) -> None:
        """Forget the outputs read in this instant that depend on any of ``vrs``."""
        if self._fresh:
            depends = self.depends
            for vr in [vr for vr in self._fresh if (d := depends.get(vr)) is None or not d.isdisjoint(vrs)]:
                del self._fresh[vr]

    def set_values(self, fmi_type: str, vrs: list[int], values: list) -> None:
        """One Set call of ``vrs`` (all of ``fmi_type``)."""
        self._batch(Writer, fmi_type, tuple(vrs)).write(values)
        self._inputs_changed(vrs)

    def set_clocks(self, vrs: list[int]) -> None:
        self._batch(ClockSetter, "Clock", tuple(vrs)).write()
        self.active.update(vrs)
        self._inputs_changed(vrs)
