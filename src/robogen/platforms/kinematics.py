"""UR5e kinematics from the published Denavit-Hartenberg table, and the case study's grid.

Standard DH convention (Universal Robots' published UR5e DH parameters): the transform from frame i-1 to
frame i is ``Rz(q_i) Tz(d_i) Tx(a_i) Rx(alpha_i)``. Frame 0 is the UR controller's "Base"
frame, frame 6 the tool flange (z out of the flange). Everything here is numpy on 6-vectors and
4x4 homogeneous matrices; nothing depends on PyBullet, so the URDF and the simulation can be
checked against it.

Inverse kinematics is a Levenberg-Marquardt iteration on the flange pose error (position in
metres, orientation as a rotation vector in radians), with the step length clipped and the
joints wrapped to (-pi, pi]. It starts from the case study's seed and, if that does not
converge, from a few other configurations, so a target it reports unreachable really is out
of reach rather than a local minimum of one start.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Iterable, Sequence

import numpy as np

# ---- the UR5e (Universal Robots' published DH parameters, masses and centres of mass) ------

DH_A = (0.0, -0.425, -0.3922, 0.0, 0.0, 0.0)
DH_D = (0.1625, 0.0, 0.0, 0.1333, 0.0997, 0.0996)
DH_ALPHA = (math.pi / 2, 0.0, 0.0, math.pi / 2, -math.pi / 2, 0.0)
LINK_MASS = (3.761, 8.058, 2.846, 1.37, 1.3, 0.365)
# Centre of mass of link i, expressed in DH frame i.
LINK_COM = (
    (0.0, -0.02561, 0.00193),
    (0.2125, 0.0, 0.11336),
    (0.15, 0.0, 0.0265),
    (0.0, -0.0018, 0.01634),
    (0.0, 0.0018, 0.01634),
    (0.0, 0.0, -0.001159),
)
JOINT_NAMES = ("shoulder_pan", "shoulder_lift", "elbow", "wrist_1", "wrist_2", "wrist_3")
# Position limits: +-2 pi for every joint; the elbow is kept within +-pi as UR's own
# description does, since the arm's construction stops it there anyway.
JOINT_LIMIT = (2 * math.pi, 2 * math.pi, math.pi, 2 * math.pi, 2 * math.pi, 2 * math.pi)
MAX_JOINT_SPEED = math.pi  # rad/s, every joint (UR5e user manual: 180 deg/s)
MAX_JOINT_TORQUE = (150.0, 150.0, 150.0, 28.0, 28.0, 28.0)  # N m
REACH = 0.85  # m, manufacturer specification

# The reference's IK seed (case study §6), in the standard UR joint convention. It is only a
# start for the iteration: as a pose it puts the flange 0.34 m below the mounting plane.
IK_SEED = (-math.pi / 2, math.pi / 4, 0.0, math.pi / 2, 0.0, 0.0)
# robogen's start pose: elbow up, flange pointing down at (-0.133, 0.492, 0.488) m, clear of
# the plane and of the arm itself; straight joint paths from it to the scenario targets are
# collision-free.
HOME = (-math.pi / 2, -math.pi / 2, math.pi / 2, -math.pi / 2, -math.pi / 2, 0.0)

# ---- the workspace: a table of holes 5 cm apart (case study §4) ----------------------------

GRID_X = range(0, 16)
GRID_Y = range(0, 24)
GRID_PITCH = 0.05
TABLE_HEIGHT = 0.020


def dh_transform(q: float, d: float, a: float, alpha: float) -> np.ndarray:
    ct, st, ca, sa = math.cos(q), math.sin(q), math.cos(alpha), math.sin(alpha)
    return np.array([
        [ct, -st * ca, st * sa, a * ct],
        [st, ct * ca, -ct * sa, a * st],
        [0.0, sa, ca, d],
        [0.0, 0.0, 0.0, 1.0],
    ])


def frames(q: Sequence[float]) -> list[np.ndarray]:
    """Frames 0..6 of the DH chain (frame 0 is the identity)."""
    out = [np.eye(4)]
    for i in range(6):
        out.append(out[-1] @ dh_transform(q[i], DH_D[i], DH_A[i], DH_ALPHA[i]))
    return out


def forward(q: Sequence[float]) -> np.ndarray:
    """The flange pose (4x4) in the base frame."""
    return frames(q)[-1]


def jacobian(q: Sequence[float]) -> np.ndarray:
    """The 6x6 geometric Jacobian (linear velocity rows first) of the flange."""
    fs = frames(q)
    ex, ey, ez = fs[-1][:3, 3]
    jac = np.empty((6, 6))
    for i in range(6):
        zx, zy, zz = fs[i][:3, 2]
        ox, oy, oz = fs[i][:3, 3]
        rx, ry, rz = ex - ox, ey - oy, ez - oz
        jac[:, i] = (zy * rz - zz * ry, zz * rx - zx * rz, zx * ry - zy * rx, zx, zy, zz)  # z x r, then z
    return jac


def rotation_x(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rotation_vector(rotation: np.ndarray) -> np.ndarray:
    """The axis-angle vector (angle in [0, pi]) of a rotation matrix (UR's pose convention)."""
    skew = np.array([rotation[2, 1] - rotation[1, 2], rotation[0, 2] - rotation[2, 0], rotation[1, 0] - rotation[0, 1]])
    cos_angle = (float(np.trace(rotation)) - 1.0) / 2.0
    sin_angle = float(np.linalg.norm(skew)) / 2.0
    angle = math.atan2(sin_angle, cos_angle)
    if angle < 1e-15:
        return np.zeros(3)
    if cos_angle > -0.9:
        return skew * (angle / (2.0 * sin_angle))
    # Near a half turn the skew part vanishes: take the axis from the symmetric part,
    # (R + R^T)/2 - cos(angle) I = (1 - cos(angle)) n n^T, and its sign from the skew part.
    sym = (rotation + rotation.T) / 2.0 - cos_angle * np.eye(3)
    k = int(np.argmax(np.diag(sym)))
    axis = sym[:, k] / math.sqrt(sym[k, k] * (1.0 - cos_angle))
    if float(axis @ skew) < 0.0:
        axis = -axis
    return axis / np.linalg.norm(axis) * angle


def rotation_vector_of_quaternion(x: float, y: float, z: float, w: float) -> tuple[float, float, float]:
    """The axis-angle vector (angle in [0, pi]) of a unit quaternion (x, y, z, w), PyBullet's
    order, in plain floats (the platform reads the flange's pose at every event). The angle is
    2 atan2(|v|, w) with w >= 0, accurate everywhere, near a half turn too, where the matrix's
    skew part vanishes (:func:`rotation_vector` needs a second formula there). At exactly a half
    turn, axis * pi and -axis * pi are the same rotation: this keeps the quaternion's sign."""
    if w < 0.0:  # q and -q are the same rotation; w >= 0 gives the angle in [0, pi]
        x, y, z, w = -x, -y, -z, -w
    s = math.sqrt(x * x + y * y + z * z)
    if s == 0.0:
        return (0.0, 0.0, 0.0)
    scale = 2.0 * math.atan2(s, w) / s
    return (x * scale, y * scale, z * scale)


def rotation_from_vector(vector: Sequence[float]) -> np.ndarray:
    """Rodrigues' formula: the rotation matrix of an axis-angle vector."""
    v = np.asarray(vector, dtype=float)
    angle = float(np.linalg.norm(v))
    if angle < 1e-15:
        return np.eye(3)
    k = v / angle
    kx = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + math.sin(angle) * kx + (1.0 - math.cos(angle)) * (kx @ kx)


def pose_error(q: Sequence[float], position: np.ndarray, rotation: np.ndarray) -> np.ndarray:
    flange = forward(q)
    return np.concatenate([position - flange[:3, 3], rotation_vector(rotation @ flange[:3, :3].T)])


def wrap(q: np.ndarray) -> np.ndarray:
    """Joint angles in (-pi, pi]."""
    return -((-q + math.pi) % (2 * math.pi) - math.pi)


# ---- grid -> pose ----------------------------------------------------------------------------

# The flange orientation of every grid target: a rotation of 5 pi / 4 about the base x axis, so
# the flange's z axis points along (0, sqrt(2)/2, -sqrt(2)/2) (case study §6).
GRID_ORIENTATION = rotation_x(5 * math.pi / 4)


def grid_in_table(X: int, Y: int, Z: int) -> bool:
    return X in GRID_X and Y in GRID_Y and Z >= 0


def grid_position(X: int, Y: int, Z: int) -> np.ndarray:
    """The base-frame position of grid cell (X, Y, Z): the table's coordinates, then the
    tilted mounting, a +45 deg rotation in the y-z plane (the rotation form for every X)."""
    x = 1.128 - (Y + 1) * GRID_PITCH
    y = 0.711 - X * GRID_PITCH
    z = TABLE_HEIGHT + Z * GRID_PITCH
    s = math.sqrt(0.5)
    return np.array([x, (y - z) * s, (y + z) * s])


def grid_pose(X: int, Y: int, Z: int) -> tuple[np.ndarray, np.ndarray]:
    return grid_position(X, Y, Z), GRID_ORIENTATION


# ---- inverse kinematics --------------------------------------------------------------------

POSITION_TOLERANCE = 1e-7  # m
ORIENTATION_TOLERANCE = 1e-7  # rad


@dataclass(frozen=True)
class IKResult:
    q: tuple[float, ...]
    position_error: float   # m
    orientation_error: float  # rad
    converged: bool
    iterations: int


def _levenberg_marquardt(position: np.ndarray, rotation: np.ndarray, seed: np.ndarray,
                         max_iterations: int) -> tuple[np.ndarray, np.ndarray, int]:
    q = wrap(np.array(seed, dtype=float))
    err = pose_error(q, position, rotation)
    cost = float(err @ err)
    damping = 1e-2
    iterations = 0
    for iterations in range(1, max_iterations + 1):
        if math.sqrt(cost) < 1e-13:
            break
        jac = jacobian(q)
        hessian, gradient = jac.T @ jac, jac.T @ err
        while True:
            step = np.linalg.solve(hessian + damping * np.eye(6), gradient)
            norm = float(np.linalg.norm(step))
            if norm > 0.5:
                step *= 0.5 / norm
            trial = wrap(q + step)
            trial_err = pose_error(trial, position, rotation)
            trial_cost = float(trial_err @ trial_err)
            if trial_cost < cost:
                q, err, cost = trial, trial_err, trial_cost
                damping = max(damping / 10.0, 1e-12)
                break
            damping *= 10.0
            if damping > 1e10:
                return q, err, iterations
    return q, err, iterations


def inverse(position: Sequence[float], rotation: np.ndarray, seeds: Iterable[Sequence[float]] = (IK_SEED,),
            max_iterations: int = 100) -> IKResult:
    """A joint vector placing the flange at (position, rotation), trying each seed in turn and
    then a fixed set of spare starts; the first converged solution wins (else the best one)."""
    position = np.asarray(position, dtype=float)
    rotation = np.asarray(rotation, dtype=float)
    best: IKResult | None = None
    for seed in [*seeds, *_SPARE_SEEDS]:
        q, err, iterations = _solved(position, rotation, np.asarray(seed, dtype=float), max_iterations)
        p_err, r_err = float(np.linalg.norm(err[:3])), float(np.linalg.norm(err[3:]))
        result = IKResult(tuple(float(v) for v in q), p_err, r_err,
                          p_err < POSITION_TOLERANCE and r_err < ORIENTATION_TOLERANCE, iterations)
        if result.converged:
            return result
        if best is None or p_err + r_err < best.position_error + best.orientation_error:
            best = result
    assert best is not None
    return best


#: the searches done in this process: (position, rotation, seed, max_iterations) as bytes -> result
_SOLVED: dict[tuple[bytes, bytes, bytes, int], tuple[np.ndarray, np.ndarray, int]] = {}
_SOLVED_MAX = 4096


def _solved(position: np.ndarray, rotation: np.ndarray, seed: np.ndarray,
            max_iterations: int) -> tuple[np.ndarray, np.ndarray, int]:
    """:func:`_levenberg_marquardt`, each search done once per process: a pure function of its
    arguments (the same doubles give the same iterations), so a platform FMU instantiated again
    (a later run, a campaign's next run) does not repeat its searches for the poses it solved."""
    key = (position.tobytes(), rotation.tobytes(), seed.tobytes(), max_iterations)
    found = _SOLVED.get(key)
    if found is None:
        q, err, iterations = _levenberg_marquardt(position, rotation, seed, max_iterations)
        q.setflags(write=False)
        err.setflags(write=False)
        if len(_SOLVED) >= _SOLVED_MAX:
            _SOLVED.clear()
        found = _SOLVED[key] = q, err, iterations
    return found


_SPARE_SEEDS = (
    (0.0, -math.pi / 2, math.pi / 2, -math.pi / 2, -math.pi / 2, 0.0),
    (-math.pi / 2, -math.pi / 2, math.pi / 2, -math.pi / 2, -math.pi / 2, 0.0),
    (math.pi / 2, -math.pi / 2, -math.pi / 2, -math.pi / 2, math.pi / 2, 0.0),
    (math.pi, -math.pi / 3, math.pi / 3, -math.pi / 2, -math.pi / 2, 0.0),
)


def nearest_equivalent(q: Sequence[float], reference: Sequence[float]) -> tuple[float, ...]:
    """The same pose with each joint shifted by whole turns to lie nearest ``reference``,
    within the joint limits (a revolute joint's angle matters only modulo 2 pi)."""
    out = []
    for value, ref, limit in zip(q, reference, JOINT_LIMIT):
        best = value
        for turns in (-2, -1, 0, 1, 2):
            candidate = value + turns * 2 * math.pi
            if abs(candidate) <= limit + 1e-12 and abs(candidate - ref) < abs(best - ref):
                best = candidate
        out.append(best)
    return tuple(out)
