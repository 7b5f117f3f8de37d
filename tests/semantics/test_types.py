"""Type compatibility (robogen.semantics.types): what may be stored where."""

from robogen.semantics import types as T


def test_numbers_widen_and_int_narrows_to_nat_but_real_never_narrows():
    assert T.assignable(T.NAT, T.INT) and T.assignable(T.INT, T.REAL) and T.assignable(T.INT, T.NAT)
    assert not T.assignable(T.REAL, T.INT) and not T.assignable(T.REAL, T.NAT)


def test_vectors_and_matrices_take_elements_that_widen_with_the_same_shape():
    assert T.assignable(T.VectorT(T.NAT, 2), T.VectorT(T.INT, 2))
    assert not T.assignable(T.VectorT(T.NAT, 3), T.VectorT(T.INT, 2))
    # a literal of naturals initialises an int matrix (was rejected: matrices had no rule)
    assert T.assignable(T.MatrixT(T.NAT, 2, 2), T.MatrixT(T.INT, 2, 2))
    assert not T.assignable(T.MatrixT(T.NAT, 2, 3), T.MatrixT(T.INT, 2, 2))
    assert not T.assignable(T.MatrixT(T.REAL, 2, 2), T.MatrixT(T.INT, 2, 2))
    # a size given by a constant is unknown to the checker: compatible with any size
    assert T.assignable(T.MatrixT(T.NAT, 2, 2), T.MatrixT(T.INT, None, 2))


def test_translated_types_are_the_same_by_structure():
    # RoboTool's translations re-declare enumerations and given types in other packages
    a, b = T.EnumT("main::Position", ("left", "right")), T.EnumT("sim::Position", ("left", "right"))
    assert T.assignable(a, b)
    assert not T.assignable(a, T.EnumT("x::Side", ("left", "centre")))
    assert T.same(T.Given("main::ID"), T.Given("pkg::ID")) and not T.same(T.Given("main::ID"), T.Given("main::Key"))
