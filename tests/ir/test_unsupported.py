"""Constructs that lowering cannot give a meaning get a located "not supported" error naming
them (exit code 1), never an internal error."""

from __future__ import annotations

from robogen.cli import main

NO_INITIAL = """interface I { event go }
interface Ops { act(x: nat) }
operation act(x: nat) { state A { } }
stm M {
\tuses I
\trequires Ops
\tinitial i
\tstate S { }
\ttransition t0 { from i to S }
\ttransition t1 { from S to S trigger go action act(1) }
}
"""


def test_a_call_of_an_operation_with_nodes_but_no_initial_node_is_not_supported(tmp_path, capsys):
    """An operation definition with nodes but none to start from (RoboTool warns) has no behaviour
    to generate; unlike an abstract one (no nodes: its call is an output clock, see
    tests/codegen/test_abstract_operations.py) it does not terminate at once either."""
    model = tmp_path / "noinitial.rct"
    model.write_text(NO_INITIAL)
    assert main(["check", str(model)]) == 0
    capsys.readouterr()
    assert main(["compile", str(model), "-o", str(tmp_path / "out")]) == 1
    assert (f"{model}:10:48: error: a call of operation 'act', whose definition has nodes but no initial node "
            "is not supported for code generation" in capsys.readouterr().err)
