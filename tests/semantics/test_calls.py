"""robogen.semantics.calls: calls of any function-typed expression, named functions and
enumeration literals used as values or constructors, and casts to any type, as RoboTool's
scope and type providers resolve and type them. Golden messages, located by the text they must
point at."""

from __future__ import annotations

from support.frontend import diagnostics, error, machine


def test_a_lambda_a_variable_and_a_parenthesised_expression_can_be_called():
    text = machine(
        "var f: nat -> nat, g: (nat * nat) -> nat, n: nat, b: boolean",
        action="n = (lambda x: nat @ x + 1)(1) ; n = f(2) ; n = g(1, 2) ; n = (if b then f else f end)(3)",
    )
    assert diagnostics(text) == []


def test_a_call_checks_the_arguments_against_the_domain():
    text = machine(
        "var f: nat -> nat, g: (nat * nat) -> nat, r: nat <-> nat, n: nat, b: boolean",
        action="n = f(true) ; n = g(1) ; n = (lambda x: nat @ x)(1, 2) ; n = n(1) ; n = r(1) ; b = f(1)",
    )
    assert diagnostics(text) == [
        error(text, "true", "argument 1 of this function of type nat -> nat must be nat, but this is boolean"),
        error(text, "g(1)", "this function of type (nat * nat) -> nat takes 2 arguments, but 1 was given"),
        error(text, "(lambda", "this function of type nat -> nat takes 1 argument, but 2 were given"),
        error(text, "n(1)", "only a function can be called, and this is nat"),
        error(text, "r(1)", "only a function can be called, and this is nat <-> nat"),
        error(text, "f(1)", "cannot assign nat to 'b' of type boolean"),
    ]


def test_a_named_function_is_a_value_whose_domain_is_a_product():
    """RoboTool types ``inc`` as ``(nat) -> nat`` (a product of one component, which robogen
    takes to be that component) and ``add`` as ``(nat * nat) -> nat``; a function without
    parameters stands for its result (K5)."""
    text = "\n".join([
        "function inc(n: nat): nat { }",
        "function add(x: nat, y: nat): nat { }",
        "function zero(): nat { }",
        machine("var f: nat -> nat, g: (nat * nat) -> nat, n: nat, b: boolean",
                action="f = inc ; g = add ; n = zero ; f = add ; b = inc"),
    ])  # fmt: skip
    assert diagnostics(text) == [
        error(text, "add ;", "cannot assign (nat * nat) -> nat to 'f' of type nat -> nat", 2),
        error(text, "inc", "cannot assign (nat) -> nat to 'b' of type boolean", 3),
    ]


def test_a_cast_takes_any_type_and_checks_that_the_value_can_be_one():
    text = "\n".join([
        "import relation_toolkit::*",
        "function inc(n: nat): nat { }",
        machine("var n: nat, r: real, b: boolean, s: Set(nat)",
                action="n = (override(inc, {(| 0, 2 |)}) as nat -> nat)(0) ; n = r as nat ; b = s is nat <-> nat ; "
                       "n = (inc as nat <-> boolean)(1) ; s = b as Set(nat)"),
    ])  # fmt: skip
    assert diagnostics(text) == [
        error(text, "(inc as", "only a function can be called, and this is nat <-> boolean"),
        error(text, "nat <-> boolean", "a value of type (nat) -> nat cannot be cast as nat <-> boolean"),
        error(text, "Set(nat)", "a value of type boolean cannot be cast as Set(nat)", 2),
    ]


def test_enumeration_literals_of_the_file_need_no_qualification():
    """RoboTool's innermost scope for names in expressions: the literals of the enumerations the
    file declares, before variables and functions (K9)."""
    text = "\n".join([
        "enumeration E { VA VB EM(nat) }",
        machine("var e: E, VB: nat", action="e = VA ; e = VB ; e = EM(1) ; e = EM ; e = EM(true) ; e = VC"),
    ])  # fmt: skip
    assert diagnostics(text) == [
        error(text, "EM ;", "enumeration literal 'EM' carries 1 value: write EM(nat)"),
        error(text, "true", "argument 1 of enumeration literal 'EM' must be nat, but this is boolean"),
        error(text, "VC", "unknown name 'VC'"),
    ]


def test_enumeration_literals_of_other_files_are_qualified():
    texts = {
        "types.rct": "package p\nenumeration Colour { red green }",
        "m.rct": "package p\n" + machine("var c: Colour", action="c = Colour::red ; c = green"),
    }
    m = texts["m.rct"]
    assert diagnostics(m, others={"types.rct": texts["types.rct"]}) == [error(m, "green", "unknown name 'green'")]


def test_variables_shadow_functions_and_operations_are_not_values():
    text = "\n".join([
        "function f(x: nat): boolean { }",
        "interface Ops { op(x: nat) }",
        machine("requires Ops", "var f: nat -> nat, n: nat", action="n = f(1) ; n = op(1)"),
    ])  # fmt: skip
    assert diagnostics(text) == [
        error(text, "op(1)", "'op' is an operation; operations are called as statements, not in expressions"),
    ]


def test_generic_functions_bind_their_type_variables_at_each_call():
    text = "\n".join([
        "function pick(s: Set(?X)): ?X { }",
        "function pair(a: ?X, b: ?X): ?X * ?X { }",
        machine("var n: nat, b: boolean, r: real", action="n = pick({1, 2}) ; b = pick({true}) ; r = pick({1.5})[1] ; "
                                                          "n = pair(1, 2)[2] ; r = pair(1, 2.5)[1] ; n = pair(1, true)[1]"),
    ])  # fmt: skip
    assert diagnostics(text) == [
        error(text, "pick({1.5})[1]", "real cannot be indexed"),
        error(text, "true)", "argument 'b' of function 'pair' must be nat, but this is boolean"),
    ]
