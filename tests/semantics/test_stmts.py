"""robogen.semantics.stmts: statements and communications, their types and where each may
appear (RoboChart and RoboSim). Golden messages, located by the text they must point at."""

from __future__ import annotations

from support.frontend import diagnostics, error, machine, robosim

from robogen.semantics import check_texts


def test_assignments_are_typed():
    text = machine("var x: nat, r: real, b: boolean", action="x = true ; x = r ; r = x ; b = 1 < 2 ; x = -1")
    # nat := int is accepted (RoboChart writes n = n - 1 for a nat n); real never narrows
    assert diagnostics(text) == [
        error(text, "true", "cannot assign boolean to 'x' of type nat"),
        error(text, "r ;", "cannot assign real to 'x' of type nat"),
    ]


def test_constants_parameters_and_bound_names_cannot_be_assigned():
    text = machine("const k: nat = 1", action="k = 2")
    assert diagnostics(text) == [error(text, "k = 2", "cannot assign to constant 'k'")]
    text = "operation Op(n: nat) {\n\tinitial i\n\tfinal f\n\ttransition t { from i to f action n = 1 }\n}"
    assert diagnostics(text) == [error(text, "n = 1", "cannot assign to parameter 'n'")]


def test_calling_an_operation_the_machine_does_not_require():
    text = "\n".join([
        "operation Go() {\n\tinitial i\n\tfinal f\n\ttransition t { from i to f }\n}",
        machine(action="Go()"),
    ])  # fmt: skip
    result = diagnostics(text)
    assert result == [error(text, "Go()", "unknown operation 'Go'", 2)]
    (d,) = check_texts({"m.rct": text}).diagnostics
    assert [n.message for n in d.notes] == [
        "'Go' is defined here but not required by this state machine: add 'requires' of an interface declaring it"
    ]
    assert (d.notes[0].span.line, d.notes[0].span.column) == (1, 11)


def test_robochart_communications_are_typed():
    text = "\n".join([
        "interface E { event n: nat event b event r: real }",
        machine(
            "uses E",
            "var x: nat, flag: boolean",
            "const k: nat = 1",
            "transition t1 { from A to A trigger n?flag }",
            "transition t2 { from A to A trigger r }",
            "transition t3 { from A to A trigger b?x }",
            "transition t4 { from A to A trigger n!x }",
            "transition t5 { from A to A trigger n?k }",
            action="send n!true ; send n ; b!1 ; n?zz ; nope",
        ),
    ])  # fmt: skip
    assert diagnostics(text) == [
        error(text, "flag }", "cannot receive a value of event 'n' (nat) into 'flag' (boolean)"),
        error(text, "b?x", "event 'b' carries no value"),
        error(text, "n!x", "a trigger is a plain event or an input (e or e?x), not an output (rule T2)"),
        error(text, "k }", "cannot receive into constant 'k'"),
        error(text, "true", "event 'n' carries nat, but this value is boolean"),
        error(text, "n ; b!1", "event 'n' carries nat: send a value with n!v or receive it with n?x"),
        error(text, "b!1", "event 'b' carries no value"),
        error(text, "zz", "unknown variable 'zz'"),
        error(text, "nope", "unknown event 'nope'"),
    ]


def test_wait_takes_an_integer_or_a_set_of_integers():
    text = machine("var r: real", action="wait(r) ; wait(true) ; wait({1, 2}) ; wait([1, 3]) ; wait(2)")
    assert diagnostics(text) == [
        error(text, "r) ;", "'wait' takes an integer number of time units, or a set of them; this is real"),
        error(text, "true", "'wait' takes an integer number of time units, or a set of them; this is boolean"),
    ]


def test_robosim_forbids_robochart_statements():
    text = robosim("output context { event o: nat }", action="wait(1) ; send o!1 ; o!1 ; (skip <{ 2 })")
    assert diagnostics(text, "m.rst") == [
        error(text, "wait(1)", "RoboSim has no 'wait': time passes in cycles; count cycles with a clock and 'since'"),
        error(text, "send o!1", "RoboChart communication statements are not allowed in RoboSim; write $e, $e!v or $op(...)"),
        error(text, "o!1 ;", "RoboChart communication statements are not allowed in RoboSim; write $e, $e!v or $op(...)", 2),
        error(text, "(skip <{ 2 })", "deadlines '<{ }' mean nothing in RoboSim and are rejected"),
    ]


def test_a_required_operation_may_be_called_by_its_qualified_name():
    text = "\n".join([
        "package p",
        "interface I { move() }",
        "operation move() { initial i final f transition t { from i to f } }",
        machine("requires I", action="p::move() ; move() ; q::move()"),
    ])  # fmt: skip
    assert diagnostics(text) == [error(text, "q::move()", "unknown operation 'q::move' (did you mean 'move'?)")]


def test_synchronisations_carry_any_value_and_inputs_name_qualified_variables():
    """K13: the value after '.' is any atom or call, typed against the event; the variable of
    an input may be qualified by the machine or interface that declares it (§3)."""
    text = "\n".join([
        "enumeration Chemical { innocuous toxic }",
        "interface Readings { var level: nat }",
        machine(
            "uses Readings",
            "var x: nat, c: Chemical",
            "event detect: Chemical",
            "event amount: nat",
            action="detect.Chemical::toxic ; amount.(x + 1) ; detect.3 ; amount?S::x ; amount?Readings::level ; "
                   "amount?Readings::x ; detect?T::c",
        ),
    ])  # fmt: skip
    assert diagnostics(text) == [
        error(text, "3 ;", "event 'detect' carries Chemical, but this value is nat"),
        error(text, "Readings::x", "'Readings::x' does not name 'x' of state machine 'S'"),
        error(text, "T::c", "'T::c' does not name 'c' of state machine 'S'"),
    ]
