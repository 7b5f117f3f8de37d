"""The UR5e platform-mapping FMU: the RoboSim platform's operations and events over PyBullet.

Package it with ``robogen package-py robogen.platforms.ur5e:UR5ePlatform -o ur5e_platform.fmu``
(``--set sample_period=SECONDS`` changes the interval of the constant clock ``sample``).

Operations arrive as triggered input clocks with clocked arguments (the d-model's output clocks
of the same names); several in one event instant apply in the order setvelocity, stop,
movejoint, movecartesian, movediscrete.

- ``movediscrete(target_X, target_Y, target_Z)``: the grid cell -> flange pose of the case study
  (§4, §6), inverse kinematics, then a joint-space move. Answered in the same event instant by
  ``feasibleMoveDiscreteCommand`` or ``nonfeasibleMoveDiscreteCommand``: feasible when the cell
  is on the table (X 0..15, Y 0..23, Z >= 0), the IK converges (1e-7 m, 1e-7 rad) and the
  solution does not collide. A repeated movediscrete with the same cell and no other operation
  in between (the d-model re-entering ArmMove) is the same command: one motion, the verdict
  given again.
- ``movejoint(target_q0..target_q5)``: a joint-space move (clamped to the joint limits).
- ``movecartesian(target_x, y, z, rx, ry, rz)``: a flange pose in the base frame, orientation
  as a rotation vector (UR's convention); unreachable poses are logged and ignored.
- ``stop()``: the motors hold the arm where it is (decelerating within the torque limits); when
  the current motion has already completed, it is held at that motion's target.
- ``setvelocity(target_v)``: the joint speed of the motors, at most ``joint_speed_limit``.

Events are the conditions of the case study (§7), level-sensitive: in every Event Mode where the
constant input clock ``sample`` ticks, each condition that holds raises its output clock:

- ``moveCompleted``: a motion was commanded and every |q_i - q_i,target| < 0.005 rad, the target
  being the joint solution of the last motion command (never true right after a new command);
- ``robotStopped``: every |qdot_i| < 0.1 rad/s and no commanded motion is still under way (a
  motion is under way from its command until it completes or a stop);
- ``collision``: the arm touches the mounting plane or itself (see scene.py).

While the arm moves, the conditions are also evaluated after every physics step; when one
becomes true the FMU returns early from fmi3DoStep at that step (if the importer allows early
return; else at the end of the step) with eventHandlingNeeded, and raises its clock in the
Event Mode that follows, so the exact time is recorded.

Physics: PyBullet in DIRECT mode, a fixed internal step ``physics_step`` (default 1/240 s). The
physics runs on its own grid start + k * physics_step: fmi3DoStep to t + h performs the steps
whose end lies in (t, t + h]. Where no condition can rise (no motion under way, the arm at rest),
the rest of the step's physics goes to PyBullet in one call (scene.step_stretch: the same physics
bit for bit, without PyBullet's cost per call at every physics step). Outputs (joint positions
and velocities, flange pose, step count) are read from the simulation when the importer asks for
them.
"""

from __future__ import annotations

import math
import operator
import shutil
import tempfile
from pathlib import Path

import numpy as np
import pybullet

from robogen.platforms.kinematics import (
    HOME, IK_SEED, JOINT_LIMIT, MAX_JOINT_SPEED, forward, grid_in_table, grid_pose, inverse, nearest_equivalent,
    rotation_from_vector, rotation_vector, rotation_vector_of_quaternion,
)
from robogen.platforms.scene import ArmScene, speed_ok, step_stretch
from robogen.platforms.urdf import ur5e_urdf
from robogen.pyfmu import Clock, Float64, FmiUsageError, Int64, Model, Setting, Step

COMPLETION_TOLERANCE = 0.005  # rad, every joint
STOPPED_SPEED = 0.1  # rad/s, every joint
EVENTS = ("moveCompleted", "robotStopped", "collision")
_STOPPED = EVENTS.index("robotStopped")
_Q, _DQ = tuple(f"q{i}" for i in range(6)), tuple(f"dq{i}" for i in range(6))
_NONE: frozenset[str] = frozenset()
_CLOSE, _SLOW = COMPLETION_TOLERANCE.__gt__, STOPPED_SPEED.__gt__  # x < tolerance (false for NaN)


def _within(q, target) -> bool:
    """Every |q_i - target_i| < COMPLETION_TOLERANCE (evaluated after every watched physics step)."""
    return all(map(_CLOSE, map(abs, map(operator.sub, q, target))))


def _joint_param(i: int) -> Float64:
    return Float64(HOME[i], causality="parameter", unit="rad", description=f"joint {i + 1} position at the start")


def _joint_output(i: int, kind: str) -> Float64:
    if kind == "q":
        return Float64(causality="output", unit="rad", depends_on=(), description=f"joint {i + 1} position")
    return Float64(causality="output", unit="rad/s", depends_on=(), description=f"joint {i + 1} velocity")


def _argument(clock: str, name: str, unit: str | None = None) -> Float64:
    return Float64(0.0, name=f"{clock}.{name}", causality="input", clock=clock, unit=unit)


def _grid_argument(name: str) -> Int64:
    return Int64(0, name=f"movediscrete.{name}", causality="input", clock="movediscrete",
                 description=f"grid {name[-1]} index")


def _event(description: str, *depends_on: str) -> Clock:
    return Clock(kind="triggered", causality="output", description=description, depends_on=depends_on)


_MOVEDISCRETE_INPUTS = ("movediscrete", "movediscrete.target_X", "movediscrete.target_Y", "movediscrete.target_Z")


class UR5ePlatform(Model):
    model_identifier = "ur5e_platform"
    model_name = "UR5ePlatform"
    description = "UR5e platform mapping: RoboSim MoveI operations and platform events over headless PyBullet"
    might_return_early = True
    default_experiment = {"startTime": 0.0, "stopTime": 100.0, "stepSize": 0.5}

    sample_period = Setting(0.5, "interval of the constant input clock 'sample' in seconds (the d-model's cycle)")

    # -- parameters ---------------------------------------------------------------------------
    physics_step = Float64(1.0 / 240.0, causality="parameter", unit="s", description="fixed physics step")
    joint_speed_limit = Float64(MAX_JOINT_SPEED, causality="parameter", unit="rad/s",
                                description="maximum joint speed (UR5e: pi rad/s)")
    initial_q0, initial_q1, initial_q2 = _joint_param(0), _joint_param(1), _joint_param(2)
    initial_q3, initial_q4, initial_q5 = _joint_param(3), _joint_param(4), _joint_param(5)

    # -- the sampling clock -------------------------------------------------------------------
    sample = Clock(kind="constant", causality="input", interval="sample_period",
                   description="periodic sampling of the level-sensitive events")

    # -- operations (MoveI) -------------------------------------------------------------------
    movediscrete = Clock(description="movediscrete(X, Y, Z): move the flange to a grid cell")
    movediscrete_target_X = _grid_argument("target_X")
    movediscrete_target_Y = _grid_argument("target_Y")
    movediscrete_target_Z = _grid_argument("target_Z")
    movejoint = Clock(description="movejoint(q0..q5): move to joint positions")
    movejoint_target_q0 = _argument("movejoint", "target_q0", "rad")
    movejoint_target_q1 = _argument("movejoint", "target_q1", "rad")
    movejoint_target_q2 = _argument("movejoint", "target_q2", "rad")
    movejoint_target_q3 = _argument("movejoint", "target_q3", "rad")
    movejoint_target_q4 = _argument("movejoint", "target_q4", "rad")
    movejoint_target_q5 = _argument("movejoint", "target_q5", "rad")
    movecartesian = Clock(description="movecartesian(x, y, z, rx, ry, rz): move the flange to a pose")
    movecartesian_target_x = _argument("movecartesian", "target_x", "m")
    movecartesian_target_y = _argument("movecartesian", "target_y", "m")
    movecartesian_target_z = _argument("movecartesian", "target_z", "m")
    movecartesian_target_rx = _argument("movecartesian", "target_rx", "rad")
    movecartesian_target_ry = _argument("movecartesian", "target_ry", "rad")
    movecartesian_target_rz = _argument("movecartesian", "target_rz", "rad")
    stop = Clock(description="stop(): hold the arm where it is")
    setvelocity = Clock(description="setvelocity(v): joint speed of later and current motions")
    setvelocity_target_v = _argument("setvelocity", "target_v", "rad/s")

    # -- events -------------------------------------------------------------------------------
    feasibleMoveDiscreteCommand = _event("the movediscrete of this instant can be executed", *_MOVEDISCRETE_INPUTS)
    nonfeasibleMoveDiscreteCommand = _event("the movediscrete of this instant cannot be executed",
                                            *_MOVEDISCRETE_INPUTS)
    moveCompleted = _event("every joint within 0.005 rad of the commanded target", "sample")
    robotStopped = _event("every joint slower than 0.1 rad/s and no motion under way", "sample")
    collision = _event("the arm touches the mounting plane or itself", "sample")

    # -- continuous outputs -------------------------------------------------------------------
    q0, q1, q2, q3, q4, q5 = (_joint_output(i, "q") for i in range(6))
    dq0, dq1, dq2, dq3, dq4, dq5 = (_joint_output(i, "dq") for i in range(6))
    ee_x = Float64(causality="output", unit="m", depends_on=(), description="flange position x (base frame)")
    ee_y = Float64(causality="output", unit="m", depends_on=(), description="flange position y (base frame)")
    ee_z = Float64(causality="output", unit="m", depends_on=(), description="flange position z (base frame)")
    ee_rx = Float64(causality="output", unit="rad", depends_on=(), description="flange rotation vector x")
    ee_ry = Float64(causality="output", unit="rad", depends_on=(), description="flange rotation vector y")
    ee_rz = Float64(causality="output", unit="rad", depends_on=(), description="flange rotation vector z")
    physics_steps = Int64(causality="output", depends_on=(), description="physics steps simulated so far")
    motions = Int64(causality="output", depends_on=(), description="motions started so far (a repeated identical command is not a new motion)")

    @classmethod
    def package_resources(cls) -> dict[str, bytes]:
        return {"ur5e.urdf": ur5e_urdf().encode("utf-8")}

    # -- life cycle -----------------------------------------------------------------------------

    def setup(self) -> None:
        self._scene: ArmScene | None = None
        self._scratch: Path | None = None
        self.outputs_stale = True
        self._motions = 0
        self._commanded: tuple[float, ...] | None = None  # target of the last motion command
        self._pending = False                             # that motion is under way
        self._discrete: tuple[int, int, int] | None = None  # the current movediscrete command
        self._discrete_feasible = False
        self._ik: dict[tuple[int, int, int], tuple[float, ...]] = {}  # grid cell -> IK solution
        self._holds = (False, False, False)               # the EVENTS' conditions, in that order
        self._edges: set[str] = set()                     # conditions that became true in a step

    def _urdf(self) -> Path:
        if self.resource_path is not None and (self.resource_path / "ur5e.urdf").is_file():
            return self.resource_path / "ur5e.urdf"
        if self._scratch is None:  # run as a plain Python object (tests), not from an FMU
            self._scratch = Path(tempfile.mkdtemp(prefix="robogen-ur5e-"))
            (self._scratch / "ur5e.urdf").write_text(ur5e_urdf())
        return self._scratch / "ur5e.urdf"

    def _initial_q(self) -> tuple[float, ...]:
        return tuple(self.get(f"initial_q{i}") for i in range(6))

    def exit_initialization_mode(self) -> None:
        dt, speed = self.physics_step, self.joint_speed_limit
        if not (math.isfinite(dt) and 0.0 < dt <= 0.1):
            raise FmiUsageError(f"physics_step must be in (0, 0.1] s, got {dt!r}")
        if not speed_ok(speed):
            raise FmiUsageError(f"joint_speed_limit must be > 0 rad/s, got {speed!r}")
        q0 = self._initial_q()
        for i, (q, limit) in enumerate(zip(q0, JOINT_LIMIT)):
            if not abs(q) <= limit:
                raise FmiUsageError(f"initial_q{i} = {q!r} rad is outside the joint's range +-{limit:.6g} rad")
        self._scene = ArmScene(self._urdf(), dt, q0, speed)
        q, dq = self._scene.joint_states()
        self._evaluate(q, dq, self._scene.in_collision())
        self.outputs_stale = True

    def free(self) -> None:
        if self._scene is not None:
            self._scene.close()
        self._scene = None
        if self._scratch is not None:
            shutil.rmtree(self._scratch, ignore_errors=True)
            self._scratch = None

    # -- outputs --------------------------------------------------------------------------------

    def update_outputs(self) -> None:
        values = self.variable_values
        if self._scene is None:  # before the physics exists: the start pose at rest
            q, dq = self._initial_q(), (0.0,) * 6
            flange = forward(q)
            position, rotation = flange[:3, 3], rotation_vector(flange[:3, :3])
            steps = 0
        else:
            q, dq = self._scene.joint_states()
            position, orientation = self._scene.flange()
            rotation = rotation_vector_of_quaternion(*orientation)
            steps = self._scene.steps
        for i in range(6):
            values[_Q[i]], values[_DQ[i]] = float(q[i]), float(dq[i])
        values["ee_x"], values["ee_y"], values["ee_z"] = (float(v) for v in position)
        values["ee_rx"], values["ee_ry"], values["ee_rz"] = (float(v) for v in rotation)
        values["physics_steps"] = steps
        values["motions"] = self._motions
        self.outputs_stale = self._scene is None

    # -- events ---------------------------------------------------------------------------------

    def _evaluate(self, q, dq, colliding: bool) -> frozenset[str]:
        """Update the three conditions (EVENTS' order) from the current state; return those that
        became true. Evaluated after every watched physics step: tuples, no dict."""
        target = self._commanded
        completed = target is not None and _within(q, target)
        if completed:
            self._pending = False
        stopped = not self._pending and all(map(_SLOW, map(abs, dq)))
        now = (completed, stopped, colliding)
        held = self._holds
        if now == held:
            return _NONE
        self._holds = now
        return frozenset(name for name, holds, before in zip(EVENTS, now, held) if holds and not before)

    def _watching(self) -> bool:
        """Whether a condition can become true: a motion under way or an arm still moving."""
        return self._pending or not self._holds[_STOPPED]

    def react(self, clocks: frozenset[str]) -> None:
        scene = self._scene
        assert scene is not None
        commanded = False
        if "setvelocity" in clocks:
            self._set_velocity(self.setvelocity_target_v)
        if "stop" in clocks:
            self._stop()
            commanded = True
        if "movejoint" in clocks:
            self._move_joint([self.get(f"movejoint.target_q{i}") for i in range(6)])
            commanded = True
        if "movecartesian" in clocks:
            self._move_cartesian([self.get(f"movecartesian.target_{k}") for k in ("x", "y", "z", "rx", "ry", "rz")])
            commanded = True
        if "movediscrete" in clocks:
            commanded = self._move_discrete(self.movediscrete_target_X, self.movediscrete_target_Y,
                                            self.movediscrete_target_Z) or commanded
        sampled = "sample" in clocks
        if commanded or sampled or self._edges:
            # Conditions after this instant's commands: an edge seen in the last step that a new
            # command made false is not reported.
            q, dq = scene.joint_states()
            self._evaluate(q, dq, scene.in_collision())
            for name, holds in zip(EVENTS, self._holds):
                if holds and (sampled or name in self._edges):
                    self.raise_clock(name)
            self._edges.clear()

    def update_discrete_states(self):
        self._edges.clear()
        return None

    # -- operations -----------------------------------------------------------------------------

    def _start_motion(self, target: tuple[float, ...]) -> None:
        assert self._scene is not None
        self._commanded = tuple(target)
        self._motions += 1
        self._pending = True
        self._scene.apply_targets(self._commanded)
        self.outputs_stale = True

    def _solve(self, position, rotation, cell: tuple[int, int, int] | None = None
               ) -> tuple[tuple[float, ...] | None, str]:
        """A collision-free joint solution for a flange pose, or None and why not. Grid cells
        keep their IK solution (the grid is fixed; the scenario revisits its cells)."""
        assert self._scene is not None
        q_now, _ = self._scene.joint_states()
        solution = self._ik.get(cell) if cell is not None else None
        if solution is None:
            result = inverse(position, rotation, seeds=(IK_SEED, q_now))
            if not result.converged:
                return None, (f"out of reach (best IK: {result.position_error * 1000:.1f} mm, "
                              f"{math.degrees(result.orientation_error):.2f} deg off)")
            solution = result.q
            if cell is not None:
                self._ik[cell] = solution
        q = nearest_equivalent(solution, q_now)
        if self._scene.collides(q):
            return None, "the arm would collide in the target pose"
        return q, ""

    def _move_discrete(self, X: int, Y: int, Z: int) -> bool:
        """Answer feasibility; start a motion unless it repeats the current command. Returns
        whether a new command was accepted."""
        cell = (X, Y, Z)
        started = False
        if cell != self._discrete:
            self._discrete = cell
            if not grid_in_table(X, Y, Z):
                q, why = None, "outside the table (X 0..15, Y 0..23, Z >= 0)"
            else:
                q, why = self._solve(*grid_pose(X, Y, Z), cell=cell)
            self._discrete_feasible = q is not None
            if q is not None:
                self._start_motion(q)
                started = True
                self.log(f"t={self.time:.9g}: movediscrete{cell}: feasible, moving to q = "
                         f"({', '.join(f'{v:.4f}' for v in q)})")
            else:
                self.log(f"t={self.time:.9g}: movediscrete{cell}: not feasible: {why}")
        else:
            self.log(f"t={self.time:.9g}: movediscrete{cell} repeated: same command")
        self.raise_clock("feasibleMoveDiscreteCommand" if self._discrete_feasible else "nonfeasibleMoveDiscreteCommand")
        return started

    def _move_joint(self, target: list[float]) -> None:
        clamped = tuple(max(-limit, min(limit, q)) for q, limit in zip(target, JOINT_LIMIT))
        if any(not math.isfinite(q) for q in target):
            self.log(f"t={self.time:.9g}: movejoint ignored: non-finite target {target}", "logStatusWarning", 1)
            return
        if clamped != tuple(target):
            self.log(f"t={self.time:.9g}: movejoint target clamped to the joint limits", "logStatusWarning", 1)
        self._discrete = None
        self._start_motion(clamped)

    def _move_cartesian(self, pose: list[float]) -> None:
        self._discrete = None
        q, why = self._solve(np.array(pose[:3]), rotation_from_vector(pose[3:]))
        if q is None:
            self.log(f"t={self.time:.9g}: movecartesian{tuple(pose)} ignored: {why}", "logStatusWarning", 1)
            return
        self._start_motion(q)

    def _stop(self) -> None:
        scene = self._scene
        assert scene is not None
        q, _ = scene.joint_states()
        target = self._commanded
        done = target is not None and _within(q, target)
        scene.apply_targets(target if done else q)
        self._pending = False
        self._discrete = None
        self.log(f"t={self.time:.9g}: stop: holding {'the completed target' if done else 'the current position'}")

    def _set_velocity(self, speed: float) -> None:
        if not speed_ok(speed):
            self.log(f"t={self.time:.9g}: setvelocity({speed!r}) ignored: needs a speed > 0", "logStatusWarning", 1)
            return
        limited = min(speed, self.joint_speed_limit)
        assert self._scene is not None
        self._scene.apply_targets(self._scene.target, speed=limited)

    # -- time -----------------------------------------------------------------------------------

    def do_step(self, t: float, h: float) -> Step | None:
        scene = self._scene
        assert scene is not None
        dt = self.physics_step
        last = math.floor((t + h - self.start_time) / dt + 1e-6)
        early = self.early_return_allowed
        step, client = pybullet.stepSimulation, scene.client  # the hot loop: no method lookups
        while scene.steps < last:
            if not self._watching():
                # Only a command makes a condition rise again: the rest of the step unobserved,
                # in as few PyBullet calls as give the same physics.
                step_stretch(client, dt, last - scene.steps)
                scene.steps = last
                break
            step(physicsClientId=client)
            scene.steps += 1
            q, dq = scene.joint_states()
            rising = self._evaluate(q, dq, scene.in_collision())
            if rising:
                self._edges |= rising
                if early:
                    self.outputs_stale = True
                    return Step(self.start_time + scene.steps * dt, event=True)
        self.outputs_stale = True
        return Step(t + h, event=True) if self._edges else None
