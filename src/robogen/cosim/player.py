"""The instance that plays a scenario: no FMU file, a binding in Python with the FMU's interface.

``[instances.d] scenario = "s.toml"`` adds to the system an instance ``d_scenario`` whose
binding is a :class:`ScenarioBinding`. Its model description (:func:`player_description`)
mirrors what the scenario drives on ``d``: a triggered output clock for each input event it
raises, a clocked output for each scalar clocked input those events set, an output for each input
value it changes, and a parameter for each of the scenario's ``[parameters]`` (so that a
campaign varies them as start values). :func:`player_links` connects each of them to ``d``, so
the master routes the scenario's ticks like any other clock tick: in dependency order (the
scenario before its instance), in the instant of their time, recorded and logged.

Time events: the binding announces the next occurrence (or input change) as ``nextEventTime``
in ``fmi3UpdateDiscreteStates``; the master enters Event Mode there and reads the output clocks
active. Input values change at communication points (a ramp is sampled at each).

Sets and sequences travel as FMI arrays (``e.value.elements``), which the master does not carry
between instances: the binding sets them on ``d`` itself (:meth:`ScenarioBinding.attach`), in the
instant of the occurrence, when the master reads the event's ``e.value.size``, after it has set
the clock on ``d`` and before ``d`` computes the instant.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Sequence

from robogen.cosim.fmi3 import FUNCTION_CODE, UNLISTED, CallNotes, DiscreteStates, FMI3Error, StepResult
from robogen.cosim.scenario import Scenario, Timeline, timeline
from robogen.cosim.system import Link
from robogen.diagnostics import RobogenError, Span
from robogen.fmu.fmi import ERROR, same_time, tolerance
from robogen.fmu.modeldesc import CoSimulation, ModelDescription, Unknown, Variable

_PARAMETER_TYPE = {bool: "Boolean", int: "Int64", float: "Float64", str: "String"}


def player_description(name: str, scenario: Scenario, plan: Timeline, target: ModelDescription) -> ModelDescription:
    """The player's model description: what ``plan`` drives on the target, mirrored as outputs."""
    variables: list[Variable] = []

    def add(var: Variable) -> Variable:
        made = replace(var, value_reference=len(variables), causality="output", initial=None, start=(), line=0,
                       attributes={}, description=f"from {scenario.path}")
        variables.append(made)
        return made

    for clock in plan.clocks():
        mine = add(replace(clock, interval_variability="triggered", variability="discrete"))
        for var in plan.scalars(clock):
            add(replace(var, clocks=(mine.value_reference,), variability="discrete"))
    for var, _segments in plan.courses.values():
        add(replace(var, variability="continuous" if var.type.startswith("Float") else "discrete"))
    taken = {v.name for v in variables}
    for pname, value in scenario.parameters.items():
        if pname in taken:
            raise RobogenError.at(f"parameter '{pname}' has the name of an event or input of the FMU; rename it",
                                  scenario.span("parameters", pname))
        variables.append(Variable(pname, len(variables), _PARAMETER_TYPE[type(value)], causality="parameter",
                                  variability="fixed", initial="exact", start=(_text(value),),
                                  description="a parameter of the scenario"))
    unknowns = tuple(Unknown("Output", v.value_reference, ()) for v in variables if v.causality == "output")
    return ModelDescription(f"scenario {scenario.path}", "", CoSimulation(name, has_event_mode=True),
                            tuple(variables), unknowns, type_definitions=target.type_definitions, path=str(scenario.path))


def _text(value) -> str:
    return ("true" if value else "false") if isinstance(value, bool) else str(value)


def player_links(player: str, md: ModelDescription, target: str, target_md: ModelDescription, span: Span) -> list[Link]:
    """A connection from each output of the player to the target's variable of the same name."""
    names = target_md.by_name()
    return [Link(player, v, target, names[v.name], span) for v in md.variables if v.causality == "output"]


class ScenarioBinding:
    """The binding of a player instance: the methods of :class:`robogen.cosim.fmi3.Binding` the
    master calls, answered from the scenario's timeline (see the module docstring)."""

    def __init__(self, name: str, scenario: Scenario, target_md: ModelDescription, md: ModelDescription,
                 notes: CallNotes | None = None):
        self.name, self.scenario, self.target_md, self.md = name, scenario, target_md, md
        self.notes = notes if notes is not None else CallNotes()
        self.note_base = self.notes.base(name)
        self.handle = None
        self.target = None  # the driven instance's binding: sets and sequences are set on it directly
        self.by_vr = md.by_vr()
        self.clock_vr = {v.name: v.value_reference for v in md.variables if v.is_clock}
        self.parameters = {v.name: _parse(v) for v in md.variables if v.causality == "parameter"}
        self.plan: Timeline | None = None
        self.time = 0.0
        self.start = 0.0
        self.stop = math.inf
        self.next = 0  # index of the next occurrence not yet raised
        self.active: dict[int, dict[str, object]] = {}  # clock vr -> its clocked values, this instant
        self.pending_arrays: list = []
        self._instantiated = False

    # -- what the master asks of a binding -------------------------------------------------------
    @property
    def instantiated(self) -> bool:
        return self._instantiated

    def raw(self, function: str):
        return None  # Python: the engine calls it through an adapter (robogen.cosim.adapters)

    def note_code(self, function: str) -> int:
        return self.note_base | FUNCTION_CODE.get(function, UNLISTED)

    def error(self, function: str, status: int) -> FMI3Error:
        return FMI3Error(function, status, self.name, "")

    def attach(self, target) -> None:
        """The binding of the instance the scenario drives (for set and sequence payloads)."""
        self.target = target

    # -- life cycle ------------------------------------------------------------------------------
    def fmi3InstantiateCoSimulation(self, instantiationToken, resourcePath, visible=False, loggingOn=False,
                                    eventModeUsed=False, earlyReturnAllowed=False) -> None:
        self._instantiated = True

    def fmi3FreeInstance(self) -> None:
        self._instantiated = False

    def fmi3EnterInitializationMode(self, tolerance_, startTime: float, stopTime: float | None) -> int:
        self.start = self.time = startTime
        self.stop = math.inf if stopTime is None else stopTime
        return 0

    def fmi3ExitInitializationMode(self) -> int:
        """The timeline with the parameters' values set in Initialization Mode; then Event Mode at
        the start time, with the occurrences due there."""
        try:
            self.plan = timeline(self.scenario, self.target_md, self.start, self.stop, self.parameters)
        except RobogenError as exc:
            d = exc.diagnostics[0]
            raise FMI3Error("fmi3ExitInitializationMode", ERROR, self.name, f"{d.span}: {d.message}") from None
        self._raise_due()
        return 0

    def fmi3EnterEventMode(self) -> int:
        self._raise_due()
        return 0

    def fmi3EnterStepMode(self) -> int:
        return 0

    def fmi3Terminate(self) -> int:
        return 0

    def fmi3Reset(self) -> int:
        self.plan, self.next, self.active = None, 0, {}
        return 0

    # -- time ------------------------------------------------------------------------------------
    def _raise_due(self) -> None:
        """Activate the clocks of the occurrences due by now (never one twice)."""
        occurrences = self.plan.occurrences if self.plan is not None else []
        limit = self.time + tolerance(self.time)
        while self.next < len(occurrences) and occurrences[self.next].time <= limit:
            o = occurrences[self.next]
            self.active[self.clock_vr[o.clock.name]] = {v.name: x for v, x in o.scalars}
            self.pending_arrays += o.arrays
            self.next += 1

    def _next_time(self) -> float | None:
        times = []
        if self.plan is not None and self.next < len(self.plan.occurrences):
            times.append(self.plan.occurrences[self.next].time)
        limit = self.time + tolerance(self.time)
        for _var, segments in (self.plan.courses.values() if self.plan is not None else ()):
            times += [s.start for s in segments if s.start > limit]
        return min(times, default=None)

    def fmi3UpdateDiscreteStates(self) -> DiscreteStates:
        self.active.clear()
        self.pending_arrays.clear()
        when = self._next_time()
        return DiscreteStates(False, False, when is not None, when if when is not None else 0.0)

    def fmi3DoStep(self, currentCommunicationPoint: float, communicationStepSize: float,
                   noSetFMUStatePriorToCurrentPoint: bool = True) -> StepResult:
        self.time = currentCommunicationPoint + communicationStepSize
        return StepResult(False, False, False, self.time)

    # -- values ----------------------------------------------------------------------------------
    def value_at(self, name: str, t: float):
        var, segments = self.plan.courses[name]
        value = None
        for segment in segments:
            if segment.start <= t or same_time(segment.start, t):
                value = segment.value(t)
        if value is None:  # before its first change: the FMU's own start value
            return _parse(var) if var.start else (0.0 if var.type.startswith("Float") else 0)
        return value

    def get_values(self, fmi_type: str, vrs: Sequence[int]) -> list:
        out = []
        for vr in vrs:
            var = self.by_vr[vr]
            if var.causality == "parameter":
                out.append(self.parameters[var.name])
            elif var.clocks:
                values = self.active.get(var.clocks[0])
                if values is None:
                    raise FMI3Error(f"fmi3Get{fmi_type}", ERROR, self.name, f"'{var.name}' read while its clock is inactive")
                self._push_arrays(var.clocks[0])
                out.append(values[var.name])
            else:
                out.append(self.value_at(var.name, self.time))
        return out

    def _push_arrays(self, clock_vr: int) -> None:
        """Set the array payloads of the active occurrence of ``clock_vr`` on the target."""
        name = self.by_vr[clock_vr].name
        mine = [(v, x) for v, x in self.pending_arrays if self.target_md.by_vr()[v.clocks[0]].name == name]
        for var, items in mine:
            self.target.set_array(var.type, var.value_reference, items)
        self.pending_arrays = [p for p in self.pending_arrays if p not in mine]

    def set_values(self, fmi_type: str, vrs: Sequence[int], values: Sequence) -> None:
        for vr, value in zip(vrs, values):
            var = self.by_vr[vr]
            if var.causality != "parameter":
                raise FMI3Error(f"fmi3Set{fmi_type}", ERROR, self.name, f"'{var.name}' is an output")
            self.parameters[var.name] = value

    def fmi3GetClock(self, vrs, n: int, values) -> int:
        for i in range(n):
            values[i] = vrs[i] in self.active
        return 0

    def fmi3SetClock(self, vrs, n: int, values) -> int:
        raise FMI3Error("fmi3SetClock", ERROR, self.name, "a scenario has no input clocks")

    def fmi3GetIntervalDecimal(self, vrs, n: int):
        raise FMI3Error("fmi3GetIntervalDecimal", ERROR, self.name, "a scenario has no time-based input clocks")

    def fmi3GetFMUState(self):
        raise FMI3Error("fmi3GetFMUState", ERROR, self.name, "a scenario has no FMU state")


def _parse(var: Variable):
    text = var.start[0] if var.start else ""
    if var.type == "Boolean":
        return text == "true"
    if var.type == "String":
        return text
    if var.type.startswith("Float"):
        return float(text or 0.0)
    return int(text or 0)


__all__ = ["ScenarioBinding", "player_description", "player_links"]
