"""tests/codegen/models/tagged.rct against a trace written by hand: enumeration literals with
arguments (``Move(real)``, ``Turn(nat, boolean)``) as values of variables, a constant and event
payloads, built with ``Turn(2, true)`` and compared: equal when the same literal with equal
arguments. At the FMU boundary a Cmd is the Enumeration variable ``.tag`` (Stop 0, Move 1,
Turn 2) and one clocked variable per argument (``.Move_1``, ``.Turn_1``, ``.Turn_2``); an
argument of a literal the tag does not select is its type's default (an input's is ignored).
"""

from __future__ import annotations

import pytest

from support.codegen_driver import Tick, build, outputs_by_instant
from robogen.codegen.api import compile_model


def cmd(tag: int, move: float = 0.0, turn: int = 0, left: bool = False) -> Tick:
    return Tick("cmd", {"cmd.tag": tag, "cmd.Move_1": move, "cmd.Turn_1": turn, "cmd.Turn_2": left})


def echo(tag: int, move: float = 0.0, turn: int = 0, left: bool = False) -> dict:
    return {"echo.tag": tag, "echo.Move_1": move, "echo.Turn_1": turn, "echo.Turn_2": left}


def run(built_fmu, inputs: dict[int, Tick], instants: int, functions: dict | None = None):
    return outputs_by_instant(built_fmu, inputs, instants, functions=functions)


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_literals_with_arguments_are_built_compared_and_sent(builds, semantics):
    inputs = {
        1: cmd(2, move=9.0, turn=2, left=True),  # Turn(2, true); Move_1 is not Turn's: ignored
        2: cmd(2, turn=2, left=True),  # the same again
        3: cmd(2, turn=2, left=False),  # Turn(2, false): another argument
        4: cmd(1, move=2.5),  # Move(2.5)
        5: cmd(0, turn=4),  # Stop; t1's condition reads last = Move(2.5): not taken
    }
    outputs, trace = run(builds.get("tagged", semantics), inputs, 7)
    # t=0: echo!c with c = Move(1.5); home = Turn(2, true) is not Turn(2, false)
    # t=1: c = Turn(2, true) == home; differs from last = Stop; echo without the ignored 9.0
    # t=2: equal to last; t=3: Turn(2, false) is neither home nor last; t=4: Move(2.5)
    assert outputs == {
        0: {"echo": echo(1, move=1.5), "same": {"same.value": False}},
        1: {"echo": echo(2, turn=2, left=True), "same": {"same.value": True}, "differs": {"differs.value": True}},
        2: {"echo": echo(2, turn=2, left=True), "same": {"same.value": True}, "differs": {"differs.value": False}},
        3: {"echo": echo(2, turn=2), "same": {"same.value": False}, "differs": {"differs.value": True}},
        4: {"echo": echo(1, move=2.5), "same": {"same.value": False}, "differs": {"differs.value": True}},
        5: {},
        6: {},
    }
    last = trace.steps[-1].variables
    # Stop waits in the buffer: c is bound only when t1 is taken, so it is still Move(2.5)
    assert (last["Driver.n"], last["Driver.c.tag"], last["Driver.c.Move_1"]) == (4, 1, 2.5)
    assert (last["Driver.home.tag"], last["Driver.home.Turn_1"], last["Driver.home.Turn_2"]) == (2, 2, True)


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_a_robosim_machine_reads_and_writes_literals_with_arguments(builds, semantics):
    inputs = {1: cmd(2, move=9.0, turn=2, left=True), 2: cmd(1, move=2.5), 3: cmd(0, turn=4), 4: cmd(2, turn=2)}
    outputs, trace = run(builds.get("taggedsim", semantics), inputs, 6)
    # a cycle with cmd decides t1 (an exec transition) and completes it, with its action, at the
    # start of the next cycle: the outputs of the command of cycle t come at t + 1. home =
    # Turn(2, true) and Stop are not counted, Move(2.5) and Turn(2, false) are; the arguments of
    # literals the tag does not select (9.0 of Move at t=1, 4 of Turn at t=3) are not echoed.
    assert outputs == {
        0: {},
        1: {},
        2: {"echo": echo(2, turn=2, left=True), "atHome": {"atHome.value": True}, "count": {"count.value": 0}},
        3: {"echo": echo(1, move=2.5), "atHome": {"atHome.value": False}, "count": {"count.value": 1}},
        4: {"echo": echo(0), "atHome": {"atHome.value": False}, "count": {"count.value": 1}},
        5: {"echo": echo(2, turn=2), "atHome": {"atHome.value": False}, "count": {"count.value": 2}},
    }
    assert trace.steps[-1].variables["Pilot.moves"] == 2


REACH = """package reach
enumeration Cmd { Stop Move(real) Turn(nat, boolean) }
function reach(c: Cmd): real { }
interface Io { event cmd: Cmd event out: real }
stm Arm {
	uses Io
	var c: Cmd = Stop
	initial i
	state S { }
	transition t0 { from i to S }
	transition t1 { from S to S trigger cmd?c action out!reach(c) }
}
"""
REACH_C = """static double rg_user_reach(rg_rec_reach_Cmd c)
{
    return c.tag == 1 ? c.Move_1 : c.tag == 2 && c.Turn_2 ? 10.0 * (double)c.Turn_1 : -1.0;
}
"""


def test_a_user_function_takes_the_tagged_struct(tmp_path):
    model, c_file = tmp_path / "reach.rct", tmp_path / "reach.c"
    model.write_text(REACH)
    c_file.write_text(REACH_C)
    python = {"reach": lambda c: c["Move_1"] if c["tag"] == 1 else 10.0 * c["Turn_1"] if c["tag"] == 2 and c["Turn_2"] else -1.0}
    built = build([model], tmp_path / "w", machine="Arm", functions=c_file)
    inputs = {1: cmd(1, move=0.5), 2: cmd(2, turn=3, left=True), 3: cmd(2, turn=3), 4: cmd(0, move=7.0)}
    outputs, _ = run(built, inputs, 5, functions=python)
    values = {t: o["out"]["out.value"] for t, o in outputs.items() if o}
    # Move(0.5): 0.5; Turn(3, true): 30; Turn(3, false): -1; Stop (its ignored 7.0): -1
    assert values == {1: 0.5, 2: 30.0, 3: -1.0, 4: -1.0}


def test_a_recursive_enumeration_is_unrolled_to_the_default_depth(tmp_path):
    """E { a b(E) } at the default --enum-depth 4: E, then E@3 down to E@0, which holds only a
    (tests/codegen/test_recursive_enumerations.py runs such values)."""
    model = tmp_path / "rec.rct"
    model.write_text("package rec\nenumeration E { a b(E) }\nstm M {\n\tvar x: E = b(a)\n\tinitial i\n\tstate S { }\n"
                     "\ttransition t0 { from i to S }\n}\n")
    config = compile_model([str(model)], tmp_path / "out", machine="M").generated.files["sources/config.h"]
    assert [level for level in ("", "_3", "_2", "_1", "_0") if f"}} rg_rec_rec_E{level};" in config] == ["", "_3", "_2", "_1", "_0"]
    assert "typedef struct {\n    int64_t tag;\n} rg_rec_rec_E_0;" in config
