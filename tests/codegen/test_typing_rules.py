"""RoboTool's typing rules where robogen was stricter, generated (tests/codegen/models/widen.rct;
the rules themselves: tests/semantics/test_robotool_typing.py). Values hand-calculated; the
interpreter's trace is the same (run_checked)."""

from __future__ import annotations

import pytest

from support.codegen_driver import Tick, outputs_by_instant


def tick(clock: str, value) -> Tick:
    return Tick(clock, {f"{clock}.value": value})


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_received_reals_are_truncated_and_connected_nats_widened(builds, semantics):
    inputs = {1: tick("r", 2.75), 2: tick("r", -2.75), 3: tick("n", 5), 4: tick("go", 7)}
    outputs, _ = outputs_by_instant(builds.get("widen", semantics), inputs, 6)
    assert outputs == {
        0: {"hello": {"hello.value": "hello"}},  # "he" ^ "llo", joined at generation
        1: {"got": {"got.value": 2}},  # r?k: 2.75 into the int k, truncated toward zero
        2: {"got": {"got.value": -2}},
        3: {"sum": {"sum.value": 6}},  # the platform's nat 5 reaches a's int n: k + 1
        4: {"sum": {"sum.value": 14}},  # b's nat 7 reaches a's int m: 2 * k
        5: {},
    }


def test_joining_strings_that_are_not_literals_is_not_supported(tmp_path):
    from robogen.codegen.api import compile_model
    from robogen.diagnostics import RobogenError

    path = tmp_path / "join.rct"
    path.write_text('interface I { event e: string }\nstm M {\n\tuses I\n\tvar s: string = "a"\n\tinitial i\n\tstate S { }\n'
                    '\ttransition t0 { from i to S action e!(s ^ "b") }\n}\n')
    with pytest.raises(RobogenError) as exc:
        compile_model([str(path)], tmp_path / "out", machine="M")
    (d,) = exc.value.diagnostics
    assert d.message == ("joining strings that are not literals (a string is one of the model's or an importer's at run "
                         "time, never a new one) is not supported for code generation")
    assert (d.span.line, d.span.column) == (7, 39)  # (s ^ "b"), with its parentheses
