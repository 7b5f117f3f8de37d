"""Constructs that lowering cannot give a meaning get a located "not supported" error naming
them (exit code 1), never an internal error."""

from __future__ import annotations

from robogen.cli import main

ABSTRACT = """interface I { event go }
interface Ops { act(x: nat) }
operation act(x: nat) { }
stm M {
\tuses I
\trequires Ops
\tinitial i
\tstate S { }
\ttransition t0 { from i to S }
\ttransition t1 { from S to S trigger go action act(1) }
}
"""


def test_a_call_of_an_operation_without_nodes_is_not_supported(tmp_path, capsys):
    """RoboChart gives an operation definition without nodes no behaviour (it is abstract): a
    call of it cannot be generated, and is not a no-op."""
    model = tmp_path / "abstract.rct"
    model.write_text(ABSTRACT)
    assert main(["check", str(model)]) == 0
    capsys.readouterr()
    assert main(["compile", str(model), "-o", str(tmp_path / "out")]) == 1
    assert (f"{model}:10:48: error: a call of operation 'act', whose definition has no initial node (an abstract "
            "operation: the model gives it no behaviour to generate) is not supported for code generation"
            in capsys.readouterr().err)
