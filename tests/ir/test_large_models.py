"""Models whose size is in the thousands: lowering, the IR dump, the C generator and the
interpreter walk them with loops (or a stack of their own), never by recursion as deep as the
model is large; a machine of thousands of blocks is generated as one C function per part."""

from __future__ import annotations

from pathlib import Path

from support.frontend import shallow_stack

from robogen.codegen.api import lower_paths
from robogen.codegen.generate import PART_SIZE, generate
from robogen.ir.dump import dump
from robogen.ir.interp import Interpreter


def test_a_flat_sum_of_a_thousand_operands(tmp_path: Path):
    terms = 1000
    path = tmp_path / "flat.rct"
    path.write_text("stm Flat {\n\tvar x: int = 1\n\tinitial i\n\tstate A { entry x = "
                    + " + ".join(f"x * {k}" for k in range(terms)) + " }\n\ttransition t { from i to A }\n}\n")
    with shallow_stack():
        fmu, _ = lower_paths([path])
        text = dump(fmu)
        model_c = generate(fmu).files["sources/model.c"]
        it = Interpreter(fmu)
        it.exit_initialization()
        it.evaluate(True)
    assert text.count(" + ") == terms - 1 and model_c.count("rg_i_add(") == terms - 1
    assert it.variables()["Flat.x"] == terms * (terms - 1) // 2  # x = 1: 0 + 1 + ... + 999


def test_a_machine_of_ten_thousand_states(tmp_path: Path):
    n = 10_000
    body = [f"\tstate S{j} {{ }}\n\ttransition t{j} {{ from S{j} to S{(j + 1) % n} trigger go }}" for j in range(n)]
    path = tmp_path / "chain.rct"
    path.write_text("stm Chain {\n\tevent go\n\tinitial i\n\ttransition t { from i to S0 }\n" + "\n".join(body) + "\n}\n")
    with shallow_stack():
        fmu, _ = lower_paths([path])
        dump(fmu)
        model_c = generate(fmu).files["sources/model.c"]
    (m,) = fmu.machines
    blocks = len(m.blocks)
    assert blocks == 2 * n + 1  # the start, and per state its evaluation and its transition
    parts = -(-blocks // PART_SIZE)
    assert model_c.count("static int rg_run_0_") == parts and f"case {parts - 1}: result = rg_run_0_{parts - 1}(" in model_c
    # blocks are numbered as recursion would have created them: S0's evaluation right after the start
    assert m.blocks[1].label == "EVAL S0" and m.blocks[2].label.startswith("t0: S0 -> S1")
    it = Interpreter(fmu)
    it.exit_initialization()
    it.evaluate(True)
    it.update()
    for _ in range(3):
        it.latch("go")
        it.evaluate(True)
        it.update()
    assert m.nodes[it.machines[0].node].label == "S3"
