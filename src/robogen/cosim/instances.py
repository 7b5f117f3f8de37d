"""One FMU instance as the master sees it: its binding, its clocks' timing, its value buffers.

A :class:`FmuInstance` holds the instance's binding: a :class:`~robogen.cosim.fmi3.Binding` in
this process, or anything with the same methods (a proxy to a worker process would do; a binding
whose :meth:`~robogen.cosim.fmi3.Binding.raw` gives no C functions keeps the master in its
general loop). Beside it: the schedule of its time-based input clocks (:mod:`robogen.cosim.clocks`),
the :class:`Reader` of each type of the outputs the master reads after a step (one cffi buffer and
one Get call per type), the output clocks it watches and the set of its clocks active in the
current super-dense instant.
"""

from __future__ import annotations

import math
from pathlib import Path

from robogen.cosim.clocks import APERIODIC, PERIODIC, Aperiodic, Periodic
from robogen.cosim.fmi3 import ACCESSOR, C_TYPES, Binding, FMI3Error, ffi, value_array, vr_array
from robogen.diagnostics import RobogenError, Span
from robogen.fmu.fmi import FATAL, INTERVAL_CHANGED, INTERVAL_NOT_YET_KNOWN, WARNING
from robogen.fmu.modeldesc import ModelDescription, Variable


class Reader:
    """One fmi3Get<Type> call that fills a buffer with several variables of one instance."""

    def __init__(self, binding: Binding, fmi_type: str, vrs: list[int]):
        self.binding, self.fmi_type, self.vrs = binding, fmi_type, vrs
        self.index = {vr: i for i, vr in enumerate(vrs)}
        self.count = len(vrs)
        self.c_vrs = vr_array(vrs)
        self.buffer = value_array(fmi_type, self.count)
        self.decodes = fmi_type == "String"  # the buffer holds C strings; values holds them decoded
        self.values = [""] * self.count if self.decodes else self.buffer
        self.function = "fmi3Get" + ACCESSOR[fmi_type]
        self.c_function = binding.raw(self.function)  # None while tracing

    def read(self) -> None:
        if self.c_function is None:
            self.binding.get(self.fmi_type, self.c_vrs, self.count, self.buffer)
        else:
            status = self.c_function(self.binding.handle, self.c_vrs, self.count, self.buffer, self.count)
            if status > WARNING:
                raise self.binding.error(self.function, status)
        if self.decodes:
            self.values[:] = [_decode(p) for p in self.buffer[0:self.count]]


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

    # -- life cycle -------------------------------------------------------------------------
    def instantiate(self, start: float) -> None:
        self.time = start
        res = self.folder / "resources"
        resources = str(res.resolve()) + "/" if res.is_dir() else None
        self.binding.fmi3InstantiateCoSimulation(self.md.instantiation_token, resources, False, False,
                                                 eventModeUsed=self.event_mode, earlyReturnAllowed=self.early)

    def set_start_values(self, values: dict[str, object]) -> None:
        """The system file's start values, one Set call per type (Initialization Mode)."""
        by_type: dict[str, tuple[list, list]] = {}
        for name, value in values.items():
            var = self.vars[name]
            vrs, vals = by_type.setdefault(var.type, ([], []))
            vrs.append(var.value_reference)
            vals.append(value)
        for fmi_type, (vrs, vals) in sorted(by_type.items()):
            self.set_values(fmi_type, vrs, vals)

    def shut_down(self) -> None:
        """fmi3Terminate if healthy, then free; never call an instance again after fmi3Fatal."""
        if self.failed_status == FATAL or not self.binding.instantiated:
            return
        if self.failed_status is None:
            try:
                self.binding.fmi3Terminate()
            except FMI3Error:
                pass
        self.binding.fmi3FreeInstance()

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

    def activate_due_clocks(self, t: float, limit: float) -> None:
        """Set every input clock due by ``limit`` (first instant at t) and move it past t."""
        due = [p for p in self.periodic if p.next_time() <= limit] + [a for a in self.aperiodic if a.next_time() <= limit]
        if due:
            self.set_clocks(sorted(c.var.value_reference for c in due))
            for c in due:
                c.ticked(t)

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
                by_type.setdefault(v.type, []).append(v.value_reference)
        self.readers = [Reader(self.binding, t, vrs) for t, vrs in sorted(by_type.items())]
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
        """Output clocks (of those watched) that read active now."""
        n = len(self.out_clocks)
        if not n:
            return []
        buf = self.out_clock_buffer
        self.binding.fmi3GetClock(self.out_clock_vrs, n, buf)
        return [vr for i, vr in enumerate(self.out_clocks) if buf[i]]

    def get_one(self, var: Variable):
        buf = value_array(var.type, 1)
        self.binding.get(var.type, vr_array([var.value_reference]), 1, buf)
        return _decode(buf[0]) if var.type == "String" else buf[0]

    def set_values(self, fmi_type: str, vrs: list[int], values: list) -> None:
        if fmi_type == "String":
            keep = [ffi.new("char[]", str(v).encode()) for v in values]
            buf = ffi.new("const char*[]", keep)
        else:
            buf = ffi.new(f"{C_TYPES[fmi_type]}[]", values)
        self.binding.set(fmi_type, vr_array(vrs), len(vrs), buf)

    def set_clocks(self, vrs: list[int]) -> None:
        self.binding.fmi3SetClock(vr_array(vrs), len(vrs), ffi.new("bool[]", [True] * len(vrs)))
        self.active.update(vrs)


def _decode(p) -> str:
    return ffi.string(p).decode("utf-8", "replace") if p != ffi.NULL else ""
