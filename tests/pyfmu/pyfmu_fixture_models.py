"""Small Python FMUs for the tests of robogen.pyfmu (not part of robogen: packaging copies this
module into each FMU's resources/python, which the C-host tests rely on)."""

from __future__ import annotations

from robogen.pyfmu import Boolean, Clock, Float64, Int32, Int64, Model, Setting, Step, String, Update


class Counter(Model):
    """Counts ticks of a periodic clock and bumps of a triggered one; ``alarm`` is an output clock
    raised at ``alarm_time`` through an early return; ``fail_after`` makes do_step raise."""

    model_identifier = "counter"
    might_return_early = True

    period = Setting(0.5, "interval of 'tick' [s]")

    tick = Clock(kind="constant", causality="input", interval="period")
    bump = Clock(kind="triggered", causality="input")
    amount = Int64(1, name="bump.amount", causality="input", clock="bump")
    ticked = Clock(kind="triggered", causality="output", depends_on=("tick",))
    count = Int64(name="ticked.count", causality="output", clock="ticked")
    alarm = Clock(kind="triggered", causality="output", depends_on=())
    total = Int64(causality="output", depends_on=("bump", "bump.amount", "tick"))
    position = Float64(causality="output", depends_on=())
    speed = Float64(1.0, causality="parameter", variability="tunable", unit="m/s")
    alarm_time = Float64(-1.0, causality="parameter", unit="s")
    fail_after = Float64(1e300, causality="parameter", variability="tunable", unit="s")
    label = String("counter", causality="parameter", variability="tunable")
    flag = Boolean(False, causality="input")
    small = Int32(7, causality="input")

    def setup(self) -> None:
        self._alarm_pending = False
        self._alarm_done = False

    def react(self, clocks: frozenset[str]) -> None:
        if "bump" in clocks:
            self.total += self.amount
        if "tick" in clocks:
            self.total += 1
            self.count = self.total
            self.raise_clock("ticked")
        if self._alarm_pending:
            self.raise_clock("alarm")
            self._alarm_pending = False

    def do_step(self, t: float, h: float) -> Step | None:
        if t + h > self.fail_after:
            raise RuntimeError(f"deliberate failure after t = {self.fail_after}")
        end = t + h
        if not self._alarm_done and 0.0 <= self.alarm_time and t < self.alarm_time <= end:
            self._alarm_done = self._alarm_pending = True
            stop = self.alarm_time if self.early_return_allowed else end
            self.position = self.speed * stop
            return Step(stop, event=True)
        self.position = self.speed * end
        return None


class TwoInstants(Model):
    """Asks for a second event instant once (discreteStatesNeedUpdate) and announces a time event."""

    model_identifier = "two_instants"
    instants = Int64(causality="output", depends_on=())

    def update_discrete_states(self) -> Update:
        self.instants += 1
        return Update(need_update=self.instants % 2 == 1, next_event_time=self.time + 1.25)


class BrokenSetup(Model):
    """Fails while being instantiated."""

    model_identifier = "broken_setup"
    x = Float64(causality="output")

    def setup(self) -> None:
        raise ValueError("setup cannot find its calibration table")


class UsesNumpy(Model):
    """Imports an extension module (numpy) at run time: the C-host trap of RTLD_LOCAL."""

    model_identifier = "uses_numpy"
    norm = Float64(causality="output", depends_on=())

    def do_step(self, t: float, h: float) -> Step | None:
        import numpy

        self.norm = float(numpy.linalg.norm(numpy.array([3.0, 4.0])) * (t + h))
        return None
