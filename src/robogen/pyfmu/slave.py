"""The FMI 3.0 Co-Simulation state machine of a Python-implemented FMU.

:class:`Slave` owns one :class:`robogen.pyfmu.model.Model` instance and answers the importer's
calls as the FMI 3.0 standard requires (its state machine of calling sequences): allowed calls per
state, clocked variables only while one of their clocks is active, output clocks deactivated by
``update_discrete_states``, a periodic clock only at its ticks and at most once per Event Mode,
Step Mode only once the event iteration is over, ``doStep`` only from ``lastSuccessfulTime``. A
rule violation raises :class:`FmiUsageError` (the embedding turns it into ``fmi3Error`` and a log
message, and the instance into Terminated: :meth:`Slave.failed`); an exception from the model
propagates with its traceback. The C runtime of generated FMUs enforces the same rules (the
tests run one set of misuse cases against both). The embedding (``_embedded.py``) converts C
arguments; this module is plain Python, so it is tested without compiling anything.
"""

from __future__ import annotations

import enum
import math
import operator
from pathlib import Path
from typing import Any, Callable, Iterable, NamedTuple, Sequence

from robogen.fmu.fmi import INTERVAL_UNCHANGED, PYTHON_FMU_LOG_CATEGORIES, same_time, time_resolution
from robogen.pyfmu.model import Clock, FmiUsageError, Model, Step, Update, Var

#: How many different Get calls (function and value references) a slave keeps checked.
MAX_GET_PLANS = 256


class State(enum.Enum):
    INSTANTIATED = "Instantiated"
    INITIALIZATION = "Initialization Mode"
    EVENT = "Event Mode"
    STEP = "Step Mode"
    TERMINATED = "Terminated"


class StepResult(NamedTuple):  # a named tuple: made at every fmi3DoStep, and cheap to make
    event_handling_needed: bool
    terminate: bool
    early_return: bool
    last_successful_time: float


class UpdateResult(NamedTuple):
    discrete_states_need_update: bool
    terminate: bool
    next_event_time_defined: bool
    next_event_time: float


Logger = Callable[[int, str, str], None]


class Slave:
    """One FMU instance: the FMI state machine around a model object."""

    def __init__(
        self,
        model_class: type[Model],
        *,
        instance_name: str = "",
        resource_path: Path | None = None,
        event_mode_used: bool = True,
        early_return_allowed: bool = False,
        logger: Logger | None = None,
    ) -> None:
        self.model_class = model_class
        self.instance_name = instance_name
        self.resource_path = resource_path
        self.event_mode_used = event_mode_used
        self.early_return_allowed = early_return_allowed
        self.logger = logger
        self._by_vr: dict[int, Var] = {v.vr: v for v in model_class.variables()}
        self._clocks = [v for v in model_class.variables() if isinstance(v, Clock)]
        self._clock_by_vr: dict[int, Clock] = {c.vr: c for c in self._clocks}
        #: a periodic clock's first tick after the start and its interval, in seconds
        self._ticks = {c.name: (model_class.clock_seconds(c.shift), model_class.clock_seconds(c.interval))
                       for c in self._clocks if c.periodic}
        #: the time resolution of its periodic clocks (robogen.fmu.fmi.time_resolution): caps the time tolerance
        self._resolution = time_resolution(x for pair in self._ticks.values() for x in pair if x)
        self._get_plans: dict[tuple, tuple[Callable[[Model], list[Any]], bool, list[Var]]] = {}
        self._plain_get = model_class.get is Model.get  # values read from the model's dict directly
        if self._clocks and not event_mode_used:
            raise FmiUsageError(f"{model_class.__name__} has clocks: it must be instantiated with eventModeUsed = true")
        self._new_model()

    def _new_model(self) -> None:
        self.model = self.model_class(instance_name=self.instance_name, resource_path=self.resource_path,
                                      logger=self.logger)
        self.model.early_return_allowed = self.early_return_allowed
        self.state = State.INSTANTIATED
        self._reset_event_bookkeeping()
        self._set_since_step = False
        self.model.setup()

    def _reset_event_bookkeeping(self) -> None:
        self._new_input_clocks: set[str] = set()   # activated since the last react()
        self._reacted = False                       # react() ran in this instant
        self._updated_in_event_mode = False         # an update closed an instant in this Event Mode
        self._update_pending = False                # the last update asked for another instant
        self._periodic_ticked: set[str] = set()     # periodic clocks activated in this Event Mode

    # -- helpers --------------------------------------------------------------------------------

    def _require(self, function: str, *states: State) -> None:
        if self.state not in states:
            allowed = " or ".join(s.value for s in states)
            raise FmiUsageError(f"{function} is not allowed in {self.state.value} (only in {allowed})")

    def _variable(self, function: str, vr: int, type_name: str) -> Var:
        var = self._by_vr.get(vr)
        if var is None:
            raise FmiUsageError(f"{function}: unknown value reference {vr}")
        if var.type_name != type_name:
            raise FmiUsageError(f"{function}: '{var.name}' (value reference {vr}) is a {var.type_name}")
        return var

    def _clock_is_active(self, var: Var) -> bool:
        return var.clock is not None and self.model.clock_active(var.clock)

    def _react_if_needed(self) -> None:
        """Let the model compute the instant's outputs once its inputs are complete."""
        if self.state is State.EVENT and (not self._reacted or self._new_input_clocks):
            clocks = frozenset(self._new_input_clocks)
            self._new_input_clocks.clear()
            self._reacted = True
            self.model.react(clocks)

    # -- life cycle -----------------------------------------------------------------------------

    def enter_initialization_mode(self, tolerance: float | None, start_time: float, stop_time: float | None) -> None:
        self._require("fmi3EnterInitializationMode", State.INSTANTIATED)
        if stop_time is not None and stop_time < start_time:
            raise FmiUsageError(f"stopTime {stop_time} is before startTime {start_time}")
        self.model.time = self.model.start_time = float(start_time)
        self.model.stop_time = stop_time
        self.state = State.INITIALIZATION
        self.model.enter_initialization_mode()

    def exit_initialization_mode(self) -> None:
        self._require("fmi3ExitInitializationMode", State.INITIALIZATION)
        self.model.exit_initialization_mode()
        self._reset_event_bookkeeping()
        self.state = State.EVENT if self.event_mode_used else State.STEP

    def enter_event_mode(self) -> None:
        self._require("fmi3EnterEventMode", State.STEP)
        if not self.event_mode_used:
            raise FmiUsageError("fmi3EnterEventMode: the instance was created with eventModeUsed = false")
        self._reset_event_bookkeeping()
        self.state = State.EVENT

    def enter_step_mode(self) -> None:
        self._require("fmi3EnterStepMode", State.EVENT)
        if not self._updated_in_event_mode:
            raise FmiUsageError("fmi3EnterStepMode: call fmi3UpdateDiscreteStates at least once per event instant")
        if self._update_pending:
            raise FmiUsageError("fmi3EnterStepMode: the event iteration is not finished: call fmi3UpdateDiscreteStates "
                                "until it returns discreteStatesNeedUpdate=false")
        if self.model.active_clocks:
            raise FmiUsageError(f"fmi3EnterStepMode: clock '{sorted(self.model.active_clocks)[0]}' is active: close "
                                "its instant with fmi3UpdateDiscreteStates first")
        self.state = State.STEP
        self._set_since_step = False

    def terminate(self) -> None:
        self._require("fmi3Terminate", State.EVENT, State.STEP)
        self.model.terminate()
        self.model.active_clocks.clear()
        self.state = State.TERMINATED

    def failed(self) -> None:
        """An fmi3Error went back to the importer: from here on FMI 3.0 allows only what
        Terminated allows (Get, fmi3Reset, fmi3FreeInstance)."""
        self.state = State.TERMINATED

    def reset(self) -> None:
        self.model.free()
        self._new_model()

    def free(self) -> None:
        self.model.free()

    # -- values ---------------------------------------------------------------------------------

    def get(self, function: str, type_name: str, vrs: Sequence[int]) -> list[Any]:
        state = self.state
        if state is State.INSTANTIATED:
            raise FmiUsageError(f"{function} is not allowed in {state.value}")
        if state is State.STEP and self._set_since_step:
            raise FmiUsageError(f"{function} after a Set in Step Mode needs an fmi3DoStep in between")
        plan = self._get_plans.get((function, *vrs))
        if plan is None:
            plan = self._get_plan(function, type_name, vrs)
        read, computed, clocked = plan
        model = self.model
        if computed:
            if state is State.EVENT:
                self._react_if_needed()  # outputs (and their clocks) of this instant
            if model.outputs_stale:
                model.update_outputs()
        for var in clocked:
            self._check_clocked_access(function, var)
        return read(model)

    def _get_plan(self, function: str, type_name: str, vrs: Sequence[int]) -> tuple[Callable[[Model], list[Any]],
                                                                                   bool, list[Var]]:
        """What a Get of these value references reads (checked once, kept for the next same
        call): a function of the model giving the values, whether any is computed (an output or
        local), the clocked ones. A model that keeps the default ``get`` is read straight from
        its values, in one C-level lookup of all the names."""
        variables = [self._variable(function, vr, type_name) for vr in vrs]
        names = [v.name for v in variables]
        plan = (_reader(names, self._plain_get), any(v.causality in ("output", "local") for v in variables),
                [v for v in variables if v.clock is not None])
        if len(self._get_plans) >= MAX_GET_PLANS:  # an importer that reads ever new combinations
            self._get_plans.clear()
        self._get_plans[(function, *vrs)] = plan
        return plan

    def set(self, function: str, type_name: str, vrs: Sequence[int], values: Sequence[Any]) -> None:
        if len(values) != len(vrs):
            raise FmiUsageError(f"{function}: {len(vrs)} value references but {len(values)} values")
        checked = []
        for vr, value in zip(vrs, values):
            var = self._variable(function, vr, type_name)
            self._check_settable(function, var)
            try:
                checked.append((var, var.coerce(value)))
            except (TypeError, OverflowError) as exc:
                raise FmiUsageError(f"{function}: {exc}") from None
        for var, value in checked:
            self.model.set(var.name, value)
        if self.state is State.STEP:
            self._set_since_step = True

    def _check_clocked_access(self, function: str, var: Var) -> None:
        if self.state is State.INITIALIZATION:
            return
        if self.state is State.EVENT and self._clock_is_active(var):
            return
        raise FmiUsageError(f"{function}: '{var.name}' is clocked by '{var.clock}', which is not active "
                            f"({self.state.value})")

    def _check_settable(self, function: str, var: Var) -> None:
        state, name = self.state, var.name
        if var.variability == "constant" or var.causality in ("output", "calculatedParameter", "local"):
            raise FmiUsageError(f"{function}: '{name}' ({var.causality}, {var.variability}) cannot be set")
        if var.clock is not None:
            if state is State.INITIALIZATION or (state is State.EVENT and self._clock_is_active(var)):
                return
            raise FmiUsageError(f"{function}: '{name}' is clocked by '{var.clock}', which is not active ({state.value})")
        if state is State.INSTANTIATED:
            ok = var.causality == "input" or var.initial in ("exact", "approx")
        elif state is State.INITIALIZATION:
            ok = var.causality == "input" or var.initial == "exact"
        elif state in (State.EVENT, State.STEP):
            ok = var.causality == "input" or (var.causality == "parameter" and var.variability == "tunable")
        else:
            ok = False
        if not ok:
            raise FmiUsageError(f"{function}: '{name}' ({var.causality}, {var.variability}) cannot be set "
                                f"in {state.value}")

    # -- clocks ---------------------------------------------------------------------------------

    def _clock(self, function: str, vr: int) -> Clock:
        clock = self._clock_by_vr.get(vr)
        if clock is None:
            self._variable(function, vr, "Clock")  # raises: unknown, or not a clock
        assert clock is not None
        return clock

    def set_clock(self, vrs: Sequence[int], values: Sequence[bool]) -> None:
        self._require("fmi3SetClock", State.EVENT)
        clocks = [self._clock("fmi3SetClock", vr) for vr in vrs]
        model = self.model
        active = model.active_clocks  # what model.clock_active reads
        for clock, value in zip(clocks, values):
            if clock.causality != "input":
                raise FmiUsageError(f"fmi3SetClock: '{clock.name}' is an {clock.causality} clock")
            if not value:
                raise FmiUsageError(f"fmi3SetClock: '{clock.name}' cannot be deactivated (canBeDeactivated=false)")
            if clock.periodic and clock.name not in active:
                self._check_tick(clock)
        for clock in clocks:
            name = clock.name
            if name not in active:
                active.add(name)
                self._new_input_clocks.add(name)
                if clock.periodic:
                    self._periodic_ticked.add(name)
                if model.logging():
                    model.log(f"t={model.time:.9g}: input clock {name} active")

    def _check_tick(self, clock: Clock) -> None:
        """A periodic clock ticks at t_k = start + shift + k * interval, once per Event Mode."""
        if clock.name in self._periodic_ticked:
            raise FmiUsageError(f"fmi3SetClock: periodic clock '{clock.name}' was already active in this Event Mode")
        shift, interval = self._ticks[clock.name]
        origin = self.model.start_time + shift
        k = max(0, round((self.model.time - origin) / interval))
        due = origin + k * interval
        if self.model.time != due and not same_time(self.model.time, due, self._resolution):
            raise FmiUsageError(f"fmi3SetClock: periodic clock '{clock.name}' is not due at t={self.model.time!r}: "
                                f"it ticks at {origin!r} + k * {interval!r}")

    def get_clock(self, vrs: Sequence[int]) -> list[bool]:
        self._require("fmi3GetClock", State.INITIALIZATION, State.EVENT)
        clocks = [self._clock("fmi3GetClock", vr) for vr in vrs]
        for clock in clocks:
            if clock.causality == "input":
                raise FmiUsageError(f"fmi3GetClock: '{clock.name}' is an input clock")
        if self.state is State.INITIALIZATION:
            return [False] * len(clocks)
        self._react_if_needed()
        active = self.model.active_clocks  # what model.clock_active reads
        return [c.name in active for c in clocks]

    def get_interval_decimal(self, vrs: Sequence[int]) -> tuple[list[float], list[int]]:
        self._require("fmi3GetIntervalDecimal", State.INITIALIZATION, State.EVENT)
        intervals, qualifiers = [], []
        for vr in vrs:
            clock = self._clock("fmi3GetIntervalDecimal", vr)
            if not clock.periodic:
                raise FmiUsageError(f"fmi3GetIntervalDecimal: '{clock.name}' is a {clock.kind} clock")
            intervals.append(self.model_class.clock_seconds(clock.interval))  # type: ignore[arg-type]
            qualifiers.append(INTERVAL_UNCHANGED)
        return intervals, qualifiers

    def get_shift_decimal(self, vrs: Sequence[int]) -> list[float]:
        self._require("fmi3GetShiftDecimal", State.INITIALIZATION)
        shifts = []
        for vr in vrs:
            clock = self._clock("fmi3GetShiftDecimal", vr)
            if not clock.periodic:
                raise FmiUsageError(f"fmi3GetShiftDecimal: '{clock.name}' is a {clock.kind} clock")
            shifts.append(self.model_class.clock_seconds(clock.shift))
        return shifts

    # -- event instants and steps ---------------------------------------------------------------

    def update_discrete_states(self) -> UpdateResult:
        self._require("fmi3UpdateDiscreteStates", State.EVENT)
        self._react_if_needed()
        update = self.model.update_discrete_states() or Update()
        if not isinstance(update, Update):
            raise TypeError(f"{type(self.model).__name__}.update_discrete_states must return Update or None")
        self.model.active_clocks.clear()
        self._new_input_clocks.clear()
        self._reacted = False
        self._updated_in_event_mode = True
        self._update_pending = update.need_update
        next_time = update.next_event_time
        defined = next_time is not None and math.isfinite(next_time)
        return UpdateResult(update.need_update, update.terminate, defined, float(next_time) if defined else 0.0)

    def do_step(self, t: float, h: float) -> StepResult:
        self._require("fmi3DoStep", State.STEP)
        model = self.model
        if not (t == model.time and math.isfinite(t)) and not same_time(t, model.time, self._resolution):
            raise FmiUsageError(f"fmi3DoStep: currentCommunicationPoint {t!r} is not the FMU's time {model.time!r}")
        if not h > 0:
            raise FmiUsageError(f"fmi3DoStep: communicationStepSize must be > 0, got {h!r}")
        target = t + h
        if model.stop_time is not None and target > model.stop_time and not same_time(target, model.stop_time, self._resolution):
            raise FmiUsageError(f"fmi3DoStep: t + h = {target!r} is past stopTime {model.stop_time!r}")
        model.time = t  # snap to the FMU's own representation of t
        result = model.do_step(t, h) or Step(target)
        if not isinstance(result, Step):
            raise TypeError(f"{type(model).__name__}.do_step must return Step or None")
        reached = result.time
        if reached > target and not same_time(reached, target, self._resolution):
            raise RuntimeError(f"{type(model).__name__}.do_step went past t + h ({reached!r} > {target!r})")
        early = reached < target and not same_time(reached, target, self._resolution)
        if early and not self.early_return_allowed:
            raise RuntimeError(f"{type(model).__name__}.do_step returned early although earlyReturnAllowed is false")
        model.time = reached if early else target
        self._set_since_step = False
        event = bool(result.event)
        if event and not self.event_mode_used:
            self._internal_event_iteration()
            event = False
        return StepResult(event, bool(result.terminate), early, model.time)

    def _internal_event_iteration(self) -> None:
        """Without Event Mode the FMU handles its own events inside fmi3DoStep (no clocks then)."""
        for _ in range(1000):
            self.model.react(frozenset())
            update = self.model.update_discrete_states() or Update()
            if not update.need_update:
                return
        raise RuntimeError("event iteration did not converge in 1000 instants")

    # -- logging --------------------------------------------------------------------------------

    def log(self, status: int, category: str, message: str) -> None:
        if self.logger is not None:
            self.logger(status, category, message)


def _reader(names: list[str], plain: bool) -> Callable[[Model], list[Any]]:
    """The values of ``names`` of a model: through its own ``get``, or (``plain``: it keeps the
    default) from its values dict."""
    if not plain:
        return lambda model: [model.get(name) for name in names]
    if len(names) == 1:
        name = names[0]
        return lambda model: [model.variable_values[name]]
    several = operator.itemgetter(*names)
    return lambda model: list(several(model.variable_values))


def log_categories(requested: Iterable[str]) -> set[str]:
    """Check SetDebugLogging categories (an empty list means all of them)."""
    requested = list(requested)
    if not requested:
        return set(PYTHON_FMU_LOG_CATEGORIES)
    unknown = [c for c in requested if c not in PYTHON_FMU_LOG_CATEGORIES]
    if unknown:
        raise FmiUsageError(f"fmi3SetDebugLogging: unknown log category '{unknown[0]}' "
                            f"(known: {', '.join(PYTHON_FMU_LOG_CATEGORIES)})")
    return set(requested)
