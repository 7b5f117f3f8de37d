"""Functions the model declares without a body (robogen.ir.declared): computed from the
postcondition that pins their result, checked against their preconditions, instantiated per call
where they are generic (a C function per instantiation for the user's), all with hand-calculated
results through the FMU and the reference interpreter."""

from __future__ import annotations

import pytest

from support.codegen_driver import Instant, Scenario, Tick, build, run_checked
from support.codegen_models import MODELS
from robogen.codegen.api import compile_model
from robogen.diagnostics import RobogenError

MODEL, C_FILE = MODELS / "declared.rct", MODELS / "declared.c"


def _weight(s, x):
    """Weight in Python, either instantiation (the interpreter's counterpart of declared.c)."""
    if isinstance(x, bool):
        return sum(1 for p in s if p["_1"] == x)
    return sum(p["_2"] for p in s if p["_1"] == x)


def _run(tmp_path, path, scenario, c_file=None, functions=None):
    built = build([path], tmp_path / path.stem, functions=c_file)
    return built, run_checked(built, scenario, functions=functions)


def _outputs(trace, *events):
    return [tuple(s.outputs[e][f"{e}.value"] for e in events) for s in trace.steps if events[0] in s.outputs]


def test_defined_and_generic_functions_give_the_hand_calculated_results(tmp_path):
    """go?n: a = Bump(a, n - 5) adds (n - 5, size(a)), b = Bump(b, n > 2) adds (n > 2, size(b));
    Weight(a, n - 5) sums the positions paired with n - 5, Weight(b, true) counts the true pairs;
    Flip(n > 3) = n <= 3, Twice(n) = 2n, Half(n) = n / 2, and Half(3) violates n % 2 == 0.
    - go 4: a {(-1,0)}, b {(T,0)}: weight 0 + 1, flip F, twice 8, half 2
    - go 6: a + (1,1), b + (T,1): weight 1 + 2, flip F, twice 12, half 3
    - go 8: a + (3,2), b + (T,2): weight 2 + 3, flip F, twice 16, half 4
    - go 2: a + (-3,3), b + (F,3): weight 3 + 3, flip T, twice 4, half 1
    - go 3: Half(3) fails: the instant ends in fmi3Error (its outputs are not shown)."""
    ticks = [Tick("go", {"go.value": v}) for v in (4, 6, 8, 2, 3)]
    scenario = Scenario([Instant(True, early=(t,)) for t in ticks], half=False)
    built, got = _run(tmp_path, MODEL, scenario, C_FILE, {"Weight__int": _weight, "Weight": _weight})
    assert _outputs(got, "ints", "bools", "weight", "flip", "twice") == [
        (1, 1, 1, False, 8), (2, 2, 3, False, 12), (3, 3, 5, False, 16), (4, 4, 6, True, 4)]
    assert _outputs(got, "half") == [(2,), (3,), (4,), (1,)]
    assert got.error is not None and got.error.instant == 4
    assert "function 'Half' called outside its precondition n % 2 == 0 at declared.rct:50" in got.error.where
    model_c = built.sources["sources/model.c"]
    # one C function per instantiation of the user's generic function; the defined ones are computed
    assert "rg_user_Weight__int(" in model_c and "rg_user_Weight__boolean(" in model_c
    assert not any(f"rg_user_{f}" in model_c for f in ("Bump", "Half", "Flip", "Twice"))


def test_each_instantiation_is_named_with_its_c_signature(tmp_path):
    with pytest.raises(RobogenError) as exc:
        compile_model([MODEL], tmp_path)
    found = {(d.message, d.span.line, d.notes[0].message) for d in exc.value.diagnostics}
    assert found == {
        ("function 'Weight' (instantiated with ?X = int) has no implementation: give robogen a C file with --functions",
         50, "the file must define: static uint64_t rg_user_Weight__int(rg_set_tup2_i_u s, int64_t x) { ... }"),
        ("function 'Weight' (instantiated with ?X = boolean) has no implementation: give robogen a C file with --functions",
         50, "the file must define: static uint64_t rg_user_Weight__boolean(rg_set_tup2_b_u s, bool x) { ... }"),
    }


def _machine(tmp_path, functions: str, action: str, name: str = "m"):
    path = tmp_path / f"{name}.rct"
    path.write_text("import set_toolkit::*\nimport sequence_toolkit::*\n" + functions +
                    "\nstm M {\n\tvar n: nat = 0\n\tevent go: nat\n\tevent out: nat\n\tinitial i\n\tstate S { }\n"
                    "\ttransition t0 { from i to S }\n"
                    f"\ttransition t1 {{ from S to S trigger go?n action {action} }}\n}}\n")
    return path


def test_recursion_between_defined_functions_is_a_located_error(tmp_path):
    path = _machine(tmp_path, "function Even(n: nat): boolean { postcondition result == (n == 0 \\/ Odd(n - 1)) }\n"
                              "function Odd(n: nat): boolean { postcondition result == (n != 0 /\\ Even(n - 1)) }\n",
                    "if Even(n) then out!1 end")
    with pytest.raises(RobogenError) as exc:
        compile_model([path], tmp_path / "out")
    (d,) = exc.value.diagnostics
    assert d.message == ("recursion between functions defined by their postcondition (Even -> Odd -> Even) "
                         "is not supported for code generation")
    assert (d.span.line, d.span.column) == (4, 68)  # the call that closes the cycle, in Odd


def test_a_type_variable_no_argument_decides_is_a_located_error(tmp_path):
    path = _machine(tmp_path, "function Card(s: Set(?X)): nat { postcondition result == size(s) }\n",
                    "out!Card({})")
    with pytest.raises(RobogenError) as exc:
        compile_model([path], tmp_path / "out")
    (d,) = exc.value.diagnostics
    assert d.message.startswith("the type ?X of function 'Card' cannot be inferred at this call")
    assert (d.span.line, d.span.column) == (12, 54)


def test_a_generic_defined_function_with_an_element_type_from_its_argument(tmp_path):
    """Card(s) of a Set(nat), of a Set(boolean) and of an empty Set(real) (its type given by a
    cast): three instantiations of one body, size(s)."""
    path = _machine(tmp_path, "function Card(s: Set(?X)): nat { postcondition result == size(s) }\n",
                    "out!(Card({n, 1, 2}) * 10 + Card({n > 1, true}) + Card({} as Set(real)) * 100)")
    ticks = [Tick("go", {"go.value": v}) for v in (1, 2, 5)]
    scenario = Scenario([Instant(True, early=(t,)) for t in ticks], half=False)
    _, got = _run(tmp_path, path, scenario)
    # n = 1: {1, 2} and {false, true}; n = 2: {1, 2} and {true}; n = 5: {1, 2, 5} and {true}
    assert _outputs(got, "out") == [(22,), (21,), (31,)]


def test_a_precondition_code_generation_cannot_evaluate_is_a_warning(tmp_path):
    path = _machine(tmp_path, "function Inc(n: nat): nat {\n\tprecondition exists k: nat @ k > n\n"
                              "\tpostcondition result == n + 1\n}\n", "out!Inc(n)")
    fmu = compile_model([path], tmp_path / "out").fmu
    (w,) = [w for w in fmu.warnings if "precondition" in w.message]
    assert w.message.startswith("the precondition exists k: nat @ k > n of function 'Inc' is not checked at run time: ")
    assert w.span.line == 4
