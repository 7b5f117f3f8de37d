"""The types of the arithmetic operators on vectors and matrices, as RoboTool's type provider
gives them (``RoboCalcTypeProvider.typeFor``, cases Plus, Minus, Neg and Mult).

- ``+`` and ``-`` of two vectors, or of two matrices, of numbers with equal dimensions: the
  same shape, the elements' common type (nat within int within real);
- ``-v``: the same shape;
- ``*``: a matrix by a matrix (the columns of the first are the rows of the second), a matrix by
  a vector (its columns are the vector's size; a vector of the matrix's rows), a vector by a
  matrix of one row (a matrix of the vector's size by the matrix's columns), a vector by a
  vector of the same size (their dot product: a number), and a number by a vector or matrix (or
  the other way round): the vector's or matrix's shape.

A dimension written as a constant is not known to the checker (``None``); it matches any other
(RoboTool compares such dimensions by the constant's name).
"""

from __future__ import annotations

from robogen.semantics.types import NAT, MatrixT, Type, VectorT, is_numeric, numeric_join


def _common(a: Type, b: Type) -> Type:
    """The common type of two numeric element types (nat + nat stays nat, unlike nat - nat)."""
    if a == NAT and b == NAT:
        return NAT
    return numeric_join(a, b)


def _equal(m: int | None, n: int | None) -> bool:
    return m is None or n is None or m == n


def _numeric(t: Type) -> bool:
    return is_numeric(t.element) if isinstance(t, (VectorT, MatrixT)) else is_numeric(t)


def linear(op: str, a: Type, b: Type) -> Type | str:
    """The type of ``a op b`` (op one of + - * / %) where a vector or matrix takes part; a
    message saying why when the operation is undefined."""
    if not (_numeric(a) and _numeric(b)):
        bad = a if not _numeric(a) else b
        return f"'{op}' needs numbers, vectors or matrices of numbers, not {bad.show()}"
    if op in ("+", "-"):
        return _add(op, a, b)
    if op == "*":
        return _multiply(a, b)
    return f"'{op}' is not defined on vectors and matrices"


def _add(op: str, a: Type, b: Type) -> Type | str:
    if isinstance(a, VectorT) and isinstance(b, VectorT):
        if _equal(a.size, b.size):
            return VectorT(_common(a.element, b.element), a.size if a.size is not None else b.size)
    elif isinstance(a, MatrixT) and isinstance(b, MatrixT):
        if _equal(a.rows, b.rows) and _equal(a.columns, b.columns):
            return MatrixT(_common(a.element, b.element), _known(a.rows, b.rows), _known(a.columns, b.columns))
    return f"'{op}' needs two vectors or two matrices of the same size, not {a.show()} and {b.show()}"


def _known(m: int | None, n: int | None) -> int | None:
    return m if m is not None else n


def _multiply(a: Type, b: Type) -> Type | str:
    if isinstance(a, MatrixT) and isinstance(b, MatrixT):
        if _equal(a.columns, b.rows):
            return MatrixT(_common(a.element, b.element), a.rows, b.columns)
        return f"cannot multiply {a.show()} by {b.show()}: the columns of the first are not the rows of the second"
    if isinstance(a, MatrixT) and isinstance(b, VectorT):
        if _equal(a.columns, b.size):
            return VectorT(_common(a.element, b.element), a.rows)
        return f"cannot multiply {a.show()} by {b.show()}: the matrix's columns are not the vector's size"
    if isinstance(a, VectorT) and isinstance(b, MatrixT):
        if b.rows in (1, None):
            return MatrixT(_common(a.element, b.element), a.size, b.columns)
        return f"cannot multiply {a.show()} by {b.show()}: a vector multiplies a matrix of one row"
    if isinstance(a, VectorT) and isinstance(b, VectorT):
        if _equal(a.size, b.size):
            return _common(a.element, b.element)  # the dot product
        return f"cannot multiply {a.show()} by {b.show()}: a dot product needs two vectors of the same size"
    scalar, shaped = (a, b) if isinstance(b, (VectorT, MatrixT)) else (b, a)
    if isinstance(shaped, VectorT):
        return VectorT(_common(shaped.element, scalar), shaped.size)
    assert isinstance(shaped, MatrixT)
    return MatrixT(_common(shaped.element, scalar), shaped.rows, shaped.columns)


def negation(t: Type) -> Type | str:
    """The type of ``-t`` for a vector or matrix ``t``."""
    if not _numeric(t):
        return f"unary '-' needs a number, a vector or a matrix of numbers, not {t.show()}"
    return t


__all__ = ["linear", "negation"]
