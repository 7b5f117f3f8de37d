"""robogen.semantics.exprs: types of expressions and statements, the rules on where each form
may appear, and RoboSim's rules on inputs and outputs. Golden messages, located by the text
they must point at."""

from __future__ import annotations

from support.frontend import at, diagnostics, error, machine, robosim, shallow_stack, warning

from robogen.semantics import check_texts


# ---------------------------------------------------------------------------- RoboChart types


def test_a_condition_must_be_boolean():
    text = machine("var x: nat", "transition t1 { from A to A condition x + 1 }")
    assert diagnostics(text) == [error(text, "x + 1", "a condition must be boolean, but this is nat")]


def test_calls_check_arity_and_argument_types():
    text = "\n".join([
        "function f(x: nat): nat { }",
        "interface Ops { op(a: nat, b: real) }",
        machine("requires Ops", "var y: nat", action="y = f(1, 2) ; y = f(true) ; op(1) ; op(1, false)"),
    ])  # fmt: skip
    assert diagnostics(text) == [
        error(text, "f(1, 2)", "function 'f' takes 1 argument, but 2 were given"),
        error(text, "true", "argument 'x' of function 'f' must be nat, but this is boolean"),
        error(text, "op(1)", "operation 'op' takes 2 arguments, but 1 was given"),
        error(text, "false", "argument 'b' of operation 'op' must be real, but this is boolean"),
    ]


def test_toolkit_functions_check_their_arguments():
    text = "\n".join([
        "import set_toolkit::*",
        "import sequence_toolkit::*",
        machine("var s: Set(nat), q: Seq(nat), n: nat", action="n = size(q, q) ; s = union(s, q) ; n = head(s)"),
    ])  # fmt: skip
    assert [d[1:] for d in diagnostics(text)] == [
        (*at(text, "size(q, q)"), "'size' takes 1 argument(s), not 2"),
        (*at(text, "union(s, q)"), "'union' expects sets, not Seq(nat)"),
        (*at(text, "head(s)"), "'head' expects a sequence, not Set(nat)"),
    ]


def test_enumeration_literals_with_values():
    text = "\n".join([
        "enumeration E { red blue(nat) }",
        machine("var e: E", action="e = E::blue ; e = E::blue(true) ; e = E::red(1) ; e = E::blue(2) ; e = E::reed"),
    ])  # fmt: skip
    assert diagnostics(text) == [
        error(text, "E::blue ;", "enumeration literal 'E::blue' carries 1 value: write E::blue(nat)"),
        error(text, "true", "argument 1 of enumeration literal 'E::blue' must be nat, but this is boolean"),
        error(text, "E::red(1)", "enumeration literal 'E::red' takes 0 arguments, but 1 was given"),
        error(text, "E::reed", "enumeration 'E' has no literal 'reed' (did you mean 'red'?)"),
    ]


def test_operators_check_their_operands():
    text = machine(
        "var n: nat, r: real, b: boolean, s: Set(nat), q: Seq(nat)",
        action="b = not n ; n = n + b ; n = r % 2 ; b = n == b ; b = b < 1 ; b = n in q ; b = b in s ; q = q cat n ; s = s + s",
    )
    assert diagnostics(text) == [
        error(text, "n ;", "'not' needs a boolean operand, not nat"),
        error(text, "b ;", "'+' needs numbers, not boolean"),
        error(text, "r % 2", "cannot assign real to 'n' of type nat"),  # '%' of reals is a real, as in RoboTool (K11)
        error(text, "n == b", "cannot compare nat with boolean"),
        error(text, "b < 1", "'<' needs numbers, not boolean"),
        error(text, "b in s", "boolean cannot be a member of Set(nat)"),
        error(text, "n ; s", "'cat' concatenates sequences or strings, not nat"),
        error(text, "s + s", "'+' is not defined on sets; use union, inter or diff"),
    ]


def test_structured_values():
    text = "\n".join([
        "datatype P { x: real y: real }",
        machine(
            "var p: P, n: nat, t: nat * boolean, s: Set(nat)",
            action="n = p.z ; n = n.x ; p = P(| x = 1.0 |) ; p = P(| x = true, y = 1.0, w = 2 |) ; n = t[3] ; "
            "n = if n > 1 then 1 else true end ; s = {1, true} ; n = <1>",
        ),
    ])  # fmt: skip
    assert diagnostics(text) == [
        error(text, "z ;", "datatype 'P' has no field 'z'"),
        error(text, "n.x", "'.x' selects a field, but this is nat, not a record", 1),
        warning(text, "P(| x = 1.0 |)", "field 'y' of 'P' is not given a value"),  # RoboTool checks only the fields given (K10)
        error(text, "true,", "field 'x' must be real, but this is boolean"),
        error(text, "w = 2", "datatype 'P' has no field 'w'"),
        error(text, "3]", "tuple of 2 components has no component 3"),
        error(text, "if n > 1", "the branches of 'if' have different types: nat and boolean"),
        error(text, "true}", "the elements of a set must have one type: nat and boolean"),
        error(text, "<1>", "cannot assign Seq(nat) to 'n' of type nat"),
    ]


def test_names_that_are_not_values():
    text = "\n".join([
        "interface Ops { op() }",
        "function f(x: nat): nat { }",
        machine("requires Ops", "event e", "clock C", "var n: nat, m: nat", action="n = e ; n = C ; n = op() ; f(1) ; n = nn ; nope()"),
    ])  # fmt: skip
    assert diagnostics(text) == [
        error(text, "e ;", "'e' is an event; events are not values"),
        error(text, "C ;", "'C' is a clock; write since(C) for the time since its reset"),
        error(text, "op() ;", "'op' is an operation; operations are called as statements, not in expressions"),
        error(text, "f(1)", "'f' is a function; a function call is an expression, not a statement"),
        error(text, "nn", "unknown name 'nn' (did you mean 'n'?)"),
        error(text, "nope()", "unknown operation 'nope' (did you mean 'op'?)"),
    ]


def test_binders_and_descriptions():
    text = machine(
        "var b: boolean, n: nat",
        action="b = forall x: nat | x @ x > 1 ; b = exists x: nat @ x + 1 ; n = the x: nat | x > 1 @ x * 2 ; "
        "b = the x: nat | x > 1 @ x ; n = let k == true @ k",
    )
    assert diagnostics(text) == [
        error(text, "x @ x > 1", "the predicate after '|' must be boolean, not nat"),
        error(text, "x + 1", "the body of 'exists' must be boolean, not nat"),
        error(text, "the x: nat | x > 1 @ x ;", "cannot assign nat to 'b' of type boolean"),
        error(text, "let k", "cannot assign boolean to 'n' of type nat"),
    ]


def test_result_only_in_postconditions():
    text = "function f(x: nat): boolean {\n\tprecondition result\n\tpostcondition result == (x > 1)\n\tpostcondition x\n}"
    assert diagnostics(text) == [
        error(text, "result", "'result' is only meaningful in a postcondition"),
        error(text, "x\n}", "a postcondition must be boolean, not nat"),
    ]


# ---------------------------------------------------------------------------- communication


# ---------------------------------------------------------------------------- RoboChart time


def test_since_is_allowed_only_in_guards():
    text = machine("var n: nat", "clock C", action="n = since(C) ; n = sinceEntry(A)")
    assert diagnostics(text) == [
        error(text, "since(C)", "'since' may only appear in a transition condition"),
        error(text, "sinceEntry(A)", "'sinceEntry' may only appear in a transition condition"),
    ]


def test_since_should_be_compared_with_a_constant():
    text = machine(
        "var n: nat",
        "const k: nat = 3",
        "clock C",
        "transition t1 { from A to A condition since(C) > n }",
        "transition t2 { from A to A condition since(C) > k + 1 /\\ n < sinceEntry(A) }",
    )
    assert diagnostics(text) == [
        warning(text, "n }", "'since' should be compared with a constant"),
        warning(text, "n < sinceEntry", "'sinceEntry' should be compared with a constant"),
    ]


def test_the_empty_tuple_is_the_empty_product():
    text = machine("var u: nat * nat, b: boolean", action="b = (||) == (||) ; u = (||)")
    assert diagnostics(text) == [error(text, "(||) }", "cannot assign empty product to 'u' of type nat * nat")]


def test_a_comparison_the_type_of_a_nat_decides_is_a_warning():
    text = machine(
        "var k: nat, i: int, b: boolean",
        "clock C",
        "transition t1 { from A to A condition k >= 0 \\/ since(C) < 0 }",
        action="b = 0 <= (k) ; b = k > -1 ; b = k == -2 ; b = -0.5 >= k ; b = k > 0 ; b = i >= 0 ; b = k - 1 >= 0 ; b = 0 >= -1",
    )
    never = "a nat is never negative"
    assert diagnostics(text) == [
        warning(text, "k >= 0", f"'k >= 0' is always true for nat k: {never}"),
        warning(text, "since(C) < 0", f"'since(C) < 0' is always false for nat since(C): {never}"),
        warning(text, "0 <= (k)", f"'0 <= k' is always true for nat k: {never}"),
        warning(text, "k > -1", f"'k > -1' is always true for nat k: {never}"),
        warning(text, "k == -2", f"'k == -2' is always false for nat k: {never}"),
        warning(text, "-0.5 >= k", f"'-0.5 >= k' is always false for nat k: {never}"),
    ]


def test_the_model_says_which_comparisons_are_constant_and_their_value():
    text = machine("var k: nat, b: boolean", action="b = k >= 0 ; b = 0 > k ; b = k > 0")
    model = check_texts({"m.rct": text})
    values = [model.constant_comparison(s.value) for s in model.files[0].items[0].members[-1].action.stmts]
    assert values == [True, False, None]
    assert model.constant_comparison(model.files[0].items[0].members[-1].action.stmts[0].target) is None


def test_a_flat_expression_of_a_thousand_operands_checks():
    n = 1000
    total = " + ".join(f"x * {i}" for i in range(n))
    every = " /\\ ".join(f"x > {i} \\/ b" for i in range(n))
    text = machine(
        "var x: nat, y: int, b: boolean",
        "event e: int",
        f"transition t1 {{ from A to A condition {every} }}",
        action=f"y = {total} - 1 ; e!({total}) ; b = {every}",
    )
    with shallow_stack():
        model = check_texts({"m.rct": text})
    assert model.diagnostics == ()
    assign = model.files[0].items[0].members[-1].action.stmts[0]
    assert model.type_of(assign.value).show() == "int" and model.type_of(assign.value.left).show() == "nat"
    # a mistake deep inside a flat expression is located at the operand
    bad = text.replace("x * 500 +", "true +", 1)
    with shallow_stack():
        assert diagnostics(bad) == [error(bad, "true +", "'+' needs numbers, not boolean")]


def test_clocks_and_states_named_by_time_expressions_must_exist():
    text = machine("clock C", "final F", "transition t1 { from A to A condition since(D) > 1 \\/ sinceEntry(B) > 1 \\/ sinceEntry(F) > 1 }", action="#D")
    assert diagnostics(text) == [
        error(text, "D) >", "unknown clock 'D'"),
        error(text, "B)", "no state 'B' in state machine 'S'"),
        error(text, "F) >", "'sinceEntry' of a final state"),
        error(text, "D }", "unknown clock 'D'"),
    ]


# ---------------------------------------------------------------------------- RoboSim


def test_robosim_inputs_are_read_in_conditions_and_outputs_written_in_actions():
    text = robosim(
        "var x: nat, f: boolean",
        "input context { event i1: nat }",
        "output context { event o1: nat event o2 }",
        "transition t1 { from A to A condition $o1 \\/ $i1?x }",
        action="$i1!1 ; f = $i1?x ; $o2!3 ; $o1 ; $nope",
    )
    assert diagnostics(text, "m.rst") == [
        error(text, "o1 \\/", "'o1' is an output event; output events cannot be tested in a condition"),
        error(text, "i1!1", "'i1' is an input event; an input event cannot be written"),
        error(text, "$i1?x ;", "'$i1?x' tests an input and may only appear in a transition condition"),
        error(text, "o2!3", "event 'o2' carries no value"),
        error(text, "$o1 ;", "event 'o1' carries nat: write $o1!v"),
        error(text, "nope", "unknown event 'nope'"),
    ]


def test_robosim_bindings_and_shared_variables():
    text = "\n".join([
        "interface Shared { var level: real const limit: real }",
        "interface Ops { move(x: real) }",
        robosim(
            "var b: boolean",
            "const k: nat = 1",
            "input context { event n: nat requires Shared }",
            "output context { requires Ops }",
            "transition t1 { from A to A condition $n?b \\/ $n?k \\/ $n?zz }",
            action="$limit = 1.0 ; $level = true ; $volume = 2 ; move(1.0) ; $move(true) ; $stop()",
        ),
    ])  # fmt: skip
    assert diagnostics(text, "m.rst") == [
        error(text, "b \\/", "cannot bind a value of event 'n' (nat) to 'b' (boolean)"),
        error(text, "k \\/", "cannot bind the value of 'n' to constant 'k'"),
        error(text, "zz", "unknown variable 'zz'"),
        error(text, "limit =", "cannot assign to constant 'limit'"),
        error(text, "true", "cannot assign boolean to 'level' of type real"),
        error(text, "volume", "unknown shared variable 'volume'"),
        error(text, "move(1.0)", "'move' is a platform operation; RoboSim calls it as $move(...)"),
        error(text, "true", "argument 'x' of operation 'move' must be real, but this is boolean", 2),
        error(text, "stop", "unknown platform operation 'stop'"),
    ]


def test_robosim_time_is_compared_with_any_number():
    text = machine(
        "cycleDef cycle == 1",
        "var n: nat",
        "clock C",
        "transition t1 { from A to A exec condition since(C) > n * cycle }",
        "transition t2 { from A to A exec condition since(C) <= n * cycle }",
        path="m.rst",
    )
    assert diagnostics(text, "m.rst") == []


def test_a_qualified_literal_whose_enumeration_is_not_imported_is_reported_at_each_use(monkeypatch):
    """A qualified literal is looked up once per file and text when that reports nothing; one
    whose lookup warns (the enumeration is not imported) warns at each of its uses."""
    from robogen.semantics.exprs import ExprChecker

    calls = []
    find = ExprChecker._enum_literal

    def counted(self, e, report):
        calls.append(e.text)
        return find(self, e, report)

    monkeypatch.setattr(ExprChecker, "_enum_literal", counted)
    shared = "package p1\nenumeration E { a b }\n"
    uses = "\n".join([
        "package p2",
        "enumeration F { c d }",
        "stm S {",
        "\tvar x: p1::E",
        "\tvar f: F",
        "\tvar y: boolean",
        "\tinitial i",
        "\tstate A { entry x = E::a ; f = F::c }",
        "\ttransition t0 { from i to A action y = x == E::b }",
        "\ttransition t1 { from A to A condition x == E::a /\\ f == F::c }",
        "}",
    ])  # fmt: skip
    result = check_texts({"a.rct": shared, "b.rct": uses})
    message = "'E' is not imported here; using 'p1::E'"
    assert [(d.span.path, d.span.line, d.span.column, d.message) for d in result.diagnostics] == [
        ("b.rct", *at(uses, "E::a ;"), message),
        ("b.rct", *at(uses, "E::b"), message),
        ("b.rct", *at(uses, "E::a /\\"), message),
    ]
    assert sorted(calls) == ["E::a", "E::a", "E::b", "F::c"]  # F::c, which reports nothing, once


def test_an_empty_collection_takes_the_type_of_the_typed_one_beside_it():
    """Found by the model fuzzer: `{}` and `<>` have elements of no type; in a conditional or a
    set literal beside a typed collection they take its type (the conditional was typed by its
    empty branch, so `dom(if b then {} else {(| 2, 0 |)} end)` was a set of ?X, and
    `Inter({{}, {R(...)}})` a set of sets of ?X; code generation refused both)."""
    text = machine("var b: boolean", "var r: Set(nat)", "var q: Seq(boolean)",
                   action="r = dom(if b then {} else {(| 2, 0 |)} end) ; q = if b then <> else <true> end ; "
                          "r = Union({{}, {3}})", path="m.rct")
    model = check_texts({"m.rct": "import relation_toolkit::*\nimport set_toolkit::*\n" + text})
    assert model.diagnostics == ()
    first, second, third = model.files[0].items[0].members[-1].action.stmts
    assert model.type_of(first.value.args[0]).show() == "Set(nat * nat)"
    assert model.type_of(second.value).show() == "Seq(boolean)"
    assert model.type_of(third.value.args[0]).show() == "Set(Set(nat))"
