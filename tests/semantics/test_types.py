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


def test_general_forms_relate_relations_functions_sequences_and_sets():
    """RoboTool compares types of different forms through their general forms."""
    pairs = T.SetT(T.ProductT((T.NAT, T.BOOLEAN)))
    assert T.assignable(pairs, T.FunctionT(T.NAT, T.BOOLEAN, relation=True))
    assert T.assignable(T.FunctionT(T.NAT, T.BOOLEAN), pairs)
    assert T.assignable(T.SeqT(T.REAL), T.SetT(T.ProductT((T.NAT, T.REAL))))
    assert T.assignable(T.VectorT(T.INT, 2), T.ProductT((T.INT, T.INT)))
    assert not T.assignable(T.SeqT(T.REAL), T.SetT(T.REAL))


def test_a_product_of_one_component_is_that_component():
    # a named function's value type: (nat) -> nat (RoboTool's product domain)
    assert T.assignable(T.FunctionT(T.ProductT((T.NAT,)), T.NAT), T.FunctionT(T.NAT, T.NAT))
    assert T.FunctionT(T.ProductT((T.NAT,)), T.NAT).show() == "(nat) -> nat"


def test_unification_binds_type_variables_consistently():
    X, Y = T.TypeVarT("X"), T.TypeVarT("Y")
    bindings: dict[str, T.Type] = {}
    assert T.unify(T.FunctionT(X, Y, relation=True), T.FunctionT(T.NAT, T.BOOLEAN), bindings)
    assert bindings == {"X": T.NAT, "Y": T.BOOLEAN}
    assert T.unify(T.SetT(X), T.SetT(T.INT), bindings) and bindings["X"] == T.INT  # widened
    assert not T.unify(T.SetT(Y), T.SetT(T.NAT), bindings)
    assert T.instantiate(T.SeqT(T.ProductT((X, Y))), bindings) == T.SeqT(T.ProductT((T.INT, T.BOOLEAN)))
    # a sequence is a set of (index, element) pairs
    bindings = {}
    assert T.unify(T.FunctionT(X, Y, relation=True), T.SeqT(T.REAL), bindings) and bindings == {"X": T.NAT, "Y": T.REAL}


def test_every_type_is_assignable_to_an_equal_copy_of_itself():
    """assignable() answers True at once for a type and itself; the general rules agree, as an
    equal but distinct copy (which takes them) shows for every form of type."""
    import copy

    enum = T.EnumT("p::E", ("a", "b"), ((), (T.NAT,)))
    record = T.RecordT("p::R", (("x", T.REAL), ("e", enum)))
    samples = [
        T.NAT, T.INT, T.REAL, T.BOOLEAN, T.STRING, T.UNKNOWN, T.Given("p::G"), enum, record,
        T.SetT(T.NAT), T.SeqT(record), T.ProductT((T.NAT, T.BOOLEAN)), T.ProductT(()),
        T.FunctionT(T.NAT, T.SetT(T.INT)), T.FunctionT(T.INT, T.NAT, relation=True),
        T.VectorT(T.REAL, 3), T.VectorT(T.INT, None), T.MatrixT(T.REAL, 2, None), T.TypeVarT("X"),
    ]  # fmt: skip
    for t in samples:
        twin = copy.deepcopy(t)
        assert twin == t and (twin is not t or t in (T.UNKNOWN,))
        assert T.assignable(t, t) and T.assignable(twin, t) and T.assignable(t, twin), t
