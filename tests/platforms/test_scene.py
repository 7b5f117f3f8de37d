"""The PyBullet scene: the collision query of a configuration runs in the simulation's own client
and leaves its physics exactly as it would have been without the query."""

from __future__ import annotations

import pybullet
import pytest

from robogen.platforms.kinematics import HOME, MAX_JOINT_SPEED
from robogen.platforms.scene import ArmScene, step_stretch, stretch_is_exact
from support import ROOT

URDF = ROOT / "models" / "ur5e" / "ur5e.urdf"
INTO_PLANE = (HOME[0], 0.3, *HOME[2:])  # the upper arm swung down through the plane z = 0


@pytest.fixture
def scene():
    s = ArmScene(URDF, 1.0 / 240.0, HOME, MAX_JOINT_SPEED)
    yield s
    s.close()


def test_collides_with_the_plane_but_not_at_home(scene):
    assert not scene.collides(HOME)
    assert scene.collides(INTO_PLANE)
    assert not scene.in_collision()  # the arm itself stayed at home


def _run(query_at: int | None) -> tuple:
    """60 physics steps of a motion away from home; ``query_at``: the step after which a colliding
    configuration is queried. The joint states at the end."""
    scene = ArmScene(URDF, 1.0 / 240.0, HOME, MAX_JOINT_SPEED)
    try:
        target = list(HOME)
        target[0] += 1.0
        target[2] -= 0.5
        scene.apply_targets(target)
        for k in range(60):
            if k == query_at:
                moving = scene.joint_states()
                states = pybullet.getJointStates(scene.robot, range(6), physicsClientId=scene.client)
                assert scene.collides(INTO_PLANE)
                assert scene.joint_states() == moving  # positions and velocities put back bit for bit
                assert pybullet.getJointStates(scene.robot, range(6), physicsClientId=scene.client) == states
            pybullet.stepSimulation(physicsClientId=scene.client)
            scene.steps += 1
        return scene.joint_states()
    finally:
        scene.close()


def test_a_query_in_the_middle_of_a_motion_does_not_change_the_physics():
    undisturbed = _run(None)
    assert max(abs(v) for v in undisturbed[1]) > 0.1  # still moving at the end: a real motion
    assert _run(30) == undisturbed  # bit for bit


def test_a_query_while_pressing_on_the_plane_keeps_the_contact_and_the_physics():
    def run(query_at):
        scene = ArmScene(URDF, 1.0 / 240.0, HOME, MAX_JOINT_SPEED)
        try:
            scene.apply_targets(INTO_PLANE)
            for k in range(400):
                if k == query_at:
                    assert scene.in_collision()  # pressing on the plane
                    assert not scene.collides(HOME)
                    assert scene.in_collision()  # still: the arm's own contact, not the query's
                pybullet.stepSimulation(physicsClientId=scene.client)
                scene.steps += 1
            return scene.joint_states(), scene.in_collision()
        finally:
            scene.close()

    undisturbed = run(None)
    assert undisturbed[1]
    assert run(300) == undisturbed


def test_a_stretch_in_one_call_is_exact_only_where_bullet_would_do_m_substeps_of_dt():
    assert all(stretch_is_exact(m, 0.25) for m in range(1, 1000))  # a power of two: every product exact
    # 3 * 0.1 = 0.30000000000000004, and that / 3 = 0.10000000000000002: not the step
    assert 3 * 0.1 / 3 != 0.1 and not stretch_is_exact(3, 0.1)
    assert stretch_is_exact(2, 0.1)  # 0.2 / 2 = 0.1


def _stepped(dt: float, schedule, stretched: bool):
    """Joint states (positions, velocities, reaction forces, motor torques) and contacts after
    each chunk of the schedule, a chunk's steps as one stretch (step_stretch) or a call a step."""
    scene = ArmScene(URDF, dt, HOME, MAX_JOINT_SPEED)
    cid, seen = scene.client, []
    try:
        for target, n in schedule:
            if target is not None:
                scene.apply_targets(target)
            if stretched:
                step_stretch(cid, dt, n)
            else:
                for _ in range(n):
                    pybullet.stepSimulation(physicsClientId=cid)
            seen.append((pybullet.getJointStates(scene.robot, range(6), physicsClientId=cid),
                         pybullet.getContactPoints(bodyA=scene.robot, physicsClientId=cid)))
        return seen
    finally:
        scene.close()


@pytest.mark.parametrize("dt", [1.0 / 240.0, 0.001, 0.002])
def test_a_stretch_in_one_call_is_the_same_physics_as_a_call_a_step(dt):
    away = (HOME[0] + 1.0, HOME[1], HOME[2] - 0.5, *HOME[3:])
    # stretches of every length around the cut-off and the sampling interval, single steps in
    # between, a motion started and changed mid-way, and the arm pressing on the plane (contacts)
    lengths = [1, 2, 3, 4, 5, 7, 13, 119, 120, 121, 240, 241, 1, 1, 60, 2, 500]
    schedule = [(away if k == 0 else INTO_PLANE if k == 9 else HOME if k == 14 else None, n)
                for k, n in enumerate(lengths)]
    single = _stepped(dt, schedule, stretched=False)
    assert any(contacts for _, contacts in single)  # the plane was touched: contacts compared too
    # the arm moving fast when a long stretch began
    assert any(lengths[i] >= 100 and max(abs(s[1]) for s in single[i - 1][0]) > 0.1 for i in range(1, len(lengths)))
    assert _stepped(dt, schedule, stretched=True) == single  # bit for bit, after every chunk
