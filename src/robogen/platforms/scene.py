"""The PyBullet scene of the UR5e platform: the arm, its mounting plane, its motors.

One :class:`ArmScene` owns one PyBullet physics client in DIRECT mode (headless, in-process),
so several platform instances in one process never share state. Every PyBullet call passes
that client's id explicitly.

The scene: the arm of ``ur5e.urdf`` with its base fixed at the origin of the world (= the DH
base frame), gravity along -z of that frame, and a plane at z = 0 (the surface the arm is
mounted on). The case study's hole table is not modelled as a body: its holes are only the
targets of the grid mapping, expressed in the base frame with the tilted mounting
(:func:`robogen.platforms.kinematics.grid_position`).

Joints are position controlled (PyBullet's constraint motor) with the UR5e torque limits and a
common speed limit. Contacts count as a collision when two bodies (or two links of the arm that
are not neighbours) touch or penetrate: contact distance <= 0. The base and the shoulder link
rest on the plane by construction, so those two pairs are filtered out.

Whether a joint configuration would collide is asked of the same client (:meth:`ArmScene.collides`):
the arm is posed there, contacts detected, and its joint positions and velocities put back
exactly (a fixed-base arm's whole dynamic state), so the physics that follows is the one it
would have been. No second client: connecting one and building its plane costs about as much
CPU as a whole second of simulated motion.
"""

from __future__ import annotations

import math
from operator import itemgetter
from pathlib import Path
from typing import Sequence

import pybullet

from robogen.platforms.kinematics import MAX_JOINT_TORQUE

JOINTS = (0, 1, 2, 3, 4, 5)
TOOL_LINK = 6
GRAVITY = 9.81
# Motor gains of PyBullet's position constraint: the position error term and the velocity
# error term of the motor's target velocity. Chosen so that a move settles without overshoot
# far below the 0.005 rad completion tolerance.
POSITION_GAIN = 0.3
VELOCITY_GAIN = 1.0
_POSITION, _VELOCITY = itemgetter(0), itemgetter(1)  # of a getJointStates entry


SELF_COLLISION = pybullet.URDF_USE_SELF_COLLISION | pybullet.URDF_USE_SELF_COLLISION_EXCLUDE_PARENT

# A stretch this long or longer is stepped in one call (see step_stretch); a shorter one, a call a step.
STRETCH_MIN = 4


def stretch_is_exact(m: int, dt: float) -> bool:
    """Whether Bullet, asked for one step of m * dt in m substeps (PyBullet's numSubSteps), does m
    substeps of exactly dt: its substep is (m * dt) / m, and it counts int(time / substep) of them
    (btDiscreteDynamicsWorld::stepSimulation, the time starting from 0 after a single step).
    Python's float arithmetic is the same IEEE double arithmetic as Bullet's."""
    total = m * dt
    substep = total / m
    return substep == dt and int(total / substep) >= m


def step_stretch(client: int, dt: float, n: int) -> None:
    """n physics steps of dt, the same physics bit for bit as n calls of stepSimulation, in two
    steps where that holds (:func:`stretch_is_exact`): n - 1 substeps of one call, then one single
    step, which also sets Bullet's time remainder back to zero for the next stretch (with the two
    calls that set the substeps and set them back, four PyBullet calls). A call
    of PyBullet costs about a tenth of a physics step of the UR5e besides the step itself
    (bench/bench_demo.py measures it). Motor targets, gravity and the contacts are the world's
    between calls; no external force is applied (PyBullet clears those after each call) and the
    arm's joints have no damping (PyBullet applies it once per call), so nothing of a call is
    lost between its substeps. tests/platforms/test_scene.py compares both ways step for step."""
    step = pybullet.stepSimulation
    m = n - 1
    if n < STRETCH_MIN or not stretch_is_exact(m, dt):
        for _ in range(n):
            step(physicsClientId=client)
        return
    pybullet.setPhysicsEngineParameter(fixedTimeStep=m * dt, numSubSteps=m, physicsClientId=client)
    step(physicsClientId=client)
    pybullet.setPhysicsEngineParameter(fixedTimeStep=dt, numSubSteps=0, physicsClientId=client)
    step(physicsClientId=client)


def _load_arm(client: int, urdf: Path, flags: int) -> tuple[int, int]:
    """The arm (base fixed at the origin) and the mounting plane in ``client``: (robot, plane)."""
    robot = pybullet.loadURDF(str(urdf), useFixedBase=True, flags=flags, physicsClientId=client)
    plane_shape = pybullet.createCollisionShape(pybullet.GEOM_PLANE, physicsClientId=client)
    plane = pybullet.createMultiBody(0.0, plane_shape, physicsClientId=client)
    for link in (-1, 0):  # the base and the shoulder sit on the plane
        pybullet.setCollisionFilterPair(plane, robot, -1, link, 0, physicsClientId=client)
    return robot, plane


class ArmScene:
    def __init__(self, urdf: Path, time_step: float, q_initial: Sequence[float], speed: float) -> None:
        self.client = pybullet.connect(pybullet.DIRECT)
        if self.client < 0:
            raise RuntimeError("PyBullet could not open a DIRECT physics client")
        cid = self.client
        pybullet.setTimeStep(time_step, physicsClientId=cid)
        pybullet.setGravity(0.0, 0.0, -GRAVITY, physicsClientId=cid)
        self.robot, self.plane = _load_arm(cid, urdf, pybullet.URDF_USE_INERTIA_FROM_FILE | SELF_COLLISION)
        for j, q in zip(JOINTS, q_initial):
            pybullet.resetJointState(self.robot, j, q, 0.0, physicsClientId=cid)
        self.speed = speed
        self.target = tuple(float(q) for q in q_initial)
        self.apply_targets(self.target)
        self.steps = 0  # physics steps done; the owner steps the client (a hot loop) and counts
        self._collision = (-1, False)  # (steps, in_collision()) of the last answer, kept for that step
        self._states_at = -1  # the steps count of self._states, the last joint_states()
        self._states: tuple[tuple[float, ...], tuple[float, ...]] = ((), ())

    # -- motors ---------------------------------------------------------------------------------

    def apply_targets(self, target: Sequence[float], speed: float | None = None) -> None:
        """Position-control every joint to ``target`` at most at ``speed`` rad/s."""
        if speed is not None:
            self.speed = speed
        self.target = tuple(float(q) for q in target)
        for j, q, torque in zip(JOINTS, self.target, MAX_JOINT_TORQUE):
            pybullet.setJointMotorControl2(
                self.robot, j, pybullet.POSITION_CONTROL, targetPosition=q, targetVelocity=0.0, force=torque,
                positionGain=POSITION_GAIN, velocityGain=VELOCITY_GAIN, maxVelocity=self.speed,
                physicsClientId=self.client)

    # -- reading ------------------------------------------------------------------------------

    def joint_states(self) -> tuple[tuple[float, ...], tuple[float, ...]]:
        """Joint positions and velocities after the last physics step (read once per step)."""
        if self._states_at != self.steps:
            states = pybullet.getJointStates(self.robot, JOINTS, physicsClientId=self.client)
            self._states = tuple(map(_POSITION, states)), tuple(map(_VELOCITY, states))
            self._states_at = self.steps
        return self._states

    def in_collision(self) -> bool:
        """Whether the last physics step found the arm touching the plane or itself (asked of
        PyBullet once per step: a :meth:`collides` query since then replaced the contacts it holds)."""
        steps, hit = self._collision
        if steps != self.steps:
            hit = self._contact()
            self._collision = (self.steps, hit)
        return hit

    def _contact(self) -> bool:
        for contact in pybullet.getContactPoints(bodyA=self.robot, physicsClientId=self.client):
            if contact[8] <= 0.0:
                return True
        return False

    def collides(self, q: Sequence[float]) -> bool:
        """Whether the arm posed at ``q`` touches the plane or itself (contact distance <= 0); the
        arm's joint positions and velocities are restored bit for bit afterwards, and
        :meth:`in_collision` answers for the arm's own pose until the next step."""
        cid, robot = self.client, self.robot
        self.in_collision()  # the arm's own answer for this step, kept before the query replaces it
        states = pybullet.getJointStates(robot, JOINTS, physicsClientId=cid)
        for j, value in zip(JOINTS, q):
            pybullet.resetJointState(robot, j, value, 0.0, physicsClientId=cid)
        pybullet.performCollisionDetection(physicsClientId=cid)
        hit = any(c[8] <= 0.0 for c in pybullet.getContactPoints(bodyA=robot, physicsClientId=cid))
        for j, state in zip(JOINTS, states):
            pybullet.resetJointState(robot, j, state[0], state[1], physicsClientId=cid)
        return hit

    def flange(self) -> tuple[tuple[float, float, float], tuple[float, float, float, float]]:
        """Position and orientation (unit quaternion x, y, z, w) of tool0 in the base frame."""
        state = pybullet.getLinkState(self.robot, TOOL_LINK, computeForwardKinematics=True,
                                      physicsClientId=self.client)
        return state[4], state[5]

    def close(self) -> None:
        if self.client >= 0:
            pybullet.disconnect(physicsClientId=self.client)
            self.client = -1


def speed_ok(value: float) -> bool:
    return math.isfinite(value) and value > 0.0
