"""UR5e kinematics from the DH table and the case study's grid mapping, against values computed
by hand (the published UR5e DH table and the case study's grid)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from robogen.platforms.kinematics import (
    GRID_ORIENTATION, HOME, IK_SEED, forward, grid_in_table, grid_pose, grid_position, inverse, jacobian,
    nearest_equivalent, rotation_from_vector, rotation_vector, rotation_vector_of_quaternion, wrap,
)

SCENARIO = [(0, 23, 1), (3, 20, 2), (8, 10, 0), (1, 13, 0)]


def test_zero_pose_by_hand():
    # All angles 0: the arm lies along -x (a2 + a3 = -0.8172), the wrist offsets d4 + d6 go
    # along -y (frame 1 turns z into -y) and d5 along -z: flange at (-0.8172, -0.2329, 0.0628),
    # flange axes x = (1, 0, 0), y = (0, 0, 1), z = (0, -1, 0).
    flange = forward([0.0] * 6)
    assert flange[:3, 3] == pytest.approx([-0.8172, -0.2329, 0.0628], abs=1e-12)
    assert flange[:3, :3] == pytest.approx(np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]]), abs=1e-12)


def test_home_pose_points_the_flange_down_above_the_plane():
    flange = forward(HOME)
    assert flange[:3, 2] == pytest.approx([0, 0, -1], abs=1e-12)
    assert flange[2, 3] > 0.3


# The worked table of the case study (§4), metres, 4 decimals.
@pytest.mark.parametrize("cell, expected", [
    ((0, 23, 1), (-0.072, 0.4533, 0.5523)),
    ((3, 20, 2), (0.078, 0.3118, 0.4815)),
    ((8, 10, 0), (0.578, 0.2058, 0.2341)),
    ((1, 13, 0), (0.428, 0.4533, 0.4815)),
])
def test_grid_to_position_with_the_45_degree_rotation(cell, expected):
    assert grid_position(*cell) == pytest.approx(expected, abs=5e-5)


def test_the_rotation_form_holds_for_the_last_column_too():
    # X = 15: y = 0.711 - 0.75 = -0.039, z = 0.02; y' = (y - z)/sqrt 2, z' = (y + z)/sqrt 2.
    assert grid_position(15, 0, 0)[1:] == pytest.approx([(-0.039 - 0.02) / math.sqrt(2), (-0.039 + 0.02) / math.sqrt(2)])


def test_grid_orientation_points_the_flange_along_the_case_study_axis():
    assert GRID_ORIENTATION[:, 2] == pytest.approx([0, math.sqrt(0.5), -math.sqrt(0.5)], abs=1e-15)


def test_table_bounds():
    assert grid_in_table(15, 23, 0) and grid_in_table(0, 0, 7)
    assert not grid_in_table(16, 0, 0) and not grid_in_table(0, 24, 0) and not grid_in_table(0, 0, -1)


@pytest.mark.parametrize("cell", SCENARIO)
def test_ik_reaches_each_scenario_target(cell):
    position, rotation = grid_pose(*cell)
    result = inverse(position, rotation, seeds=(IK_SEED,))
    assert result.converged
    flange = forward(result.q)
    assert np.linalg.norm(flange[:3, 3] - position) < 1e-9
    assert np.linalg.norm(rotation_vector(rotation @ flange[:3, :3].T)) < 1e-9
    assert all(-math.pi <= q <= math.pi for q in result.q)


@pytest.mark.parametrize("cell", [(0, 0, 0), (0, 23, 20), (15, 23, 0)])
def test_ik_reports_cells_out_of_reach(cell):
    # (0, 0, 0) lies 1.23 m from the shoulder, (0, 23, 20) 1.27 m: beyond the 0.85 m reach;
    # (15, 23, 0) is a point 4 cm from the base axis, inside the arm's own footprint.
    assert not inverse(*grid_pose(*cell)).converged


def test_jacobian_matches_finite_differences():
    q = np.array([0.3, -1.1, 1.4, -0.7, 0.5, 0.2])
    eps = 1e-7
    numeric = np.empty((6, 6))
    base = forward(q)
    for i in range(6):
        dq = np.zeros(6)
        dq[i] = eps
        moved = forward(q + dq)
        numeric[:3, i] = (moved[:3, 3] - base[:3, 3]) / eps
        numeric[3:, i] = rotation_vector(moved[:3, :3] @ base[:3, :3].T) / eps
    assert jacobian(q) == pytest.approx(numeric, abs=1e-5)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.floats(-3.0, 3.0), min_size=3, max_size=3))
def test_rotation_vector_round_trip(vector):
    v = np.array(vector)
    if np.linalg.norm(v) >= math.pi - 1e-3:
        v = v / np.linalg.norm(v) * (math.pi - 1e-3)
    assert rotation_vector(rotation_from_vector(v)) == pytest.approx(v, abs=1e-9)


def test_rotation_vector_near_half_turn():
    half = rotation_from_vector([0.0, math.pi, 0.0])
    assert abs(rotation_vector(half)[1]) == pytest.approx(math.pi)


def test_wrap_and_whole_turns():
    assert wrap(np.array([math.pi, -math.pi, 3 * math.pi, 0.1])) == pytest.approx([math.pi, math.pi, math.pi, 0.1])
    # joint 1 may go to -2 pi; the elbow (joint 3) stays within +-pi
    assert nearest_equivalent([3.0, 0, 3.0, 0, 0, 0], [-3.0, 0, -3.0, 0, 0, 0]) == pytest.approx(
        [3.0 - 2 * math.pi, 0, 3.0, 0, 0, 0])


def quaternion(v) -> tuple[float, float, float, float]:
    """The unit quaternion (x, y, z, w) of the rotation vector v: sin(angle/2) * axis, cos(angle/2)."""
    angle = float(np.linalg.norm(v))
    if angle == 0.0:
        return (0.0, 0.0, 0.0, 1.0)
    x, y, z = np.asarray(v) / angle * math.sin(angle / 2)
    return (float(x), float(y), float(z), math.cos(angle / 2))


def test_rotation_vector_of_quaternion_by_hand():
    r = math.sqrt(0.5)
    assert rotation_vector_of_quaternion(0.0, 0.0, 0.0, 1.0) == (0.0, 0.0, 0.0)
    assert rotation_vector_of_quaternion(0.0, 0.0, r, r) == pytest.approx((0.0, 0.0, math.pi / 2), abs=1e-15)
    assert rotation_vector_of_quaternion(0.0, 0.0, -r, -r) == pytest.approx((0.0, 0.0, math.pi / 2), abs=1e-15)  # -q
    assert rotation_vector_of_quaternion(1.0, 0.0, 0.0, 0.0) == (math.pi, 0.0, 0.0)  # a half turn about x
    # 120 degrees about (1, 1, 1): sin 60 / sqrt 3 = 1/2 each, cos 60 = 1/2
    third = 2 * math.pi / 3 / math.sqrt(3)
    assert rotation_vector_of_quaternion(0.5, 0.5, 0.5, 0.5) == pytest.approx((third, third, third), abs=1e-15)


def test_rotation_vector_of_quaternion_inverts_the_quaternion_of_a_rotation_vector():
    rng = np.random.default_rng(7)
    axes = [n / np.linalg.norm(n) for n in rng.normal(size=(100, 3))]
    angles = [1e-9, 1e-3, 1.0, 2.0, 3.0, math.pi - 1e-3, math.pi - 1e-9]  # near a half turn too
    for n in axes:
        for angle in angles:
            v = n * angle
            assert rotation_vector_of_quaternion(*quaternion(v)) == pytest.approx(tuple(v), rel=1e-12, abs=1e-15)
            # past a half turn: the same rotation, the other way round (angle in [0, pi]); not
            # for tiny angles, whose quaternion near a whole turn has too few digits left
            if angle < 1e-3:
                continue
            w = n * (2 * math.pi - angle)
            assert rotation_vector_of_quaternion(*quaternion(w)) == pytest.approx(tuple(-v), rel=1e-9, abs=1e-15)


def test_rotation_vector_of_quaternion_agrees_with_rotation_vector_of_its_matrix():
    rng = np.random.default_rng(11)
    for v in rng.normal(size=(200, 3)):
        expected = rotation_vector(rotation_from_vector(v))
        assert rotation_vector_of_quaternion(*quaternion(v)) == pytest.approx(tuple(expected), rel=1e-9, abs=1e-12)


@pytest.mark.parametrize("cell", [SCENARIO[1], (0, 0, 0)])
def test_a_search_done_once_per_process_gives_the_result_bit_for_bit(cell, monkeypatch):
    # a later instance of the platform (the next run, a campaign's next run) asks for the same
    # poses: the searches are not repeated, and what it gets is what the search gives
    from robogen.platforms import kinematics

    position, rotation = grid_pose(*cell)
    now = (0.3, -1.0, 1.2, -0.5, 0.4, 0.1)  # the arm's joints at the command
    monkeypatch.setattr(kinematics, "_SOLVED", {})
    first = inverse(position, rotation, seeds=(IK_SEED, now))
    searches = len(kinematics._SOLVED)
    assert searches == (1 if cell == SCENARIO[1] else 6)  # converged from the first seed; or every seed tried (4 spares)

    def no_search(*_args):
        raise AssertionError("searched again")

    monkeypatch.setattr(kinematics, "_levenberg_marquardt", no_search)
    again = inverse(position.copy(), rotation.copy(), seeds=(IK_SEED, now))
    assert again == first and again.q == first.q
    monkeypatch.undo()
    monkeypatch.setattr(kinematics, "_SOLVED", {})
    assert inverse(position, rotation, seeds=(IK_SEED, now)) == first  # searched anew: the same doubles
