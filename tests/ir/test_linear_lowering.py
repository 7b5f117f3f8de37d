"""robogen.ir.linear: vector and matrix arithmetic lowered to scalar arithmetic on elements.

Each expression is lowered, then evaluated element by element with the interpreter's scalar
arithmetic (ir.interp.arith, which the C helpers match); the expected values are worked out by
hand from the textbook definitions.
"""

from __future__ import annotations

from robogen.ir import model as ir
from robogen.ir.interp import _neg, arith
from robogen.ir.linear import arithmetic, elements, negate
from robogen.semantics import types as T

INT = T.INT


def no_conversion(e: ir.Expr, t: T.Type, span) -> ir.Expr:
    assert e.type == t or isinstance(e, ir.IndexOf), f"{e} needs no conversion to {t.show()}"
    return e


def vec(*xs: int) -> ir.VectorLit:
    return ir.VectorLit(T.VectorT(INT, len(xs)), tuple(ir.Lit(INT, x) for x in xs))


def mat(*rows: tuple[int, ...]) -> ir.VectorLit:
    t = T.MatrixT(INT, len(rows), len(rows[0]))
    return ir.VectorLit(t, tuple(ir.Lit(INT, x) for row in rows for x in row))


def value(e: ir.Expr):
    """A scalar, or the row-major list of a vector's or matrix's elements."""
    if isinstance(e, ir.VectorLit):
        return [value(x) for x in e.items]
    if isinstance(e, ir.Lit):
        return e.value
    if isinstance(e, ir.Bin):
        return arith(e.op, value(e.left), value(e.right), e.type)
    if isinstance(e, ir.Un):
        return _neg(value(e.operand), e.type)
    if isinstance(e, ir.IndexOf):
        base = value(e.base)
        *_, last = e.indices  # 1-based; the bases below are literals of a known shape
        if len(e.indices) == 2:
            columns = e.base.type.columns
            return base[(value(e.indices[0]) - 1) * columns + value(last) - 1]
        return base[value(last) - 1]
    raise AssertionError(f"unexpected {type(e).__name__}")


def test_sums_and_differences_are_elementwise():
    t = T.VectorT(INT, 3)
    assert value(arithmetic("add", vec(1, 2, 3), vec(10, 20, 30), t, no_conversion, None)) == [11, 22, 33]
    m = T.MatrixT(INT, 2, 2)
    assert value(arithmetic("sub", mat((5, 6), (7, 8)), mat((1, 2), (3, 4)), m, no_conversion, None)) == [4, 4, 4, 4]


def test_a_number_times_a_vector_keeps_its_side():
    t = T.VectorT(INT, 2)
    left = arithmetic("mul", ir.Lit(INT, 3), vec(1, -2), t, no_conversion, None)
    right = arithmetic("mul", vec(1, -2), ir.Lit(INT, 3), t, no_conversion, None)
    assert value(left) == value(right) == [3, -6]
    assert isinstance(left.items[0].left, ir.Lit) and isinstance(right.items[0].right, ir.Lit)


def test_products():
    # dot product: 1*4 + 2*5 + 3*6 = 32
    assert value(arithmetic("mul", vec(1, 2, 3), vec(4, 5, 6), INT, no_conversion, None)) == 32
    # [[1,2],[3,4]] x [[5,6],[7,8]] = [[1*5+2*7, 1*6+2*8], [3*5+4*7, 3*6+4*8]]
    m = T.MatrixT(INT, 2, 2)
    assert value(arithmetic("mul", mat((1, 2), (3, 4)), mat((5, 6), (7, 8)), m, no_conversion, None)) == [19, 22, 43, 50]
    # a 2x3 times a 3x1... as a matrix times a vector: [[1,2,3],[4,5,6]] x [1,0,-1] = [-2, -2]
    v = T.VectorT(INT, 2)
    assert value(arithmetic("mul", mat((1, 2, 3), (4, 5, 6)), vec(1, 0, -1), v, no_conversion, None)) == [-2, -2]
    # a column times a one-row matrix: [1,2] x [[3,4,5]] = [[3,4,5],[6,8,10]]
    outer = T.MatrixT(INT, 2, 3)
    assert value(arithmetic("mul", vec(1, 2), mat((3, 4, 5)), outer, no_conversion, None)) == [3, 4, 5, 6, 8, 10]


def test_negation_and_elements_of_a_variable():
    assert value(negate(mat((1, -2), (0, 4)), T.MatrixT(INT, 2, 2), no_conversion, None)) == [-1, 2, 0, -4]
    x = ir.Ref(T.MatrixT(INT, 2, 3), ir.Var("x", T.MatrixT(INT, 2, 3), "var"))
    indices = [tuple(i.value for i in e.indices) for e in elements(x)]
    assert indices == [(1, 1), (1, 2), (1, 3), (2, 1), (2, 2), (2, 3)]  # row-major, 1-based
