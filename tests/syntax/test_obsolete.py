"""Forms of RoboTool's older grammars (robogen.syntax.transform_obsolete), found in the history of
RoboChart.xtext and RoboSim.xtext: each is read as the tree of its current form, with a warning
naming that form; the two forms that have no current form are located errors that say so."""

from __future__ import annotations

import pytest

from robogen.diagnostics import RobogenError
from robogen.semantics import check_texts
from robogen.syntax.parser import parse_text

MACHINE = "stm M {{\n\tclock C\n\tvar x: nat = 0\n\tinitial i\n\tstate S {{ }}\n\ttransition t0 {{ from i to S }}\n\t{}\n}}\n"


def read(text: str, path: str) -> tuple[object, list[tuple[int, int, str, str]]]:
    """The tree of ``text`` and its notices: (line, column, message, note)."""
    f = parse_text(text, path)
    return f, [(d.span.line, d.span.column, d.message, d.notes[0].message) for d in f.notices]


EMPTY_TRIGGER = ("obsolete syntax: a bare 'trigger' (RoboTool's empty trigger, before its grammar of 2020-11) is read as no "
                 "trigger", "write the transition without the word 'trigger' (clock resets follow 'to')")


@pytest.mark.parametrize("old, current", [
    ("transition t1 { from S to S trigger action x = x + 1 }", "transition t1 { from S to S action x = x + 1 }"),
    ("transition t1 { from S to S trigger #C condition since(C) > 2 }",  # the clock resets of the old Trigger rule
     "transition t1 { from S to S #C condition since(C) > 2 }"),
    ("transition t1 { from S to S trigger\n}", "transition t1 { from S to S\n}"),
])
def test_a_bare_trigger_is_the_empty_trigger(old, current):
    got, notices = read(MACHINE.format(old), "m.rct")
    assert got == parse_text(MACHINE.format(current), "m.rct")
    assert notices == [(7, 30, *EMPTY_TRIGGER)]
    assert not check_texts({"m.rct": MACHINE.format(old)}).errors


def test_the_power_vector_type_is_a_vector():
    got, notices = read(MACHINE.format("var v: real^3, w: Set(nat)^2"), "m.rct")
    assert got == parse_text(MACHINE.format("var v: vector(real, 3), w: vector(Set(nat), 2)"), "m.rct")
    assert notices == [
        (7, 9, "obsolete syntax: the vector type 'real^3' (RoboTool's grammar of 2020-02) is read as a vector",
         "write 'vector(real, 3)'"),
        (7, 20, "obsolete syntax: the vector type 'Set(nat)^2' (RoboTool's grammar of 2020-02) is read as a vector",
         "write 'vector(Set(nat), 2)'"),
    ]


SIM = ("stm M {{\n\tcycleDef cycle == 1\n\toutput context {{ event e: nat event f }}\n\tinitial i\n\tstate S {{ }}\n"
       "\ttransition t0 {{ from i to S action {} }}\n\ttransition t1 {{ from S to S exec }}\n}}\n")


def test_send_before_a_robosim_output_is_ignored():
    got, notices = read(SIM.format("send $e!1 ; send $e.2 ; send $f"), "m.rst")
    assert got == parse_text(SIM.format("$e!1 ; $e.2 ; $f"), "m.rst")
    assert [(line, column, note) for line, column, _, note in notices] == [
        (6, 37, "write '$e!1' without 'send'"), (6, 49, "write '$e.2' without 'send'"), (6, 61, "write '$f' without 'send'")]
    assert {message for _, _, message, _ in notices} == {
        "obsolete syntax: 'send' before a RoboSim output (before RoboTool's grammar of 2021-08) is ignored"}


CONST_CYCLE = """stm M {{
{}\tcycleDef cycle == 1
\tinitial i
\tstate S {{ }}
\ttransition t0 {{ from i to S }}
\ttransition t1 {{ from S to S exec }}
}}
controller C {{
{}\tcycleDef cycle == 1
\tsref m = M
}}
module Mod {{
{}\tcycleDef cycle == 1
\tcref c = C
\trref p = P
}}
robotic platform P {{ }}
"""


def test_the_constant_cycle_of_early_robosim_is_dropped():
    old = CONST_CYCLE.format(*["\tconst cycle: nat\n"] * 3)
    got, notices = read(old, "m.rst")
    assert got == parse_text(CONST_CYCLE.format("", "", ""), "m.rst")
    assert [(line, column) for line, column, _, _ in notices] == [(2, 2), (10, 2), (15, 2)]
    assert notices[0][2:] == ("obsolete syntax: 'const cycle' (RoboSim before 2019-07) is dropped: 'cycle' is implicit",
                              "remove the declaration; 'cycleDef cycle == p' defines the period")
    model = check_texts({"m.rst": old})
    assert not model.errors and len(model.warnings) == 3


TIME_BINDING = ("the time binding '@ t' of a trigger was removed from RoboChart (RoboTool's grammar of 2020-11) and has no "
                "current form: measure time with a clock, reset on the transition ('#C') and read with 'since(C)'")
START_DEADLINE = ("start deadlines '{ d }>' were removed from RoboChart (RoboTool's grammar of 2020-10) and have no current "
                  "form: a deadline '<{ d }' after a trigger or a statement bounds when it ends")


@pytest.mark.parametrize("transition, column, note", [
    ("transition t1 { from S to S trigger e @ x }", 40, TIME_BINDING),
    ("transition t1 { from S to S trigger @ x }", 38, TIME_BINDING),
    ("transition t1 { from S to S trigger {2}> e }", 38, START_DEADLINE),
    ("transition t1 { from S to S action {1}> e <{3} }", 37, START_DEADLINE),
])
def test_forms_removed_without_a_successor_stay_syntax_errors_that_say_so(transition, column, note):
    text = "interface I { event e }\n" + MACHINE.format(transition).replace("\tclock C\n", "\tuses I\n\tclock C\n")
    with pytest.raises(RobogenError) as exc:
        parse_text(text, "m.rct")
    (d,) = exc.value.diagnostics
    assert (d.span.line, d.span.column, d.message.split(";")[0]) == (9, column, f"unexpected '{transition[column - 2]}'")
    assert d.notes[-1].message == note


def test_a_syntax_error_after_a_type_does_not_propose_the_obsolete_vector_type():
    with pytest.raises(RobogenError) as exc:
        parse_text("stm M { var x: nat 2 }", "m.rct")
    message = exc.value.diagnostics[0].message
    assert message.startswith("unexpected integer '2'; expected one of '}', '*', ',', '->',") and "'^'" not in message
