"""The PyBullet scene: the collision query of a configuration runs in the simulation's own client
and leaves its physics exactly as it would have been without the query."""

from __future__ import annotations

import pybullet
import pytest

from robogen.platforms.kinematics import HOME, MAX_JOINT_SPEED
from robogen.platforms.scene import ArmScene
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
