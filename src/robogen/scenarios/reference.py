"""``--reference`` and ``--compare``: a scenario run by the reference interpreter, beside the FMU.

:class:`InterpreterBinding` gives the master an instance of the model whose calls the reference
interpreter (:mod:`robogen.ir.interp`, the executable statement of the semantics) answers instead
of the generated C: the same model description (the FMU's own), the same value references, the
same instants. ``robogen test --reference`` runs every scenario on it; ``--compare`` runs each
scenario on both and reports the first row where the results differ (:func:`first_difference`).

An instant is computed at its first read (a Get or GetClock) or at ``fmi3UpdateDiscreteStates``,
as the generated runtime does: the input clocks set before it (with their clocked values) are
latched, the periodic clock (``cycle`` or ``tock``) makes it a periodic instant. A time-free
RoboChart FMU (``--time skip``) has no tock clock: the binding counts the tocks by time as the
generated C does (a tock due at the instant's time makes it periodic, those a step passes are idle)
and announces the interpreter's look-ahead (:meth:`Interpreter.idle_tocks`) as nextEventTime.
"""

from __future__ import annotations

import math
from fractions import Fraction
from typing import Sequence

from robogen.cosim.fmi3 import FUNCTION_CODE, UNLISTED, CallNotes, DiscreteStates, FMI3Error, StepResult
from robogen.fmu.fmi import ERROR, same_time
from robogen.fmu.modeldesc import ModelDescription
from robogen.ir import model as ir
from robogen.ir.interp import Instant, Interpreter, RuntimeFault


class InterpreterBinding:
    """The binding of a model instance run by the reference interpreter (see the module docstring)."""

    def __init__(self, fmu: ir.Fmu, md: ModelDescription, name: str, notes: CallNotes | None = None):
        self.fmu, self.md, self.name = fmu, md, name
        self.notes = notes if notes is not None else CallNotes()
        self.note_base = self.notes.base(name)
        self.handle = None
        self.by_vr = md.by_vr()
        self.periodic = {v.value_reference for v in md.variables if v.is_clock and v.causality == "input" and v.interval_decimal}
        self.states = {v.value_reference: k for k, v in enumerate(x for x in md.variables if x.name.endswith(".state")
                                                                  and x.type == "Enumeration" and x.causality == "output")}
        self.parameters: dict[str, object] = {}
        self.interp: Interpreter | None = None
        self.ticking: dict[str, dict[str, object]] = {}  # input clocks set in this instant -> clocked values
        self.tick_periodic = False
        self.shown: Instant | None = None
        self._instantiated = False
        self.event_mode = False  # reads compute the instant only in Event Mode,
        self.open = False  # and only while an instant is open (not after an update that needs no other)
        self.last_message = ""
        self.start = self.time = 0.0  # a time-free FMU's tocks: at start + k * unit
        self.next_tock: int | None = 0  # the first tock at which anything can happen (None: none before an event)

    # -- what the master asks of a binding -------------------------------------------------------
    @property
    def instantiated(self) -> bool:
        return self._instantiated

    def raw(self, function: str):
        return None

    def note_code(self, function: str) -> int:
        return self.note_base | FUNCTION_CODE.get(function, UNLISTED)

    def error(self, function: str, status: int) -> FMI3Error:
        return FMI3Error(function, status, self.name, self.last_message)

    def _fault(self, function: str, exc: RuntimeFault) -> FMI3Error:
        self.last_message = f"the reference interpreter: {exc}"
        return FMI3Error(function, ERROR, self.name, self.last_message)

    # -- life cycle ------------------------------------------------------------------------------
    def fmi3InstantiateCoSimulation(self, *args, **kwargs) -> None:
        self._instantiated = True

    def fmi3FreeInstance(self) -> None:
        self._instantiated = False

    def fmi3EnterInitializationMode(self, tolerance, startTime: float, stopTime: float | None) -> int:
        self.start = self.time = startTime
        return 0

    def fmi3ExitInitializationMode(self) -> int:
        self.interp = Interpreter(self.fmu, self.parameters or None)
        try:
            self.interp.exit_initialization()
        except RuntimeFault as exc:
            raise self._fault("fmi3ExitInitializationMode", exc) from None
        self.event_mode = self.open = True
        return 0

    def fmi3EnterEventMode(self) -> int:
        self.event_mode = self.open = True
        return 0

    def fmi3EnterStepMode(self) -> int:
        self.event_mode = self.open = False
        self.shown = None
        return 0

    def fmi3Terminate(self) -> int:
        return 0

    def fmi3Reset(self) -> int:
        self.interp, self.shown, self.ticking = None, None, {}
        self.start = self.time = 0.0
        self.next_tock = 0
        return 0

    # -- instants --------------------------------------------------------------------------------
    def _evaluate(self, function: str) -> Instant:
        """The current instant's outputs (computed at the first read in Event Mode); outside
        Event Mode, no output clock is active and the machines rest where they are."""
        if self.interp is None:
            return Instant({}, tuple(0 for _ in self.fmu.machines))
        if not self.event_mode or (self.shown is None and not self.open):
            return Instant({}, tuple(ms.node for ms in self.interp.machines))
        if self.shown is None:
            try:
                for clock, payload in self.ticking.items():
                    self.interp.latch(clock, payload)
                self.shown = self.interp.evaluate(self.tick_periodic or self._tock_now())
            except RuntimeFault as exc:
                raise self._fault(function, exc) from None
        return self.shown

    def fmi3UpdateDiscreteStates(self) -> DiscreteStates:
        self._evaluate("fmi3UpdateDiscreteStates")
        try:
            need = self.interp.update()
        except RuntimeFault as exc:
            raise self._fault("fmi3UpdateDiscreteStates", exc) from None
        self.shown, self.ticking, self.tick_periodic, self.open = None, {}, False, need
        if need or not self.fmu.time_free:
            return DiscreteStates(need, False, False, 0.0)
        wake = self.interp.idle_tocks()
        self.next_tock = None if wake is None else self.interp.cycles - 1 + wake
        return DiscreteStates(False, False, wake is not None, self._tock_time(self.next_tock or 0))

    def fmi3DoStep(self, currentCommunicationPoint: float, communicationStepSize: float,
                   noSetFMUStatePriorToCurrentPoint: bool = True) -> StepResult:
        end = currentCommunicationPoint + communicationStepSize
        if self.fmu.time_free and self.interp is not None:
            due = self._tocks_by(end)
            if same_time(self._tock_time(due - 1), end):
                due -= 1  # a tock at the step's end is Event Mode's if one comes there (the generated C's rule)
            if self.next_tock is not None:
                due = min(due, self.next_tock)
            if due > self.interp.cycles:
                self.interp.pass_idle(due - self.interp.cycles)
            if self.next_tock is not None and self._tock_time(self.next_tock) < end and \
                    not same_time(self._tock_time(self.next_tock), end):
                self.next_tock = None  # passed (the generated C warns): taken late, at the next Event Mode
        self.time = end
        return StepResult(False, False, False, end)

    # -- a time-free FMU's tocks (robogen_machine.h's rg_tocks_by, rg_tock_now) -------------------
    def _tock_time(self, k: int) -> float:
        return self.start + k * float(self.fmu.clock_interval)

    def _tocks_by(self, t: float) -> int:
        """The tocks due by time t: those at or before it, under the time tolerance."""
        k = max(0, math.floor((t - self.start) / float(self.fmu.clock_interval)))
        while k > 0 and not (self._tock_time(k) <= t or same_time(self._tock_time(k), t)):
            k -= 1
        while self._tock_time(k + 1) <= t or same_time(self._tock_time(k + 1), t):
            k += 1
        return k + 1

    def _tock_now(self) -> bool:
        """Is a tock of a time-free FMU due at this instant's time (the idle ones before it counted)?"""
        if not self.fmu.time_free or self.interp is None:
            return False
        due = self._tocks_by(self.time)
        if due > self.interp.cycles + 1:
            self.interp.pass_idle(due - 1 - self.interp.cycles)
        return due > self.interp.cycles

    def fmi3SetClock(self, vrs, n: int, values) -> int:
        self.open = True
        for i in range(n):
            if values[i]:
                vr = vrs[i]
                if vr in self.periodic:
                    self.tick_periodic = True
                else:
                    self.ticking.setdefault(self.by_vr[vr].name, {})
        return 0

    def fmi3GetClock(self, vrs, n: int, values) -> int:
        shown = self._evaluate("fmi3GetClock")
        for i in range(n):
            values[i] = self.by_vr[vrs[i]].name in shown.outputs
        return 0

    def fmi3GetIntervalDecimal(self, vrs, n: int):
        raise FMI3Error("fmi3GetIntervalDecimal", ERROR, self.name, "the generated FMUs' clocks are constant or triggered")

    def fmi3GetFMUState(self):
        raise FMI3Error("fmi3GetFMUState", ERROR, self.name, "the reference interpreter keeps no FMU state")

    # -- values ----------------------------------------------------------------------------------
    def set_values(self, fmi_type: str, vrs: Sequence[int], values: Sequence) -> None:
        for vr, value in zip(vrs, values):
            self._set(vr, value)

    def set_array(self, fmi_type: str, vr: int, values: Sequence) -> None:
        self._set(vr, list(values))

    def _set(self, vr: int, value) -> None:
        var = self.by_vr[vr]
        if var.causality == "parameter":
            self.parameters[var.name] = value
        elif var.clocks:
            clock = self.by_vr[var.clocks[0]].name
            self.ticking.setdefault(clock, {})[var.name] = value
            self.open = True
        else:
            raise FMI3Error("fmi3Set", ERROR, self.name, f"'{var.name}' cannot be set")

    def get_values(self, fmi_type: str, vrs: Sequence[int]) -> list:
        shown = self._evaluate(f"fmi3Get{fmi_type}")
        variables = None
        out = []
        for vr in vrs:
            var = self.by_vr[vr]
            if vr in self.states:
                value = shown.states[self.states[vr]]
            elif var.clocks:
                value = shown.outputs.get(self.by_vr[var.clocks[0]].name, {}).get(var.name, 0)
            elif self.interp is None:
                value = self.parameters.get(var.name, 0)
            elif var.name in ("cycles", "dropped_events", "deadline_misses"):
                value = {"cycles": self.interp.cycles, "dropped_events": self.interp.dropped,
                         "deadline_misses": self.interp.deadline_misses}[var.name]
            elif var.causality == "parameter" and var.name in self.parameters:
                value = self.parameters[var.name]
            else:
                variables = variables if variables is not None else self.interp.variables()
                value = variables.get(var.name, 0)
            out.append(_fmi(value, fmi_type))
        return out


def _fmi(value, fmi_type: str):
    """An interpreter value as the FMU shows it (exact reals as floats)."""
    if isinstance(value, Fraction):
        return float(value)
    if fmi_type in ("Float64", "Float32") and isinstance(value, int) and not isinstance(value, bool):
        return float(value)
    if fmi_type == "Boolean":
        return bool(value)
    return value


def first_difference(columns: list[str], rows: list[list], other: list[list]) -> str | None:
    """Where two runs' rows first differ (time, super-dense index, column, the two values), or None."""
    for a, b in zip(rows, other):
        for name, x, y in zip(columns, a, b):
            if not _same(x, y):
                return f"t={a[0]!r} (super-dense {a[1]}): {name} is {x!r} in the FMU, {y!r} in the reference interpreter"
    if len(rows) != len(other):
        longer, n = ("FMU", len(other)) if len(rows) > len(other) else ("reference interpreter", len(rows))
        at = (rows if len(rows) > len(other) else other)[n]
        return f"t={at[0]!r} (super-dense {at[1]}): the {longer}'s run has more rows ({len(rows)} against {len(other)})"
    return None


def _same(x, y) -> bool:
    if isinstance(x, float) and isinstance(y, float):
        return x == y or (math.isnan(x) and math.isnan(y)) or math.isclose(x, y, rel_tol=1e-12, abs_tol=1e-300)
    return x == y
