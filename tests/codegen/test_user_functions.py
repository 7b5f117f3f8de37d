"""User functions: declared in the model by their contract, implemented in C by the file given
with --functions (and in Python for the reference interpreter). The FMU and the interpreter agree
on random scenarios; a model whose functions have no implementation gets a located error that
spells out the C definition to write; the RoboSim machine of the reference models that calls
floor and random compiles."""

from __future__ import annotations

import random
from pathlib import Path

import pytest

from support.codegen_driver import FmuRunner, build, interpret, random_scenario
from robogen.codegen.api import compile_model
from robogen.codegen.generate import CodegenOptions
from robogen.diagnostics import RobogenError
from robogen.ir.lower import LoweringOptions

HERE = Path(__file__).resolve().parent
MODEL, C_FILE = HERE / "models" / "userfun.rst", HERE / "models" / "userfun.c"
PYTHON = {"sat": lambda x, hi: hi if x > hi else x, "even": lambda n: n % 2 == 0}
REFERENCE = HERE.parent.parent.parent / "shared" / "reference-models" / "alpha-untimed"


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_fmu_with_user_functions_agrees_with_the_interpreter(tmp_path, semantics):
    built = build([MODEL], tmp_path, options=LoweringOptions(semantics=semantics), functions=C_FILE)
    assert "rg_user_sat(" in built.sources["sources/model.c"] and built.sources["sources/user_functions.c"] == C_FILE.read_text()
    runner = FmuRunner(built.folder)
    rng = random.Random(7)
    try:
        outputs = 0
        for _ in range(60):
            scenario = random_scenario(rng, runner.desc, 12)
            got = runner.run(scenario)
            expected = interpret(built.fmu, scenario, runner.desc, functions=PYTHON)
            assert got.comparable() == expected.comparable()
            outputs += sum(len(s.outputs) for s in got.steps)
        assert outputs > 20  # the scenarios reach Report and its outputs
    finally:
        runner.close()


def test_a_function_without_implementation_names_the_c_definition(tmp_path):
    with pytest.raises(RobogenError) as exc:
        compile_model([MODEL], tmp_path)
    d = exc.value.diagnostics[0]
    # the first call lowered is the guard of t2
    assert d.message == "function 'even' has no implementation: give robogen a C file with --functions"
    assert (d.span.path, d.span.line, d.span.column) == (str(MODEL), 27, 45)
    assert d.notes[0].message == "the file must define: static bool rg_user_even(int64_t n) { ... }"


def test_a_wrong_signature_is_a_compiler_error(tmp_path):
    bad = tmp_path / "bad.c"
    bad.write_text("static float rg_user_sat(float x, float hi) { return x; }\n"
                   "static bool rg_user_even(int64_t n) { return n == 0; }\n")
    with pytest.raises(RobogenError) as exc:
        build([MODEL], tmp_path / "w", functions=bad)
    message = exc.value.diagnostics[0].message  # the compiler's own words, located in the sources
    assert "conflicting types for" in message and "rg_user_sat" in message and "user_functions.c:1" in message


@pytest.mark.shared
def test_the_reference_robosim_movement_machine_compiles(tmp_path):
    maths = tmp_path / "maths.c"
    maths.write_text(
        "#include <math.h>\n"
        "static uint64_t rg_user_floor(double x) { return x <= 0.0 ? 0u : (uint64_t)floor(x); }\n"
        "static double rg_user_random(void) { return 0.5; }\n"
    )
    options = LoweringOptions(settings={"lv": "0.1", "av": "30", "MB": "20", "alpha": "3"})
    built = build([REFERENCE], tmp_path / "w", machine="pkg223_aggregation_sim::Movement", options=options, functions=maths)
    # the machine's RoboSim operations (not the RoboChart ones of the same name) are inlined
    assert "clone_waitOp_j_2_4_f" in built.sources["sources/model.c"]
    assert all("rc2rs/robochart" not in line for line in built.sources["sources/model.c"].splitlines() if "case" in line)
    runner = FmuRunner(built.folder)
    try:
        trace = runner.run(random_scenario(random.Random(1), runner.desc, 40))
        assert trace.error is None and len(trace.steps) >= 40
    finally:
        runner.close()


def test_every_function_the_file_lacks_is_reported(tmp_path):
    """Without --functions both functions are named; with a file that defines only sat, even is,
    located at its first call, instead of a C compiler error."""
    with pytest.raises(RobogenError) as exc:
        compile_model([MODEL], tmp_path / "a")
    assert sorted(d.message.split("'")[1] for d in exc.value.diagnostics) == ["even", "sat"]
    part = tmp_path / "part.c"
    part.write_text("static double rg_user_sat(double x, double hi) { return x > hi ? hi : x; }\n")
    with pytest.raises(RobogenError) as exc:
        compile_model([MODEL], tmp_path / "b", codegen=CodegenOptions(functions=part))
    (d,) = exc.value.diagnostics
    assert d.message == f"function 'even' has no implementation: {part} does not define it"
    assert (d.span.line, d.span.column) == (27, 45)
    assert d.notes[0].message == "the file must define: static bool rg_user_even(int64_t n) { ... }"


def test_the_functions_file_may_define_functions_the_model_does_not_call(tmp_path):
    """Found by the model fuzzer: a model that declares two functions and calls one, with a file
    that implements both, failed to compile (`'rg_user_spare' defined but not used`)."""
    model = tmp_path / "spare.rst"
    model.write_text("function used(n: int): boolean { }\nfunction spare(x: real): real { }\n"
                     "stm S { cycleDef cycle == 1 var n: int = 0 output context { event even: boolean } initial i\n"
                     "state A { entry $even!used(n) ; n = n + 1 } transition t0 { from i to A } transition t1 { from A to A exec } }\n")
    functions = tmp_path / "spare.c"
    functions.write_text("static bool rg_user_used(int64_t n) { return n % 2 == 0; }\nstatic double rg_user_spare(double x) { return x; }\n")
    built = build([model], tmp_path / "w", functions=functions)
    runner = FmuRunner(built.folder)
    try:
        scenario = random_scenario(random.Random(3), runner.desc, 6, every_instant=True)
        got = runner.run(scenario)
        assert got.comparable() == interpret(built.fmu, scenario, runner.desc, functions={"used": lambda n: n % 2 == 0}).comparable()
        assert [s.outputs["even"]["even.value"] for s in got.steps if "even" in s.outputs][:3] == [True, False, True]
    finally:
        runner.close()
