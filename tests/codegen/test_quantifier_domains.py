"""A type that only a quantifier's domain names still gets its C declaration: the set a bound
variable ranges over is an expression of the quantifier (robogen.ir.model.Domain), and the walk
that finds every type the C code uses (robogen.ir.walk) goes into it. Found by the model fuzzer
(model 1.19, tests/fuzz/regressions/package_compile_1_19.rct: ``'rg_tup2_u_i' undeclared``)."""

from __future__ import annotations

from support.codegen_driver import Tick, build_text, outputs_by_instant

from robogen.ir.supported import tuple_type
from robogen.ir.walk import value_types
from robogen.semantics import types as T

MODEL = """\
import relation_toolkit::*
import set_toolkit::*

enumeration E { a b }

stm M {
    event go
    event ok: nat
    initial i
    state S { }
    transition t0 { from i to S }
    transition t1 {
        from S to S
        trigger go
        action if forall q: nat | q in {first((| 3, E::a |)), 1} @ q > 0 then ok!4 else ok!0 end
    }
}
"""


def test_a_tuple_type_only_a_quantifier_domain_holds_is_declared_and_runs(tmp_path):
    built = build_text(tmp_path, "quantdomain", MODEL)
    pair = tuple_type((T.NAT, next(t for t in value_types(built.fmu) if isinstance(t, T.EnumT))))
    assert any(t == pair for t in value_types(built.fmu))
    # {first((| 3, a |)), 1} = {3, 1}: every element is above 0, so go gives ok!4 each time
    outputs, _ = outputs_by_instant(built, {1: Tick("go", {}), 3: Tick("go", {})}, 4)
    assert outputs == {0: {}, 1: {"ok": {"ok.value": 4}}, 2: {}, 3: {"ok": {"ok.value": 4}}}
