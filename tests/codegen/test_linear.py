"""Vector and matrix arithmetic, % on reals, record literals that leave fields out and nat
comparisons decided by the type (tests/codegen/models/linear.rst), against values computed by
hand; the FMU and the interpreter agree on each run."""

from __future__ import annotations

import pytest

from support.codegen_driver import Instant, Scenario, Tick, run_checked


def outputs(trace) -> dict[int, dict]:
    return {s.instant: s.outputs for s in trace.steps if s.outputs}


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_vector_and_matrix_arithmetic(built, semantics):
    """u = (3, -4), w = (1, 2), m the quarter turn ((0, -1), (1, 0)): mm = m * m = -I,
    mm * w + m * u + shift = (-1, -2) + (4, 3) + (1, -1) = (4, 0), u * w = 3 - 8 = -5,
    r * (2.0, 2.0) = 1.0 + 3.0. The constants start with their values (row-major)."""
    b = built("linear", semantics)
    scenario = Scenario([Instant(True, (Tick("v", {"v.value": [1, 2]}),)), Instant(True)], half=False)
    got = outputs(run_checked(b, scenario))
    assert got[1] == {
        "sum": {"sum.value": [4, -2]}, "diff": {"diff.value": [2, -6]}, "neg": {"neg.value": [-1, -2]},
        "scaled": {"scaled.value": [2, 4]}, "rotated": {"rotated.value": [4, 0]}, "dot": {"dot.value": -5},
        "twice": {"twice.value": 4.0}, "always": {"always.value": True}, "never": {"never.value": False},
    }
    xml = b.sources["modelDescription.xml"]
    assert 'name="Lin.m" valueReference=' in xml and 'start="0 -1 1 0"' in xml and 'start="1 -1"' in xml
    assert "n >= " not in b.sources["sources/model.c"] and "n < " not in b.sources["sources/model.c"]


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_the_importers_values_of_vector_and_matrix_constants_hold(built, semantics):
    """m and shift are FMU parameters: set in Initialization Mode to the identity and (10, 20),
    mm = I and rotated = w + u + shift = (1, 2) + (3, -4) + (10, 20) = (14, 18) (their
    initialisers do not overwrite the importer's values when Initialization Mode ends)."""
    b = built("linear", semantics)
    scenario = Scenario([Instant(True, (Tick("v", {"v.value": [1, 2]}),)), Instant(True)], half=False)
    got = outputs(run_checked(b, scenario, parameters={"Lin.m": [1, 0, 0, 1], "Lin.shift": [10, 20]}))
    assert got[1]["rotated"] == {"rotated.value": [14, 18]}


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_real_remainder_and_a_record_with_a_field_left_out(built, semantics):
    """7.0 % 2.5 = 2.0 and -7.5 % 2.0 = -1.5 (the sign of the dividend, as on integers); Reading
    without count gets count = 0; -7.5 % 0.0 is a division by zero: a run-time error."""
    b = built("linear", semantics)
    scenario = Scenario([Instant(True, (Tick("x", {"x.value": 7.0}),)), Instant(True, (Tick("y", {"y.value": 2.0}),)),
                         Instant(True), Instant(True, (Tick("y", {"y.value": 0.0}),)), Instant(True)], half=False)
    trace = run_checked(b, scenario)
    got = outputs(trace)
    assert got[1] == {"rem": {"rem.value": 2.0},
                      "reading": {"reading.value": 7.0, "reading.count": 0, "reading.ok": True}}
    assert got[2] == {"rem": {"rem.value": -1.5}}
    assert trace.error is not None and trace.error.instant == 4


WIDENED = """\
stm V {
	cycleDef cycle == 1
	input context { event e3: Seq(real) event w: vector(nat, 2) }
	output context { event out: vector(int, 2) event same: boolean }
	var v47: vector(int, 1) = if true then [| 1 |] else [| 2 |] end
	var a: vector(int, 2) = [| 1, -1 |]
	var b: vector(nat, 2) = [| 3, 4 |]
	initial i
	state A { }
	transition t0 { from i to A }
	transition t1 { from A to A exec condition $w?b action a = b ; $out!(a + b) ; $same!(a == b) }
	transition t2 { from A to A exec condition not $w /\\ $e3.<> action $same!(v47 == [| 1 |]) }
	transition t3 { from A to A exec condition not $w /\\ not $e3.<> }
}
"""


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_a_vector_of_nats_is_used_as_one_of_ints(tmp_path, semantics):
    """Found by the model fuzzer: a vector(nat, 1) conditional as a vector(int, 1) initial value,
    and `$e3.<>` of a Seq(real) event, did not compile (incompatible C types). w = (5, 6) is bound
    to b and copied into a: out = a + b = (10, 12), a == b; an empty e3 matches <>, and v47 = (1)."""
    from robogen.differential import build
    from robogen.ir.lower import LoweringOptions

    model = tmp_path / "widened.rst"
    model.write_text(WIDENED)
    b = build([model], tmp_path / "w", options=LoweringOptions(semantics=semantics))
    scenario = Scenario([Instant(True), Instant(True, (Tick("w", {"w.value": [5, 6]}),)), Instant(True),
                         Instant(True, (Tick("e3", {"e3.value.size": 0, "e3.value.elements": [0.0] * 32}),)),
                         Instant(True), Instant(True)], half=False)
    sent = [s.outputs for s in run_checked(b, scenario).steps if s.outputs]
    assert sent == [{"out": {"out.value": [10, 12]}, "same": {"same.value": True}}, {"same": {"same.value": True}}]


TRANSPOSED = """\
stm Tr {
	cycleDef cycle == 1
	input context { event m: matrix(int, 2, 3) event v: vector(nat, 3) }
	output context { event t: matrix(int, 3, 2) event row: matrix(real, 1, 3) event back: boolean }
	var a: matrix(int, 2, 3)
	var b: vector(nat, 3)
	initial i
	state A { }
	transition t0 { from i to A }
	transition t1 { from A to A exec condition $m?a action $t!transpose(a) ; $back!(transpose(transpose(a)) == a) }
	transition t2 { from A to A exec condition not $m /\\ $v?b action $row!transpose(b) }
	transition t3 { from A to A exec condition not $m /\\ not $v }
}
"""


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_transpose_swaps_rows_and_columns(tmp_path, semantics):
    """Found by the model fuzzer ('inverse/transpose' was not supported, and not in the Known
    limits). m = ((1, 2, 3), (4, 5, 6)) row by row: its transpose is ((1, 4), (2, 5), (3, 6)),
    row by row 1 4 2 5 3 6, and transposing twice gives m back; the transpose of the vector
    (7, 8, 9) is the one-row matrix of its elements, as reals (RoboTool's TransposeExp)."""
    from robogen.differential import build
    from robogen.ir.lower import LoweringOptions

    model = tmp_path / "transposed.rst"
    model.write_text(TRANSPOSED)
    b = build([model], tmp_path / "t", options=LoweringOptions(semantics=semantics))
    scenario = Scenario([Instant(True, (Tick("m", {"m.value": [1, 2, 3, 4, 5, 6]}),)), Instant(True),
                         Instant(True, (Tick("v", {"v.value": [7, 8, 9]}),)), Instant(True)], half=False)
    sent = [s.outputs for s in run_checked(b, scenario).steps if s.outputs]
    assert sent == [{"t": {"t.value": [1, 4, 2, 5, 3, 6]}, "back": {"back.value": True}},
                    {"row": {"row.value": [7.0, 8.0, 9.0]}}]
