"""robogen.semantics.algebra: vector and matrix arithmetic typed as RoboTool types it (K11)."""

from __future__ import annotations

import pytest
from support.frontend import diagnostics, error, machine

from robogen.semantics import types as T
from robogen.semantics.algebra import linear, negation

V2, V3 = T.VectorT(T.INT, 2), T.VectorT(T.INT, 3)
M22, M23, M13 = T.MatrixT(T.INT, 2, 2), T.MatrixT(T.INT, 2, 3), T.MatrixT(T.NAT, 1, 3)

TYPES = [
    ("+", T.VectorT(T.NAT, 2), T.VectorT(T.REAL, 2), T.VectorT(T.REAL, 2)),
    ("-", M22, T.MatrixT(T.NAT, 2, 2), M22),
    ("*", M22, M23, M23),  # matrix by matrix
    ("*", M23, V3, V2),  # matrix by vector: a vector of the matrix's rows
    ("*", V2, M13, T.MatrixT(T.INT, 2, 3)),  # vector by a matrix of one row
    ("*", V2, T.VectorT(T.REAL, 2), T.REAL),  # the dot product
    ("*", T.NAT, V2, V2),
    ("*", M22, T.REAL, T.MatrixT(T.REAL, 2, 2)),
    ("+", T.VectorT(T.INT, None), V3, V3),  # a size given by a constant matches any
]


@pytest.mark.parametrize("op, a, b, result", TYPES, ids=[f"{a} {op} {b}" for op, a, b, _ in TYPES])
def test_types_of_vector_and_matrix_operations(op, a, b, result):
    assert linear(op, a, b) == result


UNDEFINED = [
    ("+", V2, V3, "'+' needs two vectors or two matrices of the same size, not vector(int, 2) and vector(int, 3)"),
    ("+", V2, T.INT, "'+' needs two vectors or two matrices of the same size, not vector(int, 2) and int"),
    ("*", M23, M23, "cannot multiply matrix(int, 2, 3) by matrix(int, 2, 3): the columns of the first are not the rows of the second"),
    ("*", M22, V3, "cannot multiply matrix(int, 2, 2) by vector(int, 3): the matrix's columns are not the vector's size"),
    ("*", V2, M22, "cannot multiply vector(int, 2) by matrix(int, 2, 2): a vector multiplies a matrix of one row"),
    ("*", V2, V3, "cannot multiply vector(int, 2) by vector(int, 3): a dot product needs two vectors of the same size"),
    ("/", V2, T.INT, "'/' is not defined on vectors and matrices"),
    ("*", T.VectorT(T.BOOLEAN, 2), V2, "'*' needs numbers, vectors or matrices of numbers, not vector(boolean, 2)"),
]


@pytest.mark.parametrize("op, a, b, message", UNDEFINED, ids=[m for *_, m in UNDEFINED])
def test_undefined_vector_and_matrix_operations(op, a, b, message):
    assert linear(op, a, b) == message


def test_negation_keeps_the_shape():
    assert negation(T.VectorT(T.NAT, 2)) == T.VectorT(T.NAT, 2)
    assert negation(T.MatrixT(T.BOOLEAN, 1, 1)).startswith("unary '-' needs a number")


def test_vector_arithmetic_in_a_model():
    text = machine(
        "var v: vector(int, 2), w: vector(int, 3), m: matrix(int, 2, 2), k: int, r: real",
        action="v = m * v + v ; k = v * v ; v = -v ; v = v + w ; r = r % 2.0 ; k = 7 % 2",
    )
    assert diagnostics(text) == [
        error(text, "v + w", "'+' needs two vectors or two matrices of the same size, not vector(int, 2) and vector(int, 3)"),
    ]


def test_the_elements_of_an_enumeration_take_the_widest_number_type():
    """Every row of a matrix literal counts, not the first row's alone: [| 1, 2; 2.5, 1 |] is a
    matrix(real) (it was a matrix(nat), accepted as the initial value of a matrix(nat) whose 2.5
    was lost), and <0, -1> a Seq(int) (it was a Seq(nat), where -1 wraps)."""
    text = machine("var m: matrix(nat, 2, 2) = [| 1, 2; 2.5, 1 |]", "var r: matrix(real, 2, 2) = [| 1, 2; 2.5, 1 |]",
                   "var s: Set(real) = { 1, 2.5 }", "var q: Seq(int) = <0, -1>", "var b: boolean = <0, -1> == <0, -1>")
    assert diagnostics(text) == [
        error(text, "[| 1, 2; 2.5, 1 |]", "the initial value of 'm' must be matrix(nat, 2, 2), but this is matrix(real, 2, 2)"),
    ]
