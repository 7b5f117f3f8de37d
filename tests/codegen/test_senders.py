"""Filters that bind the sender (tests/codegen/models/senders.rct): ``e[| x = from |]`` gives x the
sender of the occurrence taken - the FMU's boundary (number 0, named after the platform's
reference) or the state machine that sent it, through any connections (number k for the k-th
machine of the FMU, named by its FMI name) - in a trigger (with a predicate that reads it) and in
an input statement. Values hand-calculated; the interpreter's trace is the same (run_checked)."""

from __future__ import annotations

import pytest

from support.codegen_driver import Tick, build, outputs_by_instant
from robogen.diagnostics import RobogenError

HUB, A, C = 1, 2, 3  # the machines' numbers: the order of their state outputs, Hub.state, ctl.a.state, far.c.state


def tick(clock: str, value: int | None = None) -> Tick:
    return Tick(clock, {} if value is None else {f"{clock}.value": value})


def reports(who: int | None = None, name: str | None = None, got: int | None = None) -> dict:
    out = {}
    if who is not None:
        out["who"] = {"who.value": who}
    if name is not None:
        out["whoName"] = {"whoName.value": name}
    if got is not None:
        out["got"] = {"got.value": got}
    return out


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_the_sender_is_the_boundary_or_the_machine_that_sent(builds, semantics):
    built = builds.get("senders", semantics)
    assert [v.name for v in built.desc.states] == ["Hub.state", "ctl.a.state", "far.c.state"]
    inputs = {1: tick("ping", 7), 2: tick("go", 5), 3: tick("ask"), 4: tick("goFar", 9), 5: tick("ping", 4)}
    outputs, trace = outputs_by_instant(built, inputs, 7)
    assert outputs == {
        0: {},
        1: reports(name="robot", got=7),  # from the platform: 0 fails t1's predicate s > 0; t2 names it
        2: reports(who=A, got=5),  # a's ping!5 reaches Hub through the [ mult ] connection: t1
        3: {},  # ask: Hub waits in t3's action for far
        4: reports(name="far.c", got=9),  # c's ping!9 through Far and the module's connection
        5: reports(name="robot", got=4),
        6: {},
    }
    assert trace.steps[-1].variables["Hub.s"] == A  # t1 bound it; t2 and t3 bind n


SINGLE = """interface I { event e: nat event out: int }
stm M {
\tuses I
\tvar s: int = 5, v: nat = 0
\tinitial i
\tstate S { }
\ttransition t0 { from i to S }
\ttransition t1 { from S to S trigger e[| s = from | v == 0 |]?v action out!s }
}
"""


def test_at_a_single_machine_the_sender_is_the_environment(tmp_path):
    path = tmp_path / "single.rct"
    path.write_text(SINGLE)
    built = build([path], tmp_path / "w", machine="M")
    outputs, trace = outputs_by_instant(built, {1: tick("e", 3), 2: tick("e", 0)}, 3)
    # the predicate reads v as the value offered: 3 fails v == 0 and waits in the buffer, until
    # 0 replaces it (dropped) and is taken; the int s (5 before) receives the number 0
    assert outputs == {0: {}, 1: {}, 2: {"out": {"out.value": 0}}}
    assert trace.steps[-1].dropped == 1
    path.write_text(SINGLE.replace("v == 0", "v >= 0").replace("s: int = 5", 's: string = "x"').replace("out: int", "out: string"))
    built = build([path], tmp_path / "w2", machine="M")
    outputs, _ = outputs_by_instant(built, {1: tick("e", 3)}, 2)
    assert outputs == {0: {}, 1: {"out": {"out.value": "environment"}}}


def test_a_sender_variable_of_another_type_is_not_supported(tmp_path):
    path = tmp_path / "real.rct"
    path.write_text(SINGLE.replace("s: int = 5", "s: real = 5.0").replace("out: int", "out: real"))
    with pytest.raises(RobogenError) as exc:
        build([path], tmp_path / "w", machine="M")
    (d,) = exc.value.diagnostics
    assert d.message == ("the sender in 's' of type real (robogen gives the sender as a number, nat or int, or as a name, "
                         "string) is not supported for code generation")
    assert (d.span.line, d.span.column) == (8, 39)
