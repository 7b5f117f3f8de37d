"""Function values updated at run time (robogen.ir.functions: a finite map of pairs with a
default): tests/codegen/models/fmaps.rct through the FMU and the reference interpreter, with
hand-calculated results."""

from __future__ import annotations

import pytest

from support.codegen_driver import Instant, Scenario, Tick, build, run_checked
from support.codegen_models import MODELS
from robogen.codegen.api import compile_model
from robogen.diagnostics import RobogenError

MODEL = MODELS / "fmaps.rct"


def test_finite_maps_give_the_hand_calculated_results(tmp_path):
    """positions starts as {1 |-> 10, 2 |-> 20}; g as x * 2.
    - ask 2: 20
    - put 3: override with 3 |-> 300: 3 keys;  ask 3: 300
    - put 1: 1 |-> 100 replaces 1 |-> 10: 3 keys
    - drop 2: fdiff(2, positions) = dsub({2}, positions) = {1 |-> 100, 3 |-> 300}: 2 keys, 2 not in dom
    - bump 4: g gets 4 |-> -1: g(4) + g(5) = -1 + 10 = 9
    - bump 5: g gets 5 |-> -1 too: g(5) + g(6) = -1 + 12 = 11
    - turn 3: h tabulated with n = 3 (North 3, East 4), then n = 0: h(North) * 10 + h(East) = 34
    - ask 2: 2 is outside the domain of positions: fmi3Error naming the variable and the line."""
    ticks = [("ask", 2), ("put", 3), ("ask", 3), ("put", 1), ("drop", 2), ("bump", 4), ("bump", 5), ("turn", 3), ("ask", 2)]
    scenario = Scenario([Instant(True, early=(Tick(c, {f"{c}.value": v}),)) for c, v in ticks], half=False)
    built = build([MODEL], tmp_path / "fmaps")
    got = run_checked(built, scenario)
    out = [(c, v) for s in got.steps for c, values in s.outputs.items() for v in values.values()]
    assert out == [("got", 20), ("keys", 3), ("got", 300), ("keys", 3), ("keys", 2), ("has", False), ("gotg", 9),
                   ("gotg", 11), ("gotd", 34)]
    assert got.error is not None and got.error.instant == 8
    assert ("function variable 'positions' applied outside its domain (or before it has a value) at fmaps.rct:43"
            in got.error.where)


def _model(tmp_path, body: str):
    path = tmp_path / "m.rct"
    path.write_text("import relation_toolkit::*\nimport sequence_toolkit::*\nstm M {\n\tvar n: nat = 0\n\tevent go: nat\n\tevent out: nat\n"
                    f"{body}\n\tinitial i\n\tstate S {{ }}\n\ttransition t0 {{ from i to S }}\n}}\n")
    return path


def test_a_lambda_over_an_infinite_domain_that_reads_a_variable_is_a_located_error(tmp_path):
    path = _model(tmp_path, "\tvar f: nat -> nat\n\ttransition t1 { from S to S trigger go?n action f = lambda x: nat @ x + n }")
    with pytest.raises(RobogenError) as exc:
        compile_model([path], tmp_path / "out")
    (d,) = exc.value.diagnostics
    assert d.message.startswith("a function over nat that reads variable 'n' as a value (its results, fixed when it is "
                                "stored, would be infinitely many")
    assert (d.span.line, d.span.column) == (8, 74)  # the variable read


def test_the_pairs_of_a_function_with_a_default_are_a_run_time_error(tmp_path):
    """dom of a lambda has no finite meaning: the instant that asks for it ends in fmi3Error."""
    path = _model(tmp_path, "\tvar f: nat -> nat = lambda x: nat @ x\n"
                            "\ttransition t1 { from S to S trigger go?n action out!size(dom(f)) }")
    built = build([path], tmp_path / "out")
    got = run_checked(built, Scenario([Instant(True, early=(Tick("go", {"go.value": 1}),))], half=False))
    assert got.error is not None
    assert "f: a function given by a lambda or named function has no finite set of pairs at m.rct:8" in got.error.where


TWO_MACHINES = """\
package two
interface Io { event go: nat event out: nat }
stm A {
\tuses Io
\tvar n: nat = 0
\tevent f: nat -> nat
\tinitial i
\tstate S { }
\ttransition t0 { from i to S }
\ttransition t1 { from S to S trigger go?n
\t\taction if n > 5 then f!(lambda x: nat @ x * 3) else f!(lambda x: nat @ x + 100) end }
}
stm B {
\tuses Io
\tvar g: nat -> nat
\tevent f: nat -> nat
\tinitial i
\tstate S { }
\ttransition t0 { from i to S }
\ttransition t1 { from S to S trigger f?g action out!g(2) }
}
controller C {
\tuses Io
\tsref a = A
\tsref b = B
\tconnection C on go to a on go
\tconnection a on f to b on f
\tconnection b on out to C on out
}
robotic platform P { uses Io }
module M {
\trref p = P
\tcref c = C
\tconnection p on go to c on go ( _async )
\tconnection c on out to p on out ( _async )
}
"""


def test_a_function_value_sent_from_one_machine_to_another(tmp_path):
    """The FMU numbers the lambdas of all its machines alike: B applies what A sends.
    go 7: A sends x * 3, B answers g(2) = 6; go 1: x + 100, 102."""
    path = tmp_path / "two.rct"
    path.write_text(TWO_MACHINES)
    built = build([path], tmp_path / "two")
    got = run_checked(built, Scenario([Instant(True, early=(Tick("go", {"go.value": v}),)) for v in (7, 1)]
                                      + [Instant(True)] * 2, half=False))
    assert got.error is None
    assert [v for s in got.steps for c, values in s.outputs.items() for v in values.values()] == [6, 102]
