"""Abstract operations (tests/codegen/models/abstract.rct, abstractsim.rst): a definition without
nodes gives the model no behaviour to run, so its call leaves the FMU as a platform operation's
does - a triggered output clock named after the operation, one clocked output per parameter -
and control goes on at once (the operation terminates at once). Values are hand-calculated; the
interpreter's trace is the same (run_checked)."""

from __future__ import annotations

import pytest

from support.codegen_driver import Description, Tick, build, outputs_by_instant
from support.codegen_models import MODELS


def go(v: float) -> Tick:
    return Tick("go", {"go.value": v})


STOP = Tick("stop", {})


def move(x: float, n: int) -> dict:
    return {"moveTo": {"moveTo.x": x, "moveTo.n": n}}


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_an_abstract_operation_called_twice_ticks_its_clock_twice_with_the_arguments(builds, semantics):
    built = builds.get("abstract", semantics)
    outputs, trace = outputs_by_instant(built, {1: go(1.5), 2: go(2.0), 3: STOP, 4: go(-1.0)}, 6)
    # t1 (Idle -> Away) calls moveTo(v, k), t2 (Away -> Idle) moveTo(-v, k); k counts the calls;
    # stop takes t3 (Idle -> Idle), which calls halt(): a clock without clocked outputs
    assert outputs == {0: {}, 1: move(1.5, 1), 2: move(-2.0, 2), 3: {"halt": {}}, 4: move(-1.0, 3), 5: {}}
    assert trace.steps[-1].states["Mover.state"] == [n.id for n in built.fmu.machines[0].nodes if n.label == "Away"][0]


def test_the_clocks_of_abstract_operations_are_triggered_outputs_named_after_them(builds):
    desc: Description = builds.get("abstract", "exhaustive").desc
    assert desc.output_clocks == ["moveTo", "halt"]
    assert [(v.name, v.type, v.causality) for v in desc.clocked["moveTo"]] == [("moveTo.x", "Float64", "output"),
                                                                               ("moveTo.n", "UInt64", "output")]
    assert desc.clocked["halt"] == []
    described = {v.name: v.description for v in desc.md.modelVariables}
    assert described["moveTo"] == "call of abstract operation moveTo"
    assert described["moveTo.n"] == "argument n of abstract operation moveTo"


def test_a_machine_boundary_calls_the_abstract_operations_of_its_controller(tmp_path):
    built = build([MODELS / "abstract.rct"], tmp_path, machine="Mover")
    outputs, _ = outputs_by_instant(built, {1: go(0.5), 2: STOP, 3: go(3.0)}, 4)
    assert outputs == {0: {}, 1: move(0.5, 1), 2: {"halt": {}}, 3: move(3.0, 2)}  # stop takes t4 (Away -> Idle)
    assert built.desc.output_clocks == ["moveTo", "halt"]


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_robosim_calls_of_an_abstract_operation(builds, semantics):
    outputs, _ = outputs_by_instant(builds.get("abstractsim", semantics), {1: go(1.5), 2: go(2.0)}, 4)
    # the cycle that samples go decides the exec transition; its action (and call) runs at the
    # start of the next cycle
    assert outputs == {0: {}, 1: {}, 2: move(1.5, 1), 3: move(-2.0, 2)}
