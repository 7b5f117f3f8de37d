"""Sets at a capacity of 2: an overflow is an fmi3Error whose message names the expression and
its model line, in the FMU as in the reference interpreter, and never corrupts memory."""

from __future__ import annotations

from codegen_driver import FmuRunner, Instant, Scenario, Tick, build, interpret
from robogen.ir.lower import LoweringOptions

MODEL = """\
import set_toolkit::*
import sequence_toolkit::*
stm Grow {
	var s: Set(int) = {1}
	var v: int
	event add: int
	event size_: nat
	initial i
	state Idle { }
	transition t0 { from i to Idle }
	transition t1 { from Idle to Idle trigger add?v action s = union(s, {v}) ; size_!size(s) }
}
"""


def test_a_capacity_of_2_overflows_at_the_third_member(tmp_path):
    path = tmp_path / "grow.rct"
    path.write_text(MODEL)
    built = build([path], tmp_path / "c2", options=LoweringOptions(capacity=2))
    add = [Tick("add", {"add.value": v}) for v in (2, 2, -5)]
    # {1} + 2 = {1, 2}; + 2 again changes nothing; + -5 would be {-5, 1, 2}: 3 > 2
    scenario = Scenario([Instant(True, early=(t,)) for t in add], half=False)
    runner = FmuRunner(built.folder)
    try:
        got = runner.run(scenario)
    finally:
        runner.close()
    expected = interpret(built.fmu, scenario, runner.desc)
    assert got.comparable() == expected.comparable()
    message = "more than 2 elements (the capacity) in union(s, {v}) at grow.rct:11"
    assert expected.error is not None and message in expected.error.where
    assert got.error is not None and message in got.error.where, got.error.where
    assert got.error.instant == 2
    sizes = [s.outputs["size_"]["size_.value"] for s in got.steps if "size_" in s.outputs]
    assert sizes == [2, 2]
    last = got.steps[-1].variables
    assert last["Grow.s.elements"] == [1, 2] and last["Grow.s.size"] == 2
