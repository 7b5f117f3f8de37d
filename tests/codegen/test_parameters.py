"""Constants the model leaves without a value become FMU parameters (tests/codegen/models/gripper.rst,
shaped like the case study's d-model with its gripper branch).

Without any --set the model packages: each such constant is a fixed parameter whose start value
is its type's default (0.0 for these reals), with one located warning naming it. An importer
sets the parameters in Initialization Mode and the platform operations carry those values; set
later, the FMU refuses them. For move commands the gripper model calls the same platform
operations in the same instants as the case study's own d-model (models/ur5e/ur5e.rst).
"""

from __future__ import annotations

import re
from fractions import Fraction

import pytest

from support.codegen_driver import FmuRunner, Instant, Scenario, Tick, run_checked
from support.codegen_models import TEST_MODELS
from robogen.codegen.api import lower_paths
from robogen.cosim import fmi3

GRIP = TEST_MODELS["gripper"].path
CONSTANTS = ["close_diameter", "close_speed", "close_force", "open_diameter", "open_speed", "open_force", "velocity"]
SETTINGS = {"Gripper.close_diameter": 0.08, "Gripper.close_speed": 0.1, "Gripper.close_force": 20.0,
            "Gripper.open_diameter": 0.085, "Gripper.open_speed": 0.2, "Gripper.velocity": 0.25}


def test_each_constant_without_value_is_a_parameter_with_one_warning():
    fmu, _ = lower_paths([GRIP])
    warned = [(w.span.line, w.message) for w in fmu.warnings]
    assert [re.match(r"constant '(\w+)' has no value", m).group(1) for _, m in warned] == CONSTANTS
    assert [line for line, _ in warned] == [40, 40, 40, 41, 41, 41, 83]  # where each is declared
    assert warned[0][1] == ("constant 'close_diameter' has no value: it becomes FMU parameter 'Gripper.close_diameter' "
                            "with start 0.0; set it with --set close_diameter=... or in the importer")
    assert [(p.fmi_name, p.value, p.free) for p in fmu.params] == [(f"Gripper.{c}", 0, True) for c in CONSTANTS]
    # --set gives a value at generation time: no parameter without a value, no warning for it
    fmu, _ = lower_paths([GRIP], options=_options(velocity="0.5"))
    assert [p.value for p in fmu.params if p.var.name == "velocity"] == [0.5]
    assert not any("'velocity'" in w.message for w in fmu.warnings) and len(fmu.warnings) == 6


def _options(**settings):
    from robogen.ir.lower import LoweringOptions

    return LoweringOptions(settings=settings)


def test_the_description_declares_fixed_parameters_with_default_starts(built):
    xml = built("gripper", "exhaustive").sources["modelDescription.xml"]
    for c in CONSTANTS:
        assert re.search(rf'<Float64 name="Gripper.{c}" [^>]*causality="parameter" variability="fixed" start="0.0"', xml), c


CLOSE, CLOSED = Tick("closeGripperCommand", {}), Tick("gripperClosed", {})
OPEN, OPENED = Tick("openGripperCommand", {}), Tick("gripperOpened", {})


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_parameters_set_in_initialization_reach_the_operations(built, semantics):
    """The story, one cycle a second: close at t=1, closed at t=3, open at t=4, opened at t=5.
    By hand: t=0 the initial transition calls setvelocity(velocity); t=1 pick with the close
    settings; t=4 place with the open settings (open_force left at its start value 0.0)."""
    b = built("gripper", semantics)
    inputs = {1: CLOSE, 3: CLOSED, 4: OPEN, 5: OPENED}
    scenario = Scenario([Instant(True, (inputs[t],) if t in inputs else ()) for t in range(7)], half=False)
    trace, default = run_checked(b, scenario, SETTINGS), run_checked(b, scenario)
    assert trace.error is None, trace.error
    calls = {s.instant: s.outputs for s in trace.steps if s.outputs}
    assert calls == {
        0: {"setvelocity": {"setvelocity.target_v": 0.25}},
        1: {"pick": {"pick.diameter": 0.08, "pick.speed": 0.1, "pick.force": 20.0}},
        4: {"place": {"place.diameter": 0.085, "place.speed": 0.2, "place.force": 0.0}},
    }
    nodes = b.fmu.machines[0].nodes
    assert [nodes[s.states["Gripper.state"]].label for s in trace.steps if not s.need] == \
        ["Idle", "Closed", "Closed", "Idle", "Opened", "Idle", "Idle"]
    # without settings the start values (0.0) go out
    assert {s.instant: s.outputs for s in default.steps if s.outputs}[1] == \
        {"pick": {"pick.diameter": 0.0, "pick.speed": 0.0, "pick.force": 0.0}}


def test_a_fixed_parameter_cannot_be_set_after_initialization(built):
    b = built("gripper", "exhaustive")
    runner = FmuRunner(b.folder)
    try:
        runner.run(Scenario([Instant(True)], half=False), parameters={"Gripper.velocity": 0.5})
        var = runner.desc.by_name["Gripper.velocity"]
        buf = fmi3.value_array("Float64", 1)
        buf[0] = 1.0
        with pytest.raises(fmi3.FMI3Error):
            runner.inst._call("fmi3SetFloat64", fmi3.vr_array([var.vr]), 1, buf, 1)
        assert any("Gripper.velocity" in e for e in runner.errors)
    finally:
        runner.close()


MOVE_INPUTS = {1: Tick("moveDiscreteCommand", {"moveDiscreteCommand.target_X": 4, "moveDiscreteCommand.target_Y": -2,
                                               "moveDiscreteCommand.target_Z": 7}),
               2: Tick("feasibleMoveDiscreteCommand", {}), 4: Tick("moveCompleted", {}), 5: Tick("robotStopped", {}),
               7: Tick("moveDiscreteCommand", {"moveDiscreteCommand.target_X": 1, "moveDiscreteCommand.target_Y": 1,
                                               "moveDiscreteCommand.target_Z": 1}),
               8: Tick("nonfeasibleMoveDiscreteCommand", {})}


def _arm_calls(b, semantics_steps) -> dict[int, list]:
    """The calls of movediscrete and stop by instant (setvelocity, the gripper's own, left out)."""
    out: dict[int, list] = {}
    for s in semantics_steps:
        for name, values in s.outputs.items():
            if name in ("movediscrete", "stop"):
                out.setdefault(s.instant, []).append((name, values))
    return out


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_move_commands_give_the_case_study_trace(built, semantics):
    """A feasible move, then an infeasible one: both models call movediscrete at t=1 and t=2
    (the cycle at t=2 first completes the exec self-loop decided at t=1, re-entering ArmMove,
    then sees the verdict), stop at t=4, and for the second command movediscrete at t=7 and at
    t=8, whose verdict rejects it."""
    scenario = Scenario([Instant(True, (MOVE_INPUTS[t],) if t in MOVE_INPUTS else ()) for t in range(10)], half=False)
    traces = {}
    for name in ("gripper", "ur5e"):
        traces[name] = run_checked(built(name, semantics), scenario)
        assert traces[name].error is None
    ours = _arm_calls(built("gripper", semantics), traces["gripper"].steps)
    assert ours == _arm_calls(built("ur5e", semantics), traces["ur5e"].steps)
    move = {"movediscrete.target_X": 4, "movediscrete.target_Y": -2, "movediscrete.target_Z": 7}
    second = {"movediscrete.target_X": 1, "movediscrete.target_Y": 1, "movediscrete.target_Z": 1}
    assert ours == {1: [("movediscrete", move)], 2: [("movediscrete", move)], 4: [("stop", {})],
                    7: [("movediscrete", second)], 8: [("movediscrete", second)]}


def test_constants_that_operations_need_are_parameters_of_the_machine(built):
    """opconsts.rct: clamp(r) reports min(r, limit) + bias, scale(r) sends scaled 3 r. With limit = 5
    and bias = 100: readings 9 and 3 give 105 and 103; without settings both start at 0."""
    b = built("opconsts", "exhaustive")
    assert [(p.fmi_name, p.free) for p in b.fmu.params] == [("Clamper.clamp.bias", True), ("Clamper.limit", True)]
    assert [w.span.line for w in b.fmu.warnings] == [25, 8]
    reading = lambda v: Instant(True, (Tick("reading", {"reading.value": v}),))  # noqa: E731
    scenario = Scenario([reading(9), reading(3)], half=False)
    got = run_checked(b, scenario, {"Clamper.limit": 5, "Clamper.clamp.bias": 100})
    assert [s.outputs for s in got.steps] == [{"report": {"report.value": 105}, "scaled": {"scaled.value": 27}},
                                             {"report": {"report.value": 103}, "scaled": {"scaled.value": 9}}]
    assert [s.outputs["report"] for s in run_checked(b, scenario).steps] == [{"report.value": 0}] * 2


RECORDS = """\
datatype Pose {
	x: real
	y: real
	label: string
}
enumeration Cmd {
	Stop
	Move(real)
}
stm Arm {
	const home: Pose
	const first: Cmd
	event go
	event at: real
	event moving: boolean
	event named: string
	initial i
	state Idle { }
	transition t0 { from i to Idle }
	transition t1 { from Idle to Idle trigger go action at!(home.x + home.y) ; moving!(first != Stop) ; named!home.label }
}
"""


def test_a_record_constant_without_a_value_is_a_parameter_per_field(tmp_path):
    from support.codegen_driver import build

    path = tmp_path / "arm.rct"
    path.write_text(RECORDS)
    b = build([path], tmp_path / "arm")
    assert [(w.span.line, w.message) for w in b.fmu.warnings] == [
        (11, "constant 'home' has no value: it becomes FMU parameter 'Arm.home' with start zero; "
             "set its fields in the importer ('Arm.home.<field>')"),
        (12, "constant 'first' has no value: it becomes FMU parameter 'Arm.first' with start zero; "
             "set its fields in the importer ('Arm.first.<field>')")]
    xml = b.sources["modelDescription.xml"]
    for declared in ('<Float64 name="Arm.home.x" valueReference="', '<String name="Arm.home.label" valueReference="',
                     '<Enumeration name="Arm.first.tag" valueReference="', '<Float64 name="Arm.first.Move_1" valueReference="'):
        assert declared in xml
    go = Scenario([Instant(True, (Tick("go", {}),))], half=False)
    # the defaults: home = (0.0, 0.0, ""), first = Stop
    outputs = run_checked(b, go).steps[0].outputs
    assert (outputs["at"]["at.value"], outputs["moving"]["moving.value"], outputs["named"]["named.value"]) == (0.0, False, "")
    # the importer's values, field by field: home.x + home.y = 3.5, first = Move(0.5) is not Stop
    given = {"Arm.home.x": 1.5, "Arm.home.y": 2.0, "Arm.home.label": "dock", "Arm.first.tag": 1, "Arm.first.Move_1": 0.5}
    outputs = run_checked(b, go, parameters=given).steps[0].outputs
    assert (outputs["at"]["at.value"], outputs["moving"]["moving.value"], outputs["named"]["named.value"]) == (3.5, True, "dock")


def test_constant_values_are_computed_as_the_model_writes_them(tmp_path):
    """Found by the model fuzzer: `[| -2.0 + 0.0, 3.75 |]` was "not computable" (the evaluator
    computed a / b for every operator, and 0.0 divides nothing); vector arithmetic and negation
    were not computed at all, and integers did not wrap as they do at run time."""
    model = tmp_path / "k.rct"
    model.write_text("stm K {\n"
                     "\tconst a: vector(real, 2) = [| -2.0 + 0.0, 3.75 |]\n"
                     "\tconst b: vector(int, 2) = [| 1, 2 |] + 2 * [| 3, -4 |]\n"
                     "\tconst c: vector(int, 2) = -b - [| 1, 1 |]\n"
                     "\tconst d: int = -(3 - 10) * 2\n"
                     "\tconst e: nat = 0 - 1\n"
                     "\tconst f: int = 4611686018427387904 * 2\n"
                     "\tinitial i\n\tstate A { }\n\ttransition t0 { from i to A }\n}\n")
    fmu, _ = lower_paths([model])
    values = {p.var.name: p.value for p in fmu.params}
    assert values == {"a": [-2, Fraction(15, 4)], "b": [7, -6], "c": [-8, 5], "d": 14, "e": 2**64 - 1, "f": -(2**63)}
