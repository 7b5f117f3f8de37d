"""Constants whose value code generation cannot compute (README, FMI mapping, "constant").

A scalar, string, vector or matrix constant whose initialiser is literals, other constants and
``+ - * /`` is an FMU parameter with that start value. Any other initialiser (a conditional, a
``let``, a collection, a function call, a constant the importer sets) is computed by the FMU when
Initialization Mode ends, from the parameters' values at that time, as a constant of a collection
type always was: a ``local`` FMI variable, not a parameter. The fuzzer found these models refused
("the value of constant ... must be computable from literals and other constants"; its switch
``constant_expressions``, docs/fuzzing.md)."""

from __future__ import annotations

import re

from support.codegen_driver import Instant, Scenario, Tick, build_text, outputs_by_instant, run_checked

from robogen.codegen.api import lower_paths
from robogen.ir.lower import LoweringOptions

GO = Tick("go", {})

MODEL = """\
import set_toolkit::*
import sequence_toolkit::*

stm M {
    var x: int = k + 1
    const k: int = if size({10, 20}) > 1 then min({10, 20}) else 0 end
    const j: int = k * 2
    const h: real = let p == 3.0 @ p / 2.0
    const free: real
    const b: real = if free > 1.0 then free else 1.0 end
    event go
    event ox: int
    event oj: int
    event oh: real
    event ob: real
    initial i
    state S { }
    transition t0 { from i to S }
    transition t1 { from S to S trigger go action ox!x ; oj!j ; oh!h ; ob!b }
}
"""


def test_an_initialiser_generation_cannot_compute_is_computed_by_the_fmu(tmp_path):
    built = build_text(tmp_path, "computed", MODEL)
    # k, h and b are computed by the FMU; j reads k, so it is computed there too; free is a parameter
    assert [p.var.name for p in built.fmu.params] == ["free"]
    xml = built.sources["modelDescription.xml"]
    for name in ("k", "j", "h", "b"):
        assert re.search(rf'<\w+ name="M\.{name}" [^>]*causality="local"', xml), name
    assert re.search(r'<Float64 name="M\.free" [^>]*causality="parameter" variability="fixed"', xml)
    # by hand: size({10, 20}) = 2 > 1, so k = min({10, 20}) = 10; x = k + 1 = 11 (declared before
    # k, started after it); j = 20; h = 3.0 / 2.0 = 1.5; free starts at 0.0, so b = 1.0
    outputs, _ = outputs_by_instant(built, {1: GO}, 2)
    assert outputs[1] == {"ox": {"ox.value": 11}, "oj": {"oj.value": 20}, "oh": {"oh.value": 1.5},
                          "ob": {"ob.value": 1.0}}
    # b follows the value the importer gives free in Initialization Mode: 2.5 > 1.0
    outputs, _ = outputs_by_instant(built, {1: GO}, 2, parameters={"M.free": 2.5})
    assert outputs[1]["ob"] == {"ob.value": 2.5}


def test_a_computable_initialiser_still_gives_a_parameter_and_set_overrides_a_computed_one(tmp_path):
    path = tmp_path / "m.rct"
    path.write_text(MODEL)
    fmu, _ = lower_paths([path], options=LoweringOptions(settings={"k": "4"}))
    # --set k=4: k is a parameter of start 4, and j = k * 2 is then computable (8)
    assert {p.var.name: p.value for p in fmu.params} == {"k": 4, "j": 8, "free": 0}


def test_a_failing_initialiser_is_an_error_when_initialization_ends(tmp_path):
    built = build_text(tmp_path, "failing", MODEL.replace("const j: int = k * 2", "const j: int = <1, 2>[k]"))
    # <1, 2>[10]: the sequence has 2 elements; the FMU (and the interpreter) fail when
    # Initialization Mode ends, before any instant
    trace = run_checked(built, Scenario([Instant(True, (GO,))], half=False))
    assert trace.error is not None and trace.steps == [], trace
    assert "ExitInitializationMode" in trace.error.where, trace.error
