"""robogen.codegen.c: the generated C reads like the model. Nodes and events are named by enum
constants, every guard is quoted as the model writes it above its test, tests of constants are
folded away, and the C names made from model names never clash."""

from __future__ import annotations

import re

import pytest

from support.codegen_models import TEST_MODELS
from robogen.codegen.api import package_model
from robogen.codegen.c import CNames, Identifiers, bare, c_comment
from robogen.ir import model as ir


def test_bare_drops_only_the_parentheses_around_the_whole_expression():
    assert bare("(!a)") == "!a"
    assert bare("((a && b))") == "a && b"
    assert bare("(a) && (b)") == "(a) && (b)"
    assert bare("(a || b) && (c)") == "(a || b) && (c)"
    assert bare("f(x)") == "f(x)"


def test_identifiers_made_from_clashing_model_names_are_numbered():
    made = Identifiers()
    assert [made.make(n) for n in ("a.b", "a_b", "a::b", "c")] == ["a_b", "a_b_2", "a_b_3", "c"]


def guard_texts(fmu: ir.Fmu) -> dict[str, str]:
    """The model text of each transition's guard in the IR, by the case's label."""
    return {case.label: case.guard_text for m in fmu.machines for b in m.blocks if isinstance(b.term, ir.Branch)
            for case in b.term.cases}


def test_the_ir_keeps_each_guard_as_the_model_writes_it(built):
    """Trigger and condition in the diagrams' form `trigger [condition]` (ir.Case.guard_text)."""
    robosim = guard_texts(built("ur5e", "exhaustive").fmu)
    assert robosim["t2: Idle -> ArmMove"] == "[$moveDiscreteCommand?margs]"
    assert robosim["t2_nonfeasible: ArmMove -> Idle (exec)"] == "[$nonfeasibleMoveDiscreteCommand /\\ not $feasibleMoveDiscreteCommand]"
    assert robosim["t2_2: ArmMoving -> J2 (exec)"] == ""  # an exec transition without a condition
    robochart = guard_texts(built("inputs", "exhaustive").fmu)
    assert robochart["d4: Moving -> Moving"] == "go?o [o.steps > 0]"
    assert robochart["t1: Parked -> Driving"] == "go?o"


@pytest.mark.parametrize("name", sorted(TEST_MODELS))
def test_every_guard_is_quoted_above_its_test(built, name):
    b = built(name, "exhaustive")
    lines = b.sources["sources/model.c"].splitlines()
    comments = {line.strip() for line in lines}
    quoted = 0
    for m in b.fmu.machines:
        for block in m.blocks:
            if not isinstance(block.term, ir.Branch):
                continue
            for case in block.term.cases:
                text = c_comment(case.label) + (" " + c_comment(case.guard_text) if case.guard_text else "")
                assert any(c.startswith(f"/* {text}") for c in comments), (name, block.id, text)
                quoted += bool(case.guard_text)
    assert quoted > 0
    # the test follows its comment: an if, a fallible guard's block, or the jump of a constant guard
    for i, line in enumerate(lines[:-1]):
        if re.match(r"^ {12}/\* \S+: .* -> .*\*/$", line) and "never taken" not in line:
            assert re.match(r"^ {12}(if \(|\{|m->pc = \d+; continue;)", lines[i + 1]), (line, lines[i + 1])


@pytest.mark.parametrize("name", sorted(TEST_MODELS))
def test_nodes_and_events_are_named_not_numbered(built, name):
    b = built(name, "exhaustive")
    model_c, config_h = b.sources["sources/model.c"], b.sources["sources/config.h"]
    assert not re.search(r"m->node = \d|RG_ENTER\(\d|present\[\d|entered\[\d|rg_activate_output_clock\(inst, \d", model_c)
    names = CNames.of(b.fmu)
    for m in b.fmu.machines:
        own = names.machines[m.index]
        for node in m.nodes:  # the XML's enumeration <machine>.Node, item for item
            assert f"    {own.nodes[node.id]} = {node.id}," in config_h
            assert f"case {own.nodes[node.id]}: return \"{node.label}\";" in model_c
        for e in m.events:
            assert f"    {own.events[e.index]} = {e.index}," in config_h


FOLDING = """package folding

interface Ops {
\tevent a: int
}

interface Outs {
\tevent q: int
}

stm Fold {
\tcycleDef cycle == 1
\tvar a: int = 7, b: int = 1, q: int = 0
\tinput context { uses Ops }
\toutput context { uses Outs }
\tinitial i
\tstate S {
\t\tentry if true then q = q + 1 end ; if false then q = 9 end ; if a / b > 2 then q = 1 end ; $q!(a / b)
\t}
\tstate T { }
\ttransition t0 { from i to S }
\ttransition t1 { from S to S exec condition $a?a /\\ a / b > 0 }
\ttransition t2 { from S to T exec condition false }
\ttransition t3 { from S to S exec condition true }
\ttransition t4 { from T to T exec }
}
"""


def test_tests_of_constants_are_folded_away(tmp_path):
    """No `if (true)` and no code after it: a guard that is the constant true ends its block's
    cases (the deadlock report after it is unreachable), one that is false is a comment, and an
    if statement on a constant is its taken branch. Guards and conditions that may fault (a / b)
    are tested for the fault first. The C builds under the house flags (-Werror)."""
    model = tmp_path / "folding.rst"
    model.write_text(FOLDING)
    _, compiled = package_model([str(model)], tmp_path / "folding.fmu")
    model_c = compiled.generated.files["sources/model.c"]
    assert not re.search(r"if \((true|false)\)", model_c)
    assert "q = INT64_C(9)" not in model_c and "m->v_q = rg_i_add(m->v_q, INT64_C(1));" in model_c
    evaluation = model_c[model_c.index("/* b1: EVAL S"):model_c.index("case 2:")]
    assert "/* t2: S -> T (exec) [false]: never taken" in evaluation
    assert evaluation.rstrip().endswith("/* t3: S -> S (exec) [true]  folding.rst:24 */\n            m->pc = 9; continue;".rstrip())
    assert "rg_machine_fail" not in evaluation
    assert "bool g_ = " in evaluation and "bool c_ = " in model_c
