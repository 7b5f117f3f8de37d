"""The generator writes only what RoboTool's type provider accepts (RoboCalcTypeProvider.xtend),
which robogen's checker follows. Two rules the fuzzer's first 633 models of seed 1 broke, each
first as the checker's error on the shrunk model (the checker is right: RoboTool rejects them
too), then as the generator's rule."""

from __future__ import annotations

import random

from support.frontend import at, diagnostics

from robogen.fuzz.exprs import Exprs, Scope
from robogen.fuzz.features import DEFAULT
from robogen.fuzz.typegen import TypeEnv
from robogen.semantics import types as T

# model 1.281, shrunk: typeFor(SetExp) takes the first element's type and then the wider of it
# and each next one; real * nat and int * real are neither wider nor narrower than the other
ENUMERATION = """\
operation op() {
    var v: real -> real
    initial i
    state S { entry v = {(| 2.0, 0 |), (| -1, 0.5 |)} }
    transition t { from i to S }
}
"""

# model 1.316, shrunk: typeFor(InExp) asks the member's type to fit in the set's element type;
# the comprehension's elements are its body's, ints
MEMBERSHIP = """\
interface I { var n: int }
stm M {
    requires I
    initial i
    state S { during if forall q: real | q in {c: boolean | c in {true} @ n} @ true then skip end }
    transition t { from i to S }
}
"""


def test_an_enumeration_of_tuples_of_crossed_number_types_is_an_error():
    errors = [d for d in diagnostics(ENUMERATION) if d[0] == "error"]
    assert errors == [("error", *at(ENUMERATION, "(| -1, 0.5 |)"),
                       "the elements of a set must have one type: real * nat and int * real")]


def test_a_real_member_of_a_set_of_ints_is_an_error():
    errors = [d[3] for d in diagnostics(MEMBERSHIP) if d[0] == "error"]
    assert errors == ["real cannot be a member of Set(int)"]


def test_enumeration_elements_join_as_robotool_types_them():
    real_nat, int_real = T.ProductT((T.REAL, T.NAT)), T.ProductT((T.INT, T.REAL))
    assert T.element_join(real_nat, int_real) is None
    assert T.element_join(int_real, real_nat) is None
    assert T.element_join(T.NAT, T.REAL) == T.REAL
    assert T.element_join(T.INT, T.NAT) == T.INT
    assert T.element_join(real_nat, real_nat) == real_nat
    assert T.element_join(T.SetT(T.NAT), T.SetT(T.INT)) == T.SetT(T.INT)


def test_the_sets_a_bound_variable_ranges_over_have_exactly_its_type():
    """For ``forall x: T | x in s`` the generator writes an ``s`` whose elements the checker types
    as exactly ``T``: a variable of type Set(T), or an enumeration with a literal of type T."""
    env = TypeEnv(random.Random(1), DEFAULT)
    for k in range(200):
        gen = Exprs(random.Random(k), env, DEFAULT)
        for t in (T.NAT, T.INT, T.REAL, T.ProductT((T.REAL, T.NAT))):
            s = gen.exact_set(t, Scope(), 2)
            text = ("import set_toolkit::*\nimport sequence_toolkit::*\nimport relation_toolkit::*\n"
                    f"function f(): boolean {{ postcondition result == (forall x: {t.show()} | x in {_text(s)} @ true) }}\n")
            assert [d for d in diagnostics(text) if d[0] == "error"] == [], text


def _text(e) -> str:
    from robogen.syntax.printer import expr

    return expr(e)


def test_an_enumeration_keeps_only_elements_the_checker_accepts_together():
    """model 2.107: ``override(f, {(| fn1(10, 3), 1.0 / 2.0 |), (| 0.25, fn1(7, 100) |)})`` put an
    ``int * real`` beside a ``real * int``: the second is written again as the first."""
    from robogen.fuzz.exprs import chained
    from robogen.syntax import ast

    first, second = ast.TupleLit((ast.IntLit(1), ast.RealLit("0.5"))), ast.TupleLit((ast.RealLit("0.25"), ast.IntLit(7)))
    items, element = chained([(first, T.ProductT((T.INT, T.REAL))), (second, T.ProductT((T.REAL, T.INT)))])
    assert items == (first, first) and element == T.ProductT((T.INT, T.REAL))
    items, element = chained([(first, T.ProductT((T.NAT, T.REAL))), (second, T.ProductT((T.REAL, T.REAL)))])
    assert items == (first, second) and element == T.ProductT((T.REAL, T.REAL))
