"""The UR5e platform FMU driven alone through the FMI API (fmpy's FMU3Slave, and the C host).

The driver below acts as a master: the constant clock ``sample`` ticks at every multiple of
0.5 s, operations are set as input clocks with their clocked arguments at given times, early
returns are honoured (the next step starts at lastSuccessfulTime). Expected values come from
the case study's geometry and the event definitions, not from earlier runs.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
import zipfile
from dataclasses import dataclass

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmpy.validation import validate_fmu as fmpy_validate

from support import pyfmu as testing
from robogen.fmu.validate import validate_fmu
from robogen.platforms.kinematics import HOME, grid_position, rotation_from_vector, rotation_vector, grid_pose
from robogen.platforms.ur5e import COMPLETION_TOLERANCE, STOPPED_SPEED

SAMPLE = 0.5
DT = 1.0 / 240.0
OUTPUT_CLOCKS = ("feasibleMoveDiscreteCommand", "nonfeasibleMoveDiscreteCommand", "moveCompleted", "robotStopped",
                 "collision")
SCENARIO = [(5.0, (0, 23, 1)), (10.5, (3, 20, 2)), (15.0, (8, 10, 0)), (23.5, (1, 13, 0))]


@dataclass
class Instant:
    time: float
    early: bool              # reached through an early return
    clocks: frozenset[str]   # output clocks active in the instant
    q: np.ndarray
    dq: np.ndarray
    ee: np.ndarray           # x, y, z, rx, ry, rz
    steps: int


def drive(path, commands, stop: float, *, parameters=None, name="platform") -> list[Instant]:
    """Run the FMU to ``stop``; ``commands`` is a list of (time, operation, arguments)."""
    fmu = testing.Fmu(path, name)
    if parameters:
        fmu.set_f64(**parameters)
    fmu.slave.enterInitializationMode(startTime=0.0, stopTime=stop)
    fmu.slave.exitInitializationMode()
    pending = sorted(commands, key=lambda c: c[0])
    instants: list[Instant] = []
    t, early = 0.0, False
    while True:
        if abs(t / SAMPLE - round(t / SAMPLE)) < 1e-9:
            fmu.set_clocks("sample")
        while pending and abs(pending[0][0] - t) < 1e-9:
            _, operation, arguments = pending.pop(0)
            fmu.set_clocks(operation)
            if operation == "movediscrete":
                fmu.set_i64(dict(zip(("movediscrete.target_X", "movediscrete.target_Y", "movediscrete.target_Z"),
                                     arguments)))
            elif operation == "movejoint":
                fmu.set_f64(**{f"movejoint.target_q{i}": v for i, v in enumerate(arguments)})
            elif operation == "movecartesian":
                fmu.set_f64(**{f"movecartesian.target_{k}": v for k, v in zip(("x", "y", "z", "rx", "ry", "rz"),
                                                                             arguments)})
            elif operation == "setvelocity":
                fmu.set_f64(**{"setvelocity.target_v": arguments})
        clocks = fmu.active(*OUTPUT_CLOCKS)
        values = fmu.f64(*(f"q{i}" for i in range(6)), *(f"dq{i}" for i in range(6)),
                         "ee_x", "ee_y", "ee_z", "ee_rx", "ee_ry", "ee_rz")
        instants.append(Instant(t, early, frozenset(clocks), np.array(values[:6]), np.array(values[6:12]),
                                np.array(values[12:]), fmu.i64("physics_steps")[0]))
        fmu.slave.updateDiscreteStates()
        assert fmu.active(*OUTPUT_CLOCKS) == set()  # never sticky
        fmu.slave.enterStepMode()
        if t >= stop - 1e-9:
            break
        grid = (math.floor(t / SAMPLE + 1e-9) + 1) * SAMPLE
        target = min([grid, stop] + [c[0] for c in pending if c[0] > t + 1e-9])
        event, terminate, early, last = fmu.slave.doStep(t, target - t)
        assert early == (last < target - 1e-9)
        t = last
        fmu.slave.enterEventMode()
    fmu.close()
    return instants


def first(instants, clock, after=-1.0) -> Instant | None:
    return next((i for i in instants if i.time > after and clock in i.clocks), None)


def at(instants, time) -> Instant:
    return next(i for i in instants if abs(i.time - time) < 1e-9)


def last_before(instants, time) -> Instant:
    return [i for i in instants if i.time < time - 1e-9][-1]


@pytest.fixture(scope="module")
def scenario(platform_fmu) -> list[Instant]:
    return drive(platform_fmu, [(t, "movediscrete", cell) for t, cell in SCENARIO], 28.0)


def test_the_platform_fmu_passes_both_validators(platform_fmu):
    assert fmpy_validate(str(platform_fmu)) == []
    assert [d.render() for d in validate_fmu(platform_fmu) if d.is_error] == []


def test_sample_clock_interval_is_the_packaging_setting(platform_fmu):
    with zipfile.ZipFile(platform_fmu) as z:
        root = ET.fromstring(z.read("modelDescription.xml"))
    sample = next(v for v in root.find("ModelVariables") if v.attrib["name"] == "sample")
    assert (sample.attrib["intervalVariability"], sample.attrib["intervalDecimal"]) == ("constant", "0.5")


@pytest.mark.parametrize("index", range(4))
def test_each_scenario_target_is_reached_within_1_mm(scenario, index):
    command_time, cell = SCENARIO[index]
    settled = last_before(scenario, SCENARIO[index + 1][0] if index < 3 else 1e9)
    position, rotation = grid_pose(*cell)
    assert np.linalg.norm(settled.ee[:3] - position) < 1e-3
    flange_z = rotation_from_vector(settled.ee[3:])[:, 2]
    assert np.linalg.norm(flange_z - rotation[:, 2]) < 1e-3  # pointing along (0, sqrt2/2, -sqrt2/2)
    assert np.abs(settled.dq).max() < 1e-3


@pytest.mark.parametrize("index", range(4))
def test_feasibility_is_answered_in_the_instant_of_the_command(scenario, index):
    command_time, _ = SCENARIO[index]
    instant = at(scenario, command_time)
    assert "feasibleMoveDiscreteCommand" in instant.clocks
    assert "nonfeasibleMoveDiscreteCommand" not in instant.clocks


@pytest.mark.parametrize("index", range(4))
def test_completion_and_stop_events_only_once_the_new_target_is_reached(scenario, index):
    command_time, _ = SCENARIO[index]
    next_command = SCENARIO[index + 1][0] if index < 3 else 1e9
    final_q = last_before(scenario, next_command).q
    # Not in the command's own instant (the previous target was reached: the reference's defect).
    assert not {"moveCompleted", "robotStopped"} & at(scenario, command_time).clocks
    completed = first(scenario, "moveCompleted", after=command_time)
    stopped = first(scenario, "robotStopped", after=command_time)
    assert command_time < completed.time <= stopped.time < next_command
    # Raised at the physics step where the condition became true, not at a sample instant.
    assert completed.early and completed.time % SAMPLE > 1e-6
    assert completed.steps == round(completed.time / DT)
    assert np.abs(completed.q - final_q).max() < COMPLETION_TOLERANCE + 1e-4
    assert np.abs(stopped.dq).max() < STOPPED_SPEED
    for instant in scenario:
        if command_time <= instant.time < completed.time:
            assert not {"moveCompleted", "robotStopped"} & instant.clocks
            assert np.abs(instant.q - final_q).max() >= COMPLETION_TOLERANCE - 1e-4  # still on its way


def test_events_are_level_sensitive_at_every_sample(scenario):
    completed = first(scenario, "moveCompleted", after=SCENARIO[2][0])
    samples = [i for i in scenario if completed.time < i.time < SCENARIO[3][0] and not i.early]
    assert len(samples) >= 15
    assert all({"moveCompleted", "robotStopped"} <= i.clocks for i in samples)
    assert not any("collision" in i.clocks for i in scenario)


def test_unreachable_and_off_table_cells_are_not_feasible(platform_fmu):
    cells = [(1.0, (0, 0, 0)), (2.0, (16, 5, 0)), (3.0, (3, 4, -1)), (4.0, (0, 23, 20))]
    run = drive(platform_fmu, [(t, "movediscrete", cell) for t, cell in cells], 5.0)
    for t, _ in cells:
        instant = at(run, t)
        assert "nonfeasibleMoveDiscreteCommand" in instant.clocks
        assert "feasibleMoveDiscreteCommand" not in instant.clocks
    assert not any("nonfeasibleMoveDiscreteCommand" in i.clocks for i in run if i.time not in (1.0, 2.0, 3.0, 4.0))
    assert np.abs(run[-1].q - np.array(HOME)).max() < 1e-3  # never moved
    assert "robotStopped" in run[-1].clocks and "moveCompleted" not in run[-1].clocks


def test_a_repeated_movediscrete_is_the_same_command(platform_fmu):
    once = drive(platform_fmu, [(1.0, "movediscrete", (8, 10, 0))], 3.0)
    repeated = drive(platform_fmu, [(1.0, "movediscrete", (8, 10, 0)), (1.1, "movediscrete", (8, 10, 0)),
                                    (1.5, "movediscrete", (8, 10, 0))], 3.0)
    assert all("feasibleMoveDiscreteCommand" in at(repeated, t).clocks for t in (1.0, 1.1, 1.5))
    # One motion: it completes at the same physics step as without the repetitions.
    assert first(repeated, "moveCompleted").time == first(once, "moveCompleted").time
    assert first(repeated, "moveCompleted").steps == first(once, "moveCompleted").steps


def test_stop_holds_the_arm_and_robot_stopped_takes_the_absolute_velocity(platform_fmu):
    away = list(HOME)
    away[0] -= 2.5  # joint 1 turns in the negative direction at the speed limit
    run = drive(platform_fmu, [(0.0, "movejoint", away), (0.5, "stop", None)], 3.0)
    at_stop = at(run, 0.5)
    assert at_stop.dq[0] == pytest.approx(-math.pi, abs=0.05)
    # A signed test (|q'| not taken) would call this arm stopped.
    assert "robotStopped" not in at_stop.clocks and "moveCompleted" not in at_stop.clocks
    stopped = first(run, "robotStopped", after=0.5)
    assert stopped.time < 1.0 and np.abs(stopped.dq).max() < STOPPED_SPEED
    final = run[-1]
    assert final.q[0] == pytest.approx(at_stop.q[0], abs=1e-3)  # held where it was, not at the target
    assert abs(final.q[0] - away[0]) == pytest.approx(2.5 - math.pi * 0.5, abs=0.05)  # 0.5 s at pi rad/s
    assert first(run, "moveCompleted") is None


def test_collision_with_the_mounting_plane_is_raised_at_contact(platform_fmu):
    into_plane = list(HOME)
    into_plane[1] = 0.3  # the upper arm swings down through the plane z = 0
    run = drive(platform_fmu, [(0.0, "movejoint", into_plane)], 2.0)
    hit = first(run, "collision")
    assert hit is not None and hit.early and 0.0 < hit.time < 1.0
    assert not any("collision" in i.clocks for i in run if i.time < hit.time)
    assert all("collision" in i.clocks for i in run if i.time > hit.time and not i.early)  # still pressing
    assert first(run, "moveCompleted") is None  # the plane blocks the motion
    assert run[-1].q[1] < 0.3 - COMPLETION_TOLERANCE


def test_setvelocity_limits_the_joint_speed(platform_fmu):
    turned = list(HOME)
    turned[5] += 1.0
    run = drive(platform_fmu, [(0.0, "setvelocity", 0.5), (0.0, "movejoint", turned)], 3.0)
    assert at(run, 1.0).dq[5] == pytest.approx(0.5, abs=0.01)
    assert at(run, 1.0).q[5] - HOME[5] == pytest.approx(0.5, abs=0.02)
    done = first(run, "moveCompleted")
    assert 1.95 < done.time < 2.1  # 1 rad at 0.5 rad/s


def test_movecartesian_reaches_a_pose(platform_fmu):
    position = grid_position(3, 20, 2)
    _, rotation = grid_pose(3, 20, 2)
    pose = [*position, *rotation_vector(rotation)]
    run = drive(platform_fmu, [(0.5, "movecartesian", pose)], 3.0)
    assert np.linalg.norm(run[-1].ee[:3] - position) < 1e-3
    assert first(run, "moveCompleted", after=0.5) is not None


def test_physics_runs_on_its_own_fixed_step(platform_fmu):
    run = drive(platform_fmu, [], 100.0)
    assert run[-1].steps == 24000  # 100 s at 1/240 s
    fine = drive(platform_fmu, [], 2.0, parameters={"physics_step": 1.0 / 480.0})
    assert fine[-1].steps == 960


def test_invalid_parameters_are_refused_with_a_message(platform_fmu):
    fmu = testing.Fmu(platform_fmu, "bad")
    fmu.set_f64(physics_step=-1.0)
    fmu.slave.enterInitializationMode(startTime=0.0)
    with pytest.raises(FMICallException):
        fmu.slave.exitInitializationMode()
    assert fmu.messages(3) == ["physics_step must be in (0, 0.1] s, got -1.0"]
    fmu.slave.freeInstance()


def test_two_platforms_in_one_process_have_their_own_physics(platform_fmu):
    a, b = (testing.Fmu(platform_fmu, name, early_return=False) for name in "ab")
    for fmu in (a, b):
        fmu.slave.enterInitializationMode(startTime=0.0)
        fmu.slave.exitInitializationMode()
    a.set_clocks("movediscrete")
    a.set_i64({"movediscrete.target_X": 8, "movediscrete.target_Y": 10, "movediscrete.target_Z": 0})
    for fmu in (a, b):
        fmu.slave.updateDiscreteStates()
        fmu.slave.enterStepMode()
        assert fmu.slave.doStep(0.0, 2.0)[2:] == (False, 2.0)  # no early return: reaches 2 s
    assert np.linalg.norm(np.array(a.f64("ee_x", "ee_y", "ee_z")) - grid_position(8, 10, 0)) < 1e-3
    assert b.f64(*(f"q{i}" for i in range(6))) == pytest.approx(HOME, abs=1e-3)
    a.close()
    b.close()


def test_the_c_host_runs_the_platform_with_rtld_local(platform_fmu, host, tmp_path):
    """PyBullet and numpy are extension modules: imported inside a C host that loaded the FMU
    with RTLD_LOCAL, in a process without Python or a virtual environment."""
    directory = testing.unzip(platform_fmu, tmp_path / "platform")
    root = ET.parse(directory / "modelDescription.xml").getroot()
    vr = {v.attrib["name"]: v.attrib["valueReference"] for v in root.find("ModelVariables")}
    token = root.attrib["instantiationToken"]
    out = testing.run_host(host, [
        f"load {directory}/binaries/x86_64-linux/ur5e_platform.so",
        f"instantiate p {token} {directory}/resources/ 1 0",
        "init 0 0", "exit_init 0",
        f"set_clock 0 {vr['movediscrete']}",
        f"set_i64 0 {vr['movediscrete.target_X']} 8", f"set_i64 0 {vr['movediscrete.target_Y']} 10",
        f"set_i64 0 {vr['movediscrete.target_Z']} 0",
        f"get_clock 0 {vr['feasibleMoveDiscreteCommand']}",
        "update 0", "step_mode 0", "do_step 0 0 3",
        f"get_f64 0 {vr['ee_x']}", f"get_f64 0 {vr['ee_y']}", f"get_f64 0 {vr['ee_z']}",
        "terminate 0", "free 0",
    ])
    assert "instance 0" in out and "clock 1" in out
    reached = [float(line.split()[1]) for line in out.splitlines() if line.startswith("float64")]
    assert np.linalg.norm(np.array(reached) - grid_position(8, 10, 0)) < 1e-3
