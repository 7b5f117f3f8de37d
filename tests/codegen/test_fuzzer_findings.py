"""Code generation bugs the model fuzzer found (docs/fuzzing.md, "Regressions found"), each with
a hand-calculated run of a small machine (the interpreter's trace is the same: run_checked).

- A type that only a quantifier's domain names still gets its C declaration: the set a bound
  variable ranges over is an expression of the quantifier (robogen.ir.model.Domain), and the walk
  of every type the C code uses (robogen.ir.walk) goes into it (model 1.19,
  tests/fuzz/regressions/package_compile_1_19.rct: ``'rg_tup2_u_i' undeclared``).
- An enumeration whose elements include an empty collection nothing types (``<<>>``, a
  ``Seq(Seq(?))``) has the typed elements' type, whichever comes first
  (robogen.semantics.types.element_join; models 1.357, 1.416: ``dconcat(<q ^ <<true, false>>,
  <<>>>)`` was "using a Seq(Seq(boolean)) as a Seq(Seq(int))").
- A relation operation works on the pairs of its result: ``rsub({(| 1, 7 |)}, s)`` of a
  ``Set(int)`` s is a ``nat <-> int``, the literal's ``nat * nat`` pairs converted, never ``s``
  narrowed to nats (model 1.922: "incompatible types ... 'rg_tup2_u_i' from 'rg_tup2_u_u'").
- A comparison of a collection's size with itself (``size(q) >= size(q)``) is its known value,
  as ``x == x`` was (model 1.637: gcc's -Wtautological-compare).
- A one-element vector in a record inside a collection is copied to its FMI view element by
  element like any vector (model 1.963: "assigning to type 'int64_t' from type 'rg_vec_i_1'").
- ``rinv`` converts its relation to its result's pairs swapped (model 2.1348), and ``iter(n, {})``
  of a relation nothing types is empty or the identity (model 2.1506), ``relcomp(r, {})`` empty
  (model 2.1967); all three were "not supported".
- A conditional on a literal condition writes only its branch: the other's quantifier functions
  would be unused (model 3.261, -Wunused-function).
- A type variable bound by an argument that leaves a type open (`<<>>`) takes the type of a later
  argument that decides it: concat(<<>>, q) of a Seq(Seq(E)) (model 3.592)."""

from __future__ import annotations

from support.codegen_driver import Tick, build_text, outputs_by_instant

from robogen.ir.supported import tuple_type
from robogen.ir.walk import value_types
from robogen.semantics import types as T

GO = Tick("go", {})


def machine(declarations: str, action: str) -> str:
    """A machine whose ``go`` runs ``action`` (imports: every toolkit)."""
    return f"""\
import relation_toolkit::*
import sequence_toolkit::*
import set_toolkit::*

enumeration E {{ a b }}

stm M {{
    {declarations}
    event go
    initial i
    state S {{ }}
    transition t0 {{ from i to S }}
    transition t1 {{ from S to S trigger go action {action} }}
}}
"""


def two_goes(tmp_path, name: str, text: str) -> tuple[dict, dict]:
    """The outputs of the machine ``text`` at its first and second go (instants 1 and 2)."""
    outputs, _ = outputs_by_instant(build_text(tmp_path, name, text), {1: GO, 2: GO}, 3)
    return outputs[1], outputs[2]


def test_a_tuple_type_only_a_quantifier_domain_holds_is_declared_and_runs(tmp_path):
    text = machine("event ok: nat", "if forall q: nat | q in {first((| 3, E::a |)), 1} @ q > 0 then ok!4 else ok!0 end")
    built = build_text(tmp_path, "quantdomain", text)
    pair = tuple_type((T.NAT, next(t for t in value_types(built.fmu) if isinstance(t, T.EnumT))))
    assert any(t == pair for t in value_types(built.fmu))
    # {first((| 3, a |)), 1} = {3, 1}: every element is above 0, so go gives ok!4 each time
    outputs, _ = outputs_by_instant(built, {1: GO, 3: GO}, 4)
    assert outputs == {0: {}, 1: {"ok": {"ok.value": 4}}, 2: {}, 3: {"ok": {"ok.value": 4}}}


def test_an_empty_nested_collection_beside_a_typed_one_takes_its_type():
    typed, untyped = T.SeqT(T.SeqT(T.BOOLEAN)), T.SeqT(T.SeqT(T.UNKNOWN))
    assert T.element_join(typed, untyped) == typed
    assert T.element_join(untyped, typed) == typed


def test_dconcat_of_a_sequence_and_an_empty_one_runs(tmp_path):
    text = machine("var q: Seq(Seq(boolean)) = <<true>>\n    event n: nat\n    event last: nat",
                   "q = dconcat(<q ^ <<false>>, <<>>>) ; n!size(q) ; last!size(q[size(q)])")
    # <<true>> ^ <<false>> = <<true>, <false>>; dconcat(< that, <<>> >) = <<true>, <false>, <>>: 3
    # elements, the last empty; the next go: <<true>, <false>, <>, <false>> then <>: 5
    assert two_goes(tmp_path, "untyped", text) == ({"n": {"n.value": 3}, "last": {"last.value": 0}},
                                                   {"n": {"n.value": 5}, "last": {"last.value": 0}})


def test_a_relation_operation_converts_the_relation_to_its_result_pairs(tmp_path):
    image = "rimage(rsub({(| 1, 7 |), (| 3, 5 |)}, s), {3, -1})"
    text = machine("var s: Set(int) = {7, -1}\n    event n: nat\n    event has: boolean",
                   f"n!size({image}) ; has!(5 in {image})")
    built = build_text(tmp_path, "relations", text)
    # rsub drops the pairs whose second is in s = {7, -1}: {(3, 5)}; its image of {3, -1}: {5}
    outputs, _ = outputs_by_instant(built, {1: GO}, 2)
    assert outputs[1] == {"n": {"n.value": 1}, "has": {"has.value": True}}


def test_a_size_compared_with_itself_and_a_one_element_vector_in_a_sequence(tmp_path):
    text = "datatype R { f: vector(int, 1) }\n" + machine(
        "var q: Seq(R)\n    event n: nat\n    event b: boolean",
        "q = q ^ <R(| f = [| 5 |] |)> ; n!size(q) ; b!(size(q) >= size(q))")
    built = build_text(tmp_path, "sizes", text)
    outputs, trace = outputs_by_instant(built, {1: GO, 2: GO}, 3)
    assert outputs[1] == {"n": {"n.value": 1}, "b": {"b.value": True}}
    assert outputs[2] == {"n": {"n.value": 2}, "b": {"b.value": True}}
    views = {k: v for k, v in trace.steps[-1].variables.items() if ".f" in k}
    assert views and all(list(v)[:2] == [5, 5] for v in views.values()), views  # every element's f: [| 5 |]


def test_a_comprehension_of_empty_sequences_beside_a_typed_branch_takes_its_type(tmp_path):
    """``if c then {x: nat | x in s @ <>} else {<"a">, <"b">} end``: the comprehension's elements
    (``<>``, nothing types them) are the other branch's ``Seq(string)`` (model 1.769: "using a
    Set(Seq(int)) as a Set(Seq(string))")."""
    text = machine("var q: Set(Seq(string))\n    var k: nat = 0\n    event n: nat\n    event has: boolean",
                   'q = if k == 0 then {x: nat | x in {1, 2} @ <>} else {<"a">, <"b">} end ; '
                   "k = k + 1 ; n!size(q) ; has!(<> in q)")
    built = build_text(tmp_path, "comprehension", text)
    # first go: {<>, <>} = {<>}, one element, the empty sequence; then {<"a">, <"b">}
    outputs, _ = outputs_by_instant(built, {1: GO, 2: GO}, 3)
    assert outputs[1] == {"n": {"n.value": 1}, "has": {"has.value": True}}
    assert outputs[2] == {"n": {"n.value": 2}, "has": {"has.value": False}}


def test_rinv_converts_its_relation_to_the_swapped_pairs_of_its_result(tmp_path):
    """rinv(rsub(R, {2.0})) stored in a Set(real * boolean): R's boolean * real pairs are the
    result's swapped, never the result's own (model 2.1348: "using a Set(boolean * real) as a
    Set(real * boolean)"). dom of a relation of pairs is a set of pairs, not the relation's."""
    inverse = "rinv(rsub({(| false, -0.5 |), (| true, 2.0 |)}, {2.0}))"
    text = machine("var v: Set(real * boolean) = {}\n    var d: Set(int * int) = {}\n    event n: nat\n"
                   "    event has: boolean\n    event first: boolean",
                   f"v = {inverse} ; d = dom({{(| (| 1, -2 |), 3 |)}}) ; n!size(v) ; has!((| -0.5, false |) in v) ;"
                   " first!((| 1, -2 |) in d)")
    built = build_text(tmp_path, "inverse", text)
    # rsub drops the pairs whose second is 2.0: {(false, -0.5)}; rinv: {(-0.5, false)};
    # dom({((1, -2), 3)}) = {(1, -2)}
    outputs, _ = outputs_by_instant(built, {1: GO}, 2)
    assert outputs[1] == {"n": {"n.value": 1}, "has": {"has.value": True}, "first": {"first.value": True}}


def test_iter_of_an_empty_relation_nothing_types(tmp_path):
    """iter(2, {}) is empty and iter(0, {}) the identity, each of the type it is stored as
    (model 2.1506: "'iter' of Set(int) (a relation is a set of pairs)")."""
    text = machine("var r: Set(int * int) = {(| 1, 1 |)}\n    var q: Set(E * E) = {}\n    event n: nat\n    event m: nat",
                   "r = iter(2, (lambda x: nat @ {})(0)) ; q = iter(0, {}) ; n!size(r) ; m!size(q) ;"
                   " w = relcomp(union(w, w), (lambda x: int @ {})(-7)) ; k!size(w)")
    text = text.replace("event n: nat", "var w: Set(boolean * boolean) = {(| true, false |)}\n    event k: nat\n    event n: nat")
    built = build_text(tmp_path, "iterempty", text)
    # iter(2, {}) = {} (r had one pair); iter(0, {}) on E = {(a, a), (b, b)}; the composition of
    # w with the empty relation is empty (model 2.1967: "using a Set(boolean * boolean) as a
    # Set(boolean * int)")
    outputs, _ = outputs_by_instant(built, {1: GO}, 2)
    assert outputs[1] == {"n": {"n.value": 0}, "m": {"m.value": 2}, "k": {"k.value": 0}}


def test_a_conditional_on_a_literal_writes_only_its_branch(tmp_path):
    """`if true then {3} else {x: nat | x in {1, 2} @ x} end`: the comprehension's C function is
    not written, since no call of it would be (model 3.261: "'rg_quant_947' defined but not used",
    -Wunused-function); on `if false` it is, and runs."""
    text = machine("event n: nat\n    event m: nat",
                   "n!size(if true then {3} else {x: nat | x in {1, 2} @ x} end) ;"
                   " m!size(if false then {3} else {x: nat | x in {1, 2, 5} @ x % 2} end)")
    built = build_text(tmp_path, "literalcond", text)
    # {3} has 1 element; {x % 2 | x in {1, 2, 5}} = {1, 0, 1} = {0, 1}: 2
    outputs, _ = outputs_by_instant(built, {1: GO}, 2)
    assert outputs[1] == {"n": {"n.value": 1}, "m": {"m.value": 2}}


def test_a_generic_call_takes_its_type_variable_from_the_typed_argument(tmp_path):
    """concat(<<>>, q) of a Seq(Seq(E)): ?X is bound by <<>> to a Seq(?) first, then q decides it
    (Seq(E)); it had stayed open and become an int, "using a Seq(Seq(E)) as a Seq(Seq(int))"
    (model 3.592)."""
    text = machine("var q: Seq(Seq(E)) = <<E::a>>\n    event n: nat\n    event m: nat",
                   "q = concat(<<>>, q) ; n!size(q) ; m!size(dconcat(q))")
    # concat(<<>>, <<a>>) = <<>, <a>>: 2 elements, their concatenation <a>: 1; the next go
    # puts another <> in front: 3 and 1
    assert two_goes(tmp_path, "generic", text) == ({"n": {"n.value": 2}, "m": {"m.value": 1}},
                                                   {"n": {"n.value": 3}, "m": {"m.value": 1}})
