"""robogen.semantics.dollar: RoboSim's $ forms anywhere an expression can be, typed as RoboSim's
type provider types them, with names qualified by where they are declared (K7)."""

from __future__ import annotations

from support.frontend import diagnostics, error, robosim

INTERFACES = "\n".join([
    "datatype Pose { x: real y: real }",
    "interface Shared { var level: nat var pose: Pose var gains: vector(real, 2) }",
    "interface Inputs { event In: boolean event reading: nat }",
    "interface Outputs { event Out1: nat event Out2: boolean }",
])  # fmt: skip
CONTEXTS = ("input context { uses Inputs requires Shared }", "output context { uses Outputs }")


def test_dollar_forms_are_values_of_outputs_and_operands_anywhere():
    text = INTERFACES + "\n" + robosim(
        *CONTEXTS, "var n: nat, r: real",
        action="$Out1!$level ; $Out2.$In ; $Out1!f($level) ; r = $pose.x * $gains[1] ; n = if $In then $level else 0 end",
    )
    assert diagnostics(text.replace("f($level)", "($level + 1)"), "m.rst") == []


def test_qualified_names_after_dollar_name_where_they_are_declared():
    text = INTERFACES + "\n" + robosim(
        *CONTEXTS, "var n: nat",
        "transition t1 { from A to A exec condition $Inputs::reading?S::n \\/ $Shared::level > 1 }",
        action="$Outputs::Out1!$S::level ; $Shared::gains = $gains ; $Inputs::Out2!true",
    )
    assert diagnostics(text, "m.rst") == [
        error(text, "S::level", "'S::level' does not name 'level' of state machine 'S'"),
        error(text, "Inputs::Out2", "'Inputs::Out2' does not name 'Out2' of state machine 'S'"),
    ]


def test_a_field_of_a_record_variable_and_what_dollar_cannot_select():
    text = INTERFACES + "\n" + robosim(
        *CONTEXTS, "var r: real",
        action="r = $pose.x ; r = $pose.z ; r = $level.x ; r = $Out1",
    )
    assert diagnostics(text, "m.rst") == [
        error(text, "z ;", "datatype 'Pose' has no field 'z'"),
        error(text, "$level.x", "after $level, a variable of type nat, '.' selects a field of a record"),
        error(text, "$Out1", "cannot assign boolean to 'r' of type real"),
        error(text, "Out1", "'Out1' is an output event; output events cannot be tested in a condition", 2),
    ]


def test_a_call_through_dollar_calls_a_function_variable_and_never_an_operation():
    text = "\n".join([
        "interface Scaling { var scale: real -> real }",
        "interface Motors { move(v: real) }",
        robosim("input context { requires Scaling }", "output context { requires Motors }", "var r: real",
                action="r = $scale(2.0) ; $move($scale(r)) ; r = $scale(true) ; r = $move(1.0) ; r = $scale()"),
    ])  # fmt: skip
    assert diagnostics(text, "m.rst") == [
        error(text, "true", "argument 1 of this function of type real -> real must be real, but this is boolean"),
        error(text, "$move(1.0)", "'move' is an operation; operations are called as statements, not in expressions"),
        error(text, "$scale()", "this function of type real -> real takes 1 argument, but 0 were given"),
    ]
