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
