"""An enumeration whose elements include an empty collection nothing types (``<<>>``, a
``Seq(Seq(?))``) has the typed elements' type, whichever comes first: robogen.semantics.types
.element_join. Found by the model fuzzer (model 1.357 of make fuzz SEED=1: ``dconcat(<q ^ <<true,
false>>, <<>>>)`` was "using a Seq(Seq(boolean)) as a Seq(Seq(int))")."""

from __future__ import annotations

from support.codegen_driver import Tick, build_text, outputs_by_instant

from robogen.semantics import types as T

MODEL = """\
import sequence_toolkit::*

stm M {
    var q: Seq(Seq(boolean)) = <<true>>
    event go
    event n: nat
    event last: nat
    initial i
    state S { }
    transition t0 { from i to S }
    transition t1 {
        from S to S
        trigger go
        action q = dconcat(<q ^ <<false>>, <<>>>) ; n!size(q) ; last!size(q[size(q)])
    }
}
"""


def test_an_empty_nested_collection_beside_a_typed_one_takes_its_type():
    typed, untyped = T.SeqT(T.SeqT(T.BOOLEAN)), T.SeqT(T.SeqT(T.UNKNOWN))
    assert T.element_join(typed, untyped) == typed
    assert T.element_join(untyped, typed) == typed


def test_dconcat_of_a_sequence_and_an_empty_one_runs(tmp_path):
    built = build_text(tmp_path, "untyped", MODEL)
    # <<true>> ^ <<false>> = <<true>, <false>>; dconcat(< that, <<>> >) = <<true>, <false>, <>>: 3
    # elements, the last empty; the next go: <<true>, <false>, <>, <false>> then <>: 5
    outputs, _ = outputs_by_instant(built, {1: Tick("go", {}), 2: Tick("go", {})}, 3)
    assert outputs[1] == {"n": {"n.value": 3}, "last": {"last.value": 0}}
    assert outputs[2] == {"n": {"n.value": 5}, "last": {"last.value": 0}}
