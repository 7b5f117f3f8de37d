"""Where robogen's typing was stricter than RoboTool's, it follows RoboTool's source: each test
names the rule of RoboCalcTypeProvider.xtend or RoboChartValidator.xtend (robochart-textual) that
decides. (What code generation makes of them: tests/codegen/test_typing_rules.py.)"""

from __future__ import annotations

from support.frontend import diagnostics, error, machine

INPUTS = "interface I { event r: real event n: nat event z: int }"


def test_a_real_event_may_be_received_into_an_integer_variable():
    """RoboChartValidator, InputCommunicationTypeError: typeCompatible(t.parameter.type,
    t.event.type) - the variable's type must fit the event's, so int and nat fit real (the value
    is converted when received); the other way, robogen's rule that a value may be stored
    (nat into int) still holds."""
    text = "\n".join([INPUTS, machine("uses I", "var k: int, u: nat, x: real, b: boolean",
                                      "transition t1 { from A to A trigger r?k }", "transition t2 { from A to A trigger r?u }",
                                      "transition t3 { from A to A trigger n?x }", "transition t4 { from A to A trigger z?u }",
                                      "transition t5 { from A to A trigger r?b }")])
    assert diagnostics(text) == [error(text, "b }", "cannot receive a value of event 'r' (real) into 'b' (boolean)")]


def test_a_connection_may_widen_a_number():
    """RoboChartValidator, RPConnectionIncompatibleType: typeCompatible(c.efrom.type,
    c.eto.type) - nat to int, nat or int to real; never real to an integer."""
    text = "\n".join([
        "stm M {\n\tevent i: int\n\tevent x: real\n\tevent o: nat\n\tinitial i0\n\tstate A { }\n\ttransition t0 { from i0 to A }\n}",
        "controller C {\n\tevent n: nat\n\tevent r: real\n\tevent back: real\n\tsref m = M",
        "\tconnection C on n to m on i\n\tconnection C on n to m on x\n\tconnection m on i to C on back\n\tconnection C on r to m on o\n}",
    ])
    assert [d for d in diagnostics(text) if d[0] == "error"] == [
        error(text, "n to m on x", "event 'n' of 'C' is connected twice"),
        error(text, "connection C on r to m on o",
              "connected events have different types: 'r' of 'C' carries real, 'o' of 'm' carries nat"),
    ]


def test_two_strings_concatenate():
    """RoboCalcTypeProvider.typeFor, case Cat: typeCompatible(t1, string) and typeCompatible(t2,
    string) give string."""
    text = machine('var s: string, q: Seq(nat)', action='s = "a" ^ s ; s = s cat "b" ; q = q ^ <1> ; q = "a" ^ q')
    assert diagnostics(text) == [error(text, '"a" ^ q', "'^' concatenates sequences or strings, not string")]


def test_a_set_range_of_reals_is_a_set_of_reals():
    """RoboCalcTypeProvider.typeFor, case SetRange: bounds compatible with real give Set(real)."""
    text = machine("var s: Set(real), t: Set(int)", action="s = {0.5 to 2.5} ; t = {1 to 3} ; t = {true to 2}")
    assert diagnostics(text) == [error(text, "true", "a set range needs numeric bounds, not boolean")]


def test_a_comprehension_of_several_variables_without_a_term_is_a_set_of_tuples():
    """RoboCalcTypeProvider.typeFor(SetComp): without '@ e', the variable's type, or the product
    of the variables' types when there are several."""
    text = machine("var p: Set(nat * int), s: Set(nat)",
                   action="p = {x: nat, y: int | x < y} ; s = {x: nat | x < 3} ; s = {x: nat, y: nat | x < y}")
    assert diagnostics(text) == [error(text, "{x: nat, y: nat | x < y}", "cannot assign Set(nat * nat) to 's' of type Set(nat)")]


def test_the_transpose_of_a_vector_is_a_matrix_of_one_row():
    """RoboCalcTypeProvider.typeFor, case TransposeExp: a VectorType gives a MatrixType of one row
    and the vector's size as its columns."""
    text = machine("var v: vector(real, 3), m: matrix(real, 1, 3), w: matrix(real, 3, 1)",
                   action="m = transpose(v) ; w = transpose(transpose(v)) ; m = inverse(v)")
    assert diagnostics(text) == [error(text, "v)", "'inverse' needs a matrix, not vector(real, 3)", occurrence=3)]
