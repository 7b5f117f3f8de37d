"""A machine of many blocks is generated as one C function per part of its blocks and a
dispatcher (robogen.codegen.generate.PART_SIZE; a 10,000-state machine did not compile as one
function). Here the parts are made tiny so that small test models take that form, and the FMU
must still do exactly what the interpreter does: runs that cross parts, stepwise micro-steps that
end in one part and resume in another, the runaway bound counted across parts."""

from __future__ import annotations

import pytest

from support.codegen_driver import build
from support.codegen_models import TEST_MODELS
from robogen.codegen import generate as generate_module
from robogen.ir.lower import LoweringOptions
from test_differential import run_differential


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
@pytest.mark.parametrize("name", ["relay", "arith"])
def test_a_machine_in_parts_behaves_as_one_function(tmp_path, monkeypatch, name, semantics):
    monkeypatch.setattr(generate_module, "PART_SIZE", 3)
    model = TEST_MODELS[name]
    options = LoweringOptions(semantics=semantics, max_steps=model.max_steps, settings=dict(model.settings))
    b = build([model.path], tmp_path, options=options)
    model_c = b.sources["sources/model.c"]
    assert "static int rg_run_0_1(" in model_c and "RG_RUN_JUMP" in model_c
    stats = run_differential(b, name, seed=3)
    assert stats["outputs"] > 0
