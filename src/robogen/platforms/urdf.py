"""A UR5e URDF written from the DH table of :mod:`robogen.platforms.kinematics`.

Links are simple geometry: a cylinder (visual and collision) along each DH segment, with the
published mass at the published centre of mass and the inertia of a solid cylinder of that
mass. Frames follow the DH chain exactly, so PyBullet's forward kinematics equals the DH chain:

- ``base`` is DH frame 0 (the UR "Base" frame, not ROS's ``base_link``);
- link ``i`` (``shoulder_link`` ... ``wrist_3_link``) is DH frame i-1 turned by q_i about z,
  so joint i+1 sits at ``xyz = (a_i, 0, d_i)``, ``rpy = (alpha_i, 0, 0)`` in it;
- ``tool0`` is DH frame 6, the flange, z pointing out of it.

The repository's UR5e case study commits this module's output (``python -m
robogen.platforms.urdf PATH`` rewrites it); a test checks they agree.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

from robogen.platforms.kinematics import (
    DH_A, DH_ALPHA, DH_D, JOINT_LIMIT, JOINT_NAMES, LINK_COM, LINK_MASS, MAX_JOINT_SPEED, MAX_JOINT_TORQUE,
    rotation_x,
)

LINK_NAMES = ("shoulder_link", "upper_arm_link", "forearm_link", "wrist_1_link", "wrist_2_link", "wrist_3_link")
VISUAL_RADIUS = (0.06, 0.054, 0.045, 0.04, 0.04, 0.035)
# Collision cylinders are thinner than the visuals and stop short of the joints at both ends,
# so neighbours-but-one do not touch at a joint where the real arm has clearance.
COLLISION_RADIUS = (0.05, 0.045, 0.035, 0.03, 0.03, 0.03)
COLLISION_END_GAP = 0.05
MIN_CYLINDER = 0.04  # m: the length given to links whose DH segment is shorter
BASE_MASS = 4.0  # kg; the base is fixed, its mass does not enter the dynamics


def _f(value: float) -> str:
    text = f"{value:.9g}"
    return "0" if text in ("-0", "0") else text


def _vec(values) -> str:
    return " ".join(_f(float(v)) for v in values)


def _segment_rpy(segment: np.ndarray) -> tuple[float, float, float]:
    """rpy turning a cylinder's z axis onto ``segment`` (along x or z in this chain)."""
    if abs(segment[0]) > abs(segment[2]):
        return (0.0, math.pi / 2, 0.0)
    return (0.0, 0.0, 0.0)


def _inertia(mass: float, radius: float, length: float, along_x: bool) -> dict[str, float]:
    axial = 0.5 * mass * radius**2
    transverse = mass * (3 * radius**2 + length**2) / 12.0
    if along_x:
        return {"ixx": axial, "iyy": transverse, "izz": transverse}
    return {"ixx": transverse, "iyy": transverse, "izz": axial}


def _cylinder_link(name: str, mass: float, com, inertia: dict[str, float], centre, rpy, visual: tuple[float, float],
                   collision: tuple[float, float], material: str) -> str:
    """A link drawn and collided as one cylinder (radius, length) placed at ``centre``, ``rpy``."""
    return f"""  <link name="{name}">
    <inertial>
      <origin xyz="{_vec(com)}" rpy="0 0 0"/>
      <mass value="{_f(mass)}"/>
      <inertia ixx="{_f(inertia['ixx'])}" ixy="0" ixz="0" iyy="{_f(inertia['iyy'])}" iyz="0" izz="{_f(inertia['izz'])}"/>
    </inertial>
    <visual>
      <origin xyz="{_vec(centre)}" rpy="{_vec(rpy)}"/>
      <geometry><cylinder radius="{_f(visual[0])}" length="{_f(visual[1])}"/></geometry>
      <material name="{material}"/>
    </visual>
    <collision>
      <origin xyz="{_vec(centre)}" rpy="{_vec(rpy)}"/>
      <geometry><cylinder radius="{_f(collision[0])}" length="{_f(collision[1])}"/></geometry>
    </collision>
  </link>
"""


def _link(index: int) -> str:
    segment = np.array([DH_A[index], 0.0, DH_D[index]])
    length = float(np.linalg.norm(segment))
    com = segment + rotation_x(DH_ALPHA[index]) @ np.array(LINK_COM[index])
    along_x = abs(segment[0]) > abs(segment[2])
    shown = max(length, MIN_CYLINDER)
    centre = segment / 2 if length > 0 else np.zeros(3)
    inertia = _inertia(LINK_MASS[index], VISUAL_RADIUS[index], shown, along_x)
    collision = (COLLISION_RADIUS[index], max(length - 2 * COLLISION_END_GAP, 0.01))
    return _cylinder_link(LINK_NAMES[index], LINK_MASS[index], com, inertia, centre, _segment_rpy(segment),
                          (VISUAL_RADIUS[index], shown), collision, "ur_grey")


def _joint(index: int) -> str:
    parent = "base" if index == 0 else LINK_NAMES[index - 1]
    if index == 0:
        xyz, rpy = (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
    else:
        xyz, rpy = (DH_A[index - 1], 0.0, DH_D[index - 1]), (DH_ALPHA[index - 1], 0.0, 0.0)
    limit = JOINT_LIMIT[index]
    return f"""  <joint name="{JOINT_NAMES[index]}_joint" type="revolute">
    <parent link="{parent}"/>
    <child link="{LINK_NAMES[index]}"/>
    <origin xyz="{_vec(xyz)}" rpy="{_vec(rpy)}"/>
    <axis xyz="0 0 1"/>
    <limit lower="{_f(-limit)}" upper="{_f(limit)}" effort="{_f(MAX_JOINT_TORQUE[index])}" velocity="{_f(MAX_JOINT_SPEED)}"/>
    <dynamics damping="0" friction="0"/>
  </joint>
"""


def ur5e_urdf() -> str:
    """The URDF text (deterministic)."""
    parts = [
        '<?xml version="1.0"?>\n',
        "<!-- UR5e from Universal Robots' published DH parameters, link masses and centres of mass.\n"
        "     Generated by robogen.platforms.urdf: do not edit; regenerate with\n"
        "     python -m robogen.platforms.urdf OUTPUT.urdf -->\n",
        '<robot name="ur5e">\n',
        '  <material name="ur_grey"><color rgba="0.7 0.7 0.72 1"/></material>\n',
        '  <material name="ur_blue"><color rgba="0.2 0.4 0.7 1"/></material>\n',
        _cylinder_link("base", BASE_MASS, (0.0, 0.0, 0.03), _inertia(BASE_MASS, 0.075, 0.06, False), (0.0, 0.0, 0.03),
                       (0.0, 0.0, 0.0), (0.075, 0.06), (0.075, 0.06), "ur_blue"),
    ]
    for i in range(6):
        parts.append(_joint(i))
        parts.append(_link(i))
    parts.append(f"""  <joint name="flange_tool0_joint" type="fixed">
    <parent link="{LINK_NAMES[5]}"/>
    <child link="tool0"/>
    <origin xyz="{_vec((DH_A[5], 0.0, DH_D[5]))}" rpy="{_vec((DH_ALPHA[5], 0.0, 0.0))}"/>
  </joint>
  <link name="tool0">
    <inertial>
      <origin xyz="0 0 0" rpy="0 0 0"/>
      <mass value="0.001"/>
      <inertia ixx="1e-07" ixy="0" ixz="0" iyy="1e-07" iyz="0" izz="1e-07"/>
    </inertial>
  </link>
</robot>
""")
    return "".join(parts)


def main(argv: list[str]) -> int:
    if len(argv) != 1:
        print("usage: python -m robogen.platforms.urdf OUTPUT.urdf", file=sys.stderr)
        return 2
    Path(argv[0]).write_text(ur5e_urdf())
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
