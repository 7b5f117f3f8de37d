"""The controller FMU plays the plan at the exact planned times (nextEventTime, early return) and
counts what it receives."""

from __future__ import annotations


import pytest
from fmpy import read_model_description
from fmpy.validation import validate_fmu as fmpy_validate

from support import pyfmu as testing
from robogen.diagnostics import RobogenError
from robogen.fmu.validate import validate_fmu
from robogen.pyfmu.build import package
from support import ROOT

PLAN = ROOT / "models" / "ur5e" / "plan.toml"
TARGETS = ("moveDiscreteCommand.target_X", "moveDiscreteCommand.target_Y", "moveDiscreteCommand.target_Z")
CASE_STUDY_TIMES = [5.0, 10.5, 15.0, 23.5, 30.0, 35.5, 40.0, 48.5, 55.0, 60.5, 65.0, 73.5, 80.0, 85.5, 90.0, 98.5]


def started(path, stop=100.0, **kwargs):
    fmu = testing.Fmu(path, "controller", **kwargs)
    fmu.slave.enterInitializationMode(startTime=0.0, stopTime=stop)
    fmu.slave.exitInitializationMode()
    return fmu


def test_controller_passes_both_validators(controller_fmu):
    assert fmpy_validate(str(controller_fmu)) == []
    assert [d.render() for d in validate_fmu(controller_fmu) if d.is_error] == []


def test_commands_at_the_exact_planned_times_through_next_event_time(controller_fmu):
    fmu = started(controller_fmu)
    commands, t = [], 0.0
    while True:
        if fmu.clocks("moveDiscreteCommand")["moveDiscreteCommand"]:
            commands.append((t, tuple(fmu.i64(*TARGETS))))
        need_update, terminate, _, _, defined, next_time = fmu.slave.updateDiscreteStates()
        if need_update:
            continue
        fmu.slave.enterStepMode()
        if not defined:
            break
        _, _, early, t = fmu.slave.doStep(t, next_time - t)  # straight to the announced time
        assert not early and t == next_time
        fmu.slave.enterEventMode()
    assert [time for time, _ in commands] == CASE_STUDY_TIMES  # exact, not rounded to a grid
    assert [target for _, target in commands][:4] == [(0, 23, 1), (3, 20, 2), (8, 10, 0), (1, 13, 0)]
    assert fmu.i64("commands_sent") == [16]
    fmu.close()


def test_a_master_stepping_past_a_command_is_stopped_at_its_time(controller_fmu):
    fmu = started(controller_fmu)
    fmu.slave.updateDiscreteStates()
    fmu.slave.enterStepMode()
    assert fmu.slave.doStep(0.0, 4.0) == (False, False, False, 4.0)
    event, _, early, last = fmu.slave.doStep(4.0, 2.0)
    assert (event, early, last) == (True, True, 5.0)
    fmu.slave.enterEventMode()
    assert fmu.active("moveDiscreteCommand") == {"moveDiscreteCommand"}
    assert fmu.i64(*TARGETS) == [0, 23, 1]
    fmu.close()


def test_without_early_return_a_late_command_is_raised_with_a_warning(controller_fmu):
    fmu = started(controller_fmu, early_return=False)
    fmu.slave.updateDiscreteStates()
    fmu.slave.enterStepMode()
    event, _, early, last = fmu.slave.doStep(0.0, 5.5)
    assert (event, early, last) == (True, False, 5.5)
    fmu.slave.enterEventMode()
    assert fmu.active("moveDiscreteCommand") == {"moveDiscreteCommand"}
    assert "t=5.5: moveDiscreteCommand(0, 23, 1) (planned at 5 s)" in fmu.messages(1)
    fmu.close()


def test_received_events_are_counted(controller_fmu):
    fmu = started(controller_fmu)
    fmu.set_clocks("feasibleMoveDiscreteCommand", "robotStopped")
    assert fmu.i64("received_feasibleMoveDiscreteCommand", "received_robotStopped", "received_collision") == [1, 1, 0]
    fmu.slave.updateDiscreteStates()
    fmu.set_clocks("robotStopped")
    assert fmu.i64("received_robotStopped") == [2]
    fmu.close()


def test_a_bad_plan_is_refused_when_packaging_with_its_location(tmp_path):
    plan = tmp_path / "plan.toml"
    plan.write_text("[[command]]\ntime = 1.0\ntarget = [1, 2]\n")
    with pytest.raises(RobogenError) as failure:
        package("robogen.platforms.controller:PlanController", tmp_path / "c.fmu", [f"plan={plan}"])
    [diagnostic] = failure.value.diagnostics
    assert (diagnostic.span.path, diagnostic.span.line) == (str(plan), 3)
    with pytest.raises(RobogenError, match="not found"):
        package("robogen.platforms.controller:PlanController", tmp_path / "c.fmu", [f"plan={tmp_path}/none.toml"])


def test_the_plan_has_no_default_and_packaging_without_one_says_so(tmp_path):
    from robogen.platforms.controller import PlanController

    assert PlanController.plan is None and PlanController.settings()["plan"].required
    with pytest.raises(RobogenError, match=r"PlanController needs --set plan=VALUE: the setting 'plan' has no default"):
        package("robogen.platforms.controller:PlanController", tmp_path / "c.fmu")
    assert not (tmp_path / "c.fmu").exists()


def test_packaged_with_early_return_false_it_declares_none_and_still_keeps_the_planned_times(tmp_path):
    path = package("robogen.platforms.controller:PlanController", tmp_path / "c.fmu",
                   [f"plan={PLAN}", "early_return=false"]).path
    md = read_model_description(str(path))
    assert md.coSimulation.mightReturnEarlyFromDoStep is False
    fmu = started(path, early_return=False)
    *_, defined, next_time = fmu.slave.updateDiscreteStates()
    assert (defined, next_time) == (True, 5.0)  # the first command's time
    fmu.slave.enterStepMode()
    assert fmu.slave.doStep(0.0, next_time) == (True, False, False, 5.0)  # a master honouring nextEventTime
    fmu.slave.enterEventMode()
    assert fmu.active("moveDiscreteCommand") == {"moveDiscreteCommand"} and fmu.i64(*TARGETS) == [0, 23, 1]
    assert not fmu.messages(1)  # on time: no warning
    fmu.close()
