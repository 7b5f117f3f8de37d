"""The controller FMU: plays a plan of grid move commands and records what comes back.

Package it with ``robogen package-py robogen.platforms.controller:PlanController -o
ur5e_controller.fmu --set plan=PATH``: the plan has no default, and the file travels in the FMU's
resources (a relative PATH is relative to the working directory of the command, as any path
given on a command line).

Each planned command raises the output clock ``moveDiscreteCommand`` with the clocked Int64
outputs ``moveDiscreteCommand.target_X/Y/Z`` at its exact time: ``fmi3UpdateDiscreteStates``
announces it as ``nextEventTime`` and the command is raised in the first Event Mode at or after
that time. A master that steps past it anyway is stopped by an early return at the command time
(when allowed; otherwise the command is raised late, at the end of the step, with a warning).
``--set early_return=false`` declares ``mightReturnEarlyFromDoStep="false"`` instead: for masters
that honour ``nextEventTime`` (robogen's does), which then need no early-return handling for this
FMU (robogen's master runs a system with at most one FMU that may return early wholly in C).
Two commands at the same time take two event instants (``discreteStatesNeedUpdate``).

The platform's events can be connected to the controller's triggered input clocks of the same
names; it counts them (``received_*`` outputs) and logs each with its time.
"""

from __future__ import annotations

from pathlib import Path
from typing import Iterator

from robogen.diagnostics import RobogenError, Span
from robogen.platforms.plan import Command, CommandPlan, load_plan
from robogen.pyfmu import Clock, FmiUsageError, Int64, Model, Setting, Step, Update
from robogen.fmu.fmi import same_time

RECEIVED = ("feasibleMoveDiscreteCommand", "nonfeasibleMoveDiscreteCommand", "moveCompleted", "robotStopped",
            "collision")


def _target(axis: str) -> Int64:
    return Int64(name=f"moveDiscreteCommand.target_{axis}", causality="output", clock="moveDiscreteCommand",
                 description=f"grid {axis} of the command")


def _received(event: str) -> Int64:
    return Int64(causality="output", depends_on=(event,), description=f"ticks of {event} received so far")


class PlanController(Model):
    model_identifier = "ur5e_controller"
    model_name = "PlanController"
    description = "plays a plan of movediscrete commands (grid targets at exact times)"
    might_return_early = True
    default_experiment = {"startTime": 0.0, "stopTime": 100.0, "stepSize": 0.5}

    plan = Setting(str, "the plan file (TOML), copied into the FMU")
    early_return = Setting(True, "declare mightReturnEarlyFromDoStep: stop a master that steps past a command at "
                                 "its time (false: for a master that honours nextEventTime)")

    def __init_subclass__(cls, **kwargs) -> None:
        super().__init_subclass__(**kwargs)
        cls.might_return_early = bool(cls.early_return)  # the packaged setting (Model.configured's subclass)

    moveDiscreteCommand = Clock(kind="triggered", causality="output", depends_on=(),
                                description="a planned move command (raised by time)")
    moveDiscreteCommand_target_X = _target("X")
    moveDiscreteCommand_target_Y = _target("Y")
    moveDiscreteCommand_target_Z = _target("Z")
    commands_sent = Int64(causality="output", depends_on=(), description="commands raised so far")

    feasibleMoveDiscreteCommand = Clock(description="the platform accepted a command")
    nonfeasibleMoveDiscreteCommand = Clock(description="the platform refused a command")
    moveCompleted = Clock(description="the platform reports the motion completed")
    robotStopped = Clock(description="the platform reports the arm stopped")
    collision = Clock(description="the platform reports a collision")
    received_feasibleMoveDiscreteCommand = _received("feasibleMoveDiscreteCommand")
    received_nonfeasibleMoveDiscreteCommand = _received("nonfeasibleMoveDiscreteCommand")
    received_moveCompleted = _received("moveCompleted")
    received_robotStopped = _received("robotStopped")
    received_collision = _received("collision")

    @classmethod
    def package_resources(cls) -> dict[str, bytes]:
        path = Path(cls.plan)
        if not path.is_file():
            where = "" if path.is_absolute() else f" (relative to {Path.cwd()})"
            raise RobogenError.at(f"plan file '{path}' not found{where}", Span.whole_file(str(path)))
        load_plan(path)  # reject a bad plan now, with located errors, not inside a simulation
        return {"plan.toml": path.read_bytes()}

    def setup(self) -> None:
        packaged = None if self.resource_path is None else self.resource_path / "plan.toml"
        if packaged is None or not packaged.is_file():
            raise FmiUsageError("the plan is missing from the FMU's resources (resources/plan.toml)")
        self._plan: CommandPlan = load_plan(packaged)
        self._upcoming: Iterator[Command] = iter(())
        self._next: Command | None = None
        self._emitted = False  # a command was raised in the current instant

    def exit_initialization_mode(self) -> None:
        self._upcoming = self._plan.events(until=self.stop_time)
        self._advance()
        while self._next is not None and self._next.time < self.time and not same_time(self._next.time, self.time):
            self._advance()  # planned before the start time

    def _advance(self) -> None:
        self._next = next(self._upcoming, None)

    def _due(self) -> bool:
        n = self._next
        return n is not None and (n.time < self.time or same_time(n.time, self.time))

    def react(self, clocks: frozenset[str]) -> None:
        for event in RECEIVED:
            if event in clocks:
                name = f"received_{event}"
                self.set(name, self.get(name) + 1)
                if self.logging():  # a sample's events come at every sample: no message formatted in vain
                    self.log(f"t={self.time:.9g}: received {event}")
        if self._due() and not self._emitted:
            command = self._next
            assert command is not None
            self.raise_clock("moveDiscreteCommand")
            self.moveDiscreteCommand_target_X, self.moveDiscreteCommand_target_Y, self.moveDiscreteCommand_target_Z = (
                command.target)
            self.commands_sent += 1
            self._emitted = True
            late = "" if same_time(command.time, self.time) else f" (planned at {command.time:.9g} s)"
            self.log(f"t={self.time:.9g}: moveDiscreteCommand{command.target}{late}",
                     "logStatusWarning" if late else "logEvents", 1 if late else 0)
            self._advance()

    def update_discrete_states(self) -> Update:
        self._emitted = False
        again = self._due()  # another command planned for this same time
        return Update(need_update=again, next_event_time=None if self._next is None else self._next.time)

    def do_step(self, t: float, h: float) -> Step | None:
        n = self._next
        end = t + h
        if n is None or (n.time > end and not same_time(n.time, end)):
            return None
        if same_time(n.time, end) or not self.early_return_allowed:
            return Step(end, event=True)
        return Step(max(n.time, t), event=True)
