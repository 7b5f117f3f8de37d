"""Vector and matrix arithmetic, lowered to arithmetic on their elements.

RoboChart types ``+``, ``-`` and ``*`` on vectors and matrices as :mod:`robogen.semantics.algebra`
says: element-wise sums and differences of equal shapes, a number times a vector or matrix,
matrix × matrix, matrix × vector, a vector times a one-row matrix, and the dot product of two
vectors (a number); unary ``-`` negates each element; ``transpose`` swaps rows and columns. The IR has no vector operations: each
becomes a vector (or matrix) literal whose items are the scalar expressions of its elements, in
the element type of the result (row-major for matrices), so the C emitter and the interpreter
compute them with the scalar arithmetic they already share (wrapping integers, real division
by zero a run-time error). Operands of vector type are side-effect free (variables, fields,
literals, event values, conditionals), so reading one several times is reading the same value.
"""

from __future__ import annotations

from typing import Callable

from robogen.diagnostics import Span
from robogen.ir import model as ir
from robogen.semantics import types as T

Conv = Callable[[ir.Expr, T.Type, "Span | None"], ir.Expr]


def elements(e: ir.Expr) -> list[ir.Expr]:
    """The elements of a vector or matrix expression, row-major."""
    if isinstance(e, ir.VectorLit):
        return list(e.items)
    t = e.type
    if isinstance(t, T.VectorT):
        return [ir.IndexOf(t.element, e, (_index(k),)) for k in range(t.size or 0)]
    assert isinstance(t, T.MatrixT)
    return [ir.IndexOf(t.element, e, (_index(i), _index(j))) for i in range(t.rows or 0) for j in range(t.columns or 0)]


def _index(k: int) -> ir.Expr:
    return ir.Lit(T.INT, k + 1)  # 1-based, as the model indexes


def _shaped(t: T.Type) -> bool:
    return isinstance(t, (T.VectorT, T.MatrixT))


def negate(e: ir.Expr, t: T.Type, conv: Conv, span: Span | None) -> ir.Expr:
    """``-e`` for a vector or matrix ``e`` of type ``t``."""
    el = t.element  # type: ignore[attr-defined]
    return ir.VectorLit(t, tuple(ir.Un(el, "neg", conv(x, el, span)) for x in elements(e)))


def arithmetic(op: str, a: ir.Expr, b: ir.Expr, t: T.Type, conv: Conv, span: Span | None) -> ir.Expr:
    """``a op b`` (op add, sub or mul) where a vector or matrix takes part; ``t`` is the type of
    the result, as the checker gave it."""
    el = t.element if _shaped(t) else t  # type: ignore[attr-defined]

    def bin_(o: str, x: ir.Expr, y: ir.Expr) -> ir.Expr:
        return ir.Bin(el, o, conv(x, el, span), conv(y, el, span))

    def total(terms: list[ir.Expr]) -> ir.Expr:
        out = terms[0]
        for x in terms[1:]:
            out = ir.Bin(el, "add", out, x)
        return out

    if op in ("add", "sub"):
        return ir.VectorLit(t, tuple(bin_(op, x, y) for x, y in zip(elements(a), elements(b))))
    assert op == "mul"
    if not _shaped(a.type) or not _shaped(b.type):  # a number times a vector or matrix
        scalar, shaped = (a, b) if _shaped(b.type) else (b, a)
        return ir.VectorLit(t, tuple(bin_("mul", scalar, x) if scalar is a else bin_("mul", x, scalar)
                                     for x in elements(shaped)))
    xs, ys = elements(a), elements(b)
    if isinstance(a.type, T.VectorT) and isinstance(b.type, T.VectorT):  # the dot product
        return total([bin_("mul", x, y) for x, y in zip(xs, ys)])
    if isinstance(a.type, T.VectorT):  # a column times a one-row matrix
        cols = b.type.columns or 0  # type: ignore[attr-defined]
        return ir.VectorLit(t, tuple(bin_("mul", x, ys[j]) for x in xs for j in range(cols)))
    rows, inner = a.type.rows or 0, a.type.columns or 0  # type: ignore[attr-defined]
    cols = (b.type.columns or 0) if isinstance(b.type, T.MatrixT) else 1  # matrix x vector: one column
    items = [total([bin_("mul", xs[i * inner + k], ys[k * cols + j]) for k in range(inner)])
             for i in range(rows) for j in range(cols)]
    return ir.VectorLit(t, tuple(items))


def transpose(e: ir.Expr, t: T.MatrixT, conv: Conv, span: Span | None) -> ir.Expr:
    """``transpose(e)`` of type ``t``: element [i, j] is e's [j, i]; of a vector (a column), the
    matrix of one row that holds its elements (RoboTool's TransposeExp)."""
    xs, el = elements(e), t.element
    rows, cols = t.rows or 0, t.columns or 0
    if isinstance(e.type, T.VectorT):
        return ir.VectorLit(t, tuple(conv(x, el, span) for x in xs))
    return ir.VectorLit(t, tuple(conv(xs[j * rows + i], el, span) for i in range(rows) for j in range(cols)))


__all__ = ["arithmetic", "negate", "elements", "transpose"]
