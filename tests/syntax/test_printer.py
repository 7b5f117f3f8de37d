"""robogen.syntax.printer: printed models parse back to equal trees (equality ignores spans),
with only the parentheses precedence needs."""

from __future__ import annotations

import pytest
from support.frontend import REFERENCE, corpus_files, reference_files, relative_ids, shallow_stack

from robogen.syntax import ast, printer
from robogen.syntax.parser import parse_file, parse_text


def round_trip(f: ast.File) -> str:
    text = printer.file(f)
    again = parse_text(text, f.path, f.language)
    assert again == f, text
    return text


@pytest.mark.parametrize("path", corpus_files(), ids=lambda p: p.name)
def test_own_models_print_back_to_equal_trees(path):
    text = round_trip(parse_file(path))
    # printing is canonical: the printed text prints to itself
    assert printer.file(parse_text(text, str(path))) == text


@pytest.mark.shared
@pytest.mark.parametrize("path", reference_files(), ids=relative_ids(reference_files(), REFERENCE))
def test_reference_models_print_back_to_equal_trees(path):
    round_trip(parse_file(path))


def cond(text: str, path: str = "m.rct") -> ast.Expr:
    return parse_text(f"stm S {{ transition t {{ from a to b condition {text} }} }}", path).items[0].members[0].condition


@pytest.mark.parametrize(
    "text, printed",
    [
        ("(a \\/ b) /\\ c", "(a \\/ b) /\\ c"),
        ("a \\/ (b /\\ c)", "a \\/ b /\\ c"),
        ("(a - b) - c", "a - b - c"),
        ("a - (b - c)", "a - (b - c)"),
        ("not (a == b)", "not a == b"),
        ("(not a) == b", "(not a) == b"),
        ("-(x + 1) * 2", "-(x + 1) * 2"),
        ("(x + 1) as real", "x + 1 as real"),
        ("((x as real) as int)", "(x as real) as int"),
        ("(the x: nat | p @ x) == 1", "the x: nat | p @ x == 1"),  # `the` binds tighter than ==
        ("the x: nat | p @ (x == 1)", "the x: nat | p @ (x == 1)"),
        ("let k == 1 @ (k == 2)", "let k == 1 @ (k == 2)"),
        ("(forall x: nat @ p) /\\ q", "(forall x: nat @ p) /\\ q"),
        ("<(a + b), c> == s", "<a + b, c> == s"),
        ("(r.f)[1]", "r.f[1]"),
        ("{x: nat | x > 0 @ x * 2}", "{x: nat | x > 0 @ x * 2}"),
        ("x is (nat * nat)", "x is (nat * nat)"),
        # chains: a looser operator on the left is parenthesised, however far down the chain
        ("((a \\/ b) /\\ c) /\\ d", "(a \\/ b) /\\ c /\\ d"),
        ("((a \\/ b) \\/ c) /\\ d", "(a \\/ b \\/ c) /\\ d"),
        ("(((a - b) * c) - d) * e", "((a - b) * c - d) * e"),
        ("(a /\\ b) \\/ c => d", "a /\\ b \\/ c => d"),
        ("(||) == (| 1 |)", "(||) == (| 1 |)"),
    ],
)
def test_expressions_print_with_the_parentheses_precedence_needs(text, printed):
    e = cond(text)
    assert printer.expr(e) == printed
    assert cond(printed) == e


def test_robosim_expressions_and_statements():
    e = cond("$e?x : (x > 1) /\\ not $f \\/ $g.(1 + 2)", "m.rst")
    assert printer.expr(e) == "$e?x : (x > 1) /\\ not $f \\/ $g.(1 + 2)"
    f = parse_text("stm S { transition t { from a to b exec action $o!(x + 1) ; $p(1) ; $v = 2 ; exec } }", "m.rst")
    t = f.items[0].members[0]
    assert printer.stmt(t.action) == "$o!(x + 1) ; $p(1) ; $v = 2 ; exec"
    assert printer.transition_label(t) == "exec / $o!(x + 1) ; $p(1) ; $v = 2 ; exec"


def test_calls_through_dollar_and_filters_without_send():
    f = parse_text("stm S { transition t { from a to b exec action x = $f(1) + $g() ; $o!$f($x) } }", "m.rst")
    assert printer.stmt(f.items[0].members[0].action) == "x = $f(1) + $g() ; $o!$f($x)"
    assert parse_text(printer.file(f), "m.rst") == f
    f = parse_text("stm S { transition t { from a to b action e[| x > 1 |]!x ; e[||]?y } }")
    assert printer.stmt(f.items[0].members[0].action) == "e[| x > 1 |]!x ; e[||]?y"
    assert parse_text(printer.file(f)) == f


def test_a_synchronisation_without_send_keeps_its_value():
    """Found by the model fuzzer: `e.R(| f = 1 |)` and `e.r.f` do not parse back as the
    synchronisation `e.v` (after `e.`, the grammar reads a name, a call or an atom that does not
    start with a name); such values are printed in parentheses, the others as they were."""
    f = parse_text("stm S { transition t { from a to b action e.(R(| f = 1 |)) ; e.(r.f) ; e.(q[1]) ; "
                   "e.v ; e.E::l ; e.f(1) ; e.3 ; e.(| 1, 2 |) ; send e.R(| f = 1 |) } }")
    assert printer.stmt(f.items[0].members[0].action) == (
        "e.(R(| f = 1 |)) ; e.(r.f) ; e.(q[1]) ; e.v ; e.E::l ; e.f(1) ; e.3 ; e.(| 1, 2 |) ; send e.R(| f = 1 |)")
    assert parse_text(printer.file(f)) == f


def test_a_flat_expression_of_a_thousand_operands_prints_in_a_loop():
    text = " \\/ ".join(f"(x{i} + 1) * 2 - y > {i} /\\ b{i}" for i in range(1000))
    with shallow_stack():
        printed = printer.expr(cond(text))
        assert printer.expr(cond(printed)) == printed == text


def test_statements_keep_their_grouping():
    f = parse_text("stm S { transition t { from a to b action (a = 1 ; b = 2) <{ 3 } ; (c = 1 <{ 1 }) <{ 2 } } }")
    s = f.items[0].members[0].action
    assert printer.stmt(s) == "(a = 1 ; b = 2) <{ 3 } ; (c = 1 <{ 1 }) <{ 2 }"
    assert parse_text(printer.file(f)) == f


def test_transition_labels_use_the_diagram_form():
    f = parse_text("stm S { transition t { from a to b trigger e?x #C <{ 2 } condition x > 1 action y = x } }")
    assert printer.transition_label(f.items[0].members[0]) == "e?x #C <{2} [x > 1] / y = x"
    f = parse_text("stm S { transition t { from a to b condition else } transition u { from p to b probability 0.5 } }")
    assert [printer.transition_label(t) for t in f.items[0].members] == ["[else]", "p = 0.5"]


def test_names_that_are_keywords_are_printed_escaped():
    f = parse_text("interface I { event ^exec event ^state } stm ^stm { uses I var ^var: nat initial ^initial }", "m.rst")
    text = round_trip(f)
    assert "event ^exec" in text and "stm ^stm {" in text and "var ^var: nat" in text
    # RoboSim's keywords are plain names in RoboChart, printed as such
    g = parse_text("stm exec { var cycle: nat }", "m.rct")
    assert "stm exec {" in round_trip(g) and "var cycle: nat" in printer.file(g)
    # outside a whole file, expressions print names as they are (for diagrams)
    assert printer.expr(ast.Name(("state",))) == "state"


def test_printed_layout():
    f = parse_text("package p import q::* stm S { var x: nat = 1 initial i state A { entry x = 2 } transition t { from i to A } }")
    assert printer.file(f) == (
        "package p\n"
        "import q::*\n"
        "\n"
        "stm S {\n"
        "\tvar x: nat = 1\n"
        "\tinitial i\n"
        "\tstate A {\n"
        "\t\tentry x = 2\n"
        "\t}\n"
        "\ttransition t {\n"
        "\t\tfrom i\n"
        "\t\tto A\n"
        "\t}\n"
        "}\n"
    )
