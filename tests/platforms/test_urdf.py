"""The UR5e URDF: the committed file is the generator's output, and PyBullet's forward
kinematics of it equals the DH chain (< 0.1 mm) with the published masses and limits."""

from __future__ import annotations

import math

import numpy as np
import pybullet
import pytest

from robogen.platforms.kinematics import JOINT_LIMIT, LINK_MASS, MAX_JOINT_SPEED, MAX_JOINT_TORQUE, forward
from robogen.platforms.urdf import ur5e_urdf
from support import ROOT

COMMITTED = ROOT / "models" / "ur5e" / "ur5e.urdf"


@pytest.fixture(scope="module")
def arm():
    client = pybullet.connect(pybullet.DIRECT)
    robot = pybullet.loadURDF(str(COMMITTED), useFixedBase=True, flags=pybullet.URDF_USE_INERTIA_FROM_FILE,
                              physicsClientId=client)
    yield client, robot
    pybullet.disconnect(physicsClientId=client)


def test_committed_urdf_is_the_generator_output():
    assert COMMITTED.read_text() == ur5e_urdf()


def test_pybullet_forward_kinematics_equals_the_dh_chain(arm):
    client, robot = arm
    rng = np.random.default_rng(20240611)
    worst_position = worst_rotation = 0.0
    for _ in range(500):
        q = rng.uniform(-2 * math.pi, 2 * math.pi, 6)
        for j in range(6):
            pybullet.resetJointState(robot, j, q[j], physicsClientId=client)
        state = pybullet.getLinkState(robot, 6, computeForwardKinematics=True, physicsClientId=client)
        rotation = np.array(pybullet.getMatrixFromQuaternion(state[5])).reshape(3, 3)
        flange = forward(q)
        worst_position = max(worst_position, float(np.linalg.norm(np.array(state[4]) - flange[:3, 3])))
        worst_rotation = max(worst_rotation, float(np.abs(rotation - flange[:3, :3]).max()))
    assert worst_position < 1e-4  # 0.1 mm
    assert worst_rotation < 1e-5


def test_links_carry_the_published_masses_and_joints_the_published_limits(arm):
    client, robot = arm
    assert pybullet.getNumJoints(robot, physicsClientId=client) == 7  # six revolute joints and tool0
    for j in range(6):
        assert pybullet.getDynamicsInfo(robot, j, physicsClientId=client)[0] == pytest.approx(LINK_MASS[j])
        info = pybullet.getJointInfo(robot, j, physicsClientId=client)
        assert info[2] == pybullet.JOINT_REVOLUTE
        assert (info[8], info[9]) == pytest.approx((-JOINT_LIMIT[j], JOINT_LIMIT[j]))
        assert (info[10], info[11]) == pytest.approx((MAX_JOINT_TORQUE[j], MAX_JOINT_SPEED))
    assert pybullet.getJointInfo(robot, 6, physicsClientId=client)[12] == b"tool0"
