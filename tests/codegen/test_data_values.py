"""RoboChart's data values through the FMU and the reference interpreter, with hand-calculated
results: sets at a capacity of 2 (an overflow is an fmi3Error whose message names the expression
and its model line, and never corrupts memory), function values, and strings."""

from __future__ import annotations

from pathlib import Path

from support.codegen_driver import FmuRunner, Instant, Scenario, Tick, build_text, interpret
from support.codegen_models import MODELS
from robogen.ir.lower import LoweringOptions

MODEL = """\
import set_toolkit::*
import sequence_toolkit::*
stm Grow {
	var s: Set(int) = {1}
	var v: int
	event add: int
	event size_: nat
	initial i
	state Idle { }
	transition t0 { from i to Idle }
	transition t1 { from Idle to Idle trigger add?v action s = union(s, {v}) ; size_!size(s) }
}
"""


def _run(tmp_path, name: str, text: str, scenario: Scenario, options: LoweringOptions | None = None,
         c_functions: str | None = None, functions: dict | None = None):
    built = build_text(tmp_path, name, text, options, c_functions)
    runner = FmuRunner(built.folder)
    try:
        got = runner.run(scenario)
    finally:
        runner.close()
    expected = interpret(built.fmu, scenario, runner.desc, functions=functions)
    assert got.comparable() == expected.comparable()
    return got, expected


def test_a_capacity_of_2_overflows_at_the_third_member(tmp_path):
    add = [Tick("add", {"add.value": v}) for v in (2, 2, -5)]
    # {1} + 2 = {1, 2}; + 2 again changes nothing; + -5 would be {-5, 1, 2}: 3 > 2
    scenario = Scenario([Instant(True, early=(t,)) for t in add], half=False)
    got, expected = _run(tmp_path, "grow", MODEL, scenario, LoweringOptions(capacity=2))
    message = "more than 2 elements (the capacity) in union(s, {v}) at grow.rct:11"
    assert expected.error is not None and message in expected.error.where
    assert got.error is not None and message in got.error.where, got.error.where
    assert got.error.instant == 2
    sizes = [s.outputs["size_"]["size_.value"] for s in got.steps if "size_" in s.outputs]
    assert sizes == [2, 2]
    last = got.steps[-1].variables
    assert last["Grow.s.elements"] == [1, 2] and last["Grow.s.size"] == 2


FUNCTION_VARIABLE = """\
stm Late {
	var f: nat -> nat
	event go
	event out: nat
	initial i
	state Idle { }
	transition t0 { from i to Idle }
	transition t1 { from Idle to Idle trigger go action out!f(1) ; f = lambda x: nat @ x + 1 }
}
"""




def test_a_function_variable_applied_before_any_assignment_is_a_located_error(tmp_path):
    scenario = Scenario([Instant(True, early=(Tick("go", {}),))], half=False)
    got, expected = _run(tmp_path, "late", FUNCTION_VARIABLE, scenario)
    message = "function variable 'f' applied outside its domain (or before it has a value) at late.rct:8"
    assert expected.error is not None and message in expected.error.where
    assert got.error is not None and message in got.error.where, got.error.where


def test_function_values_give_the_hand_calculated_results(tmp_path):
    """tests/codegen/models/functions.rct: f starts as x, then x * 10 - 5, then x + 1 overridden at
    2 (100) and 3 (-3); the two-parameter lambda gives n * 2 - 1."""
    ticks = [("use", 2), ("set", 1), ("use", 3), ("set", 2), ("use", 2), ("use", 3), ("use", 4), ("set", 0), ("use", 2)]
    scenario = Scenario([Instant(True, early=(Tick(c, {f"{c}.value": v}),)) for c, v in ticks], half=False)
    text = (MODELS / "functions.rct").read_text()
    got, _ = _run(tmp_path, "functions", text, scenario)
    applied = [(s.outputs["applied"]["applied.value"], s.outputs["product"]["product.value"])
               for s in got.steps if "applied" in s.outputs]
    assert applied == [(2, 3), (25, 5), (100, 3), (-3, 5), (5, 7), (3, 3)]


COPIES = """\
stm Copy {
	var f: nat -> int = lambda x: nat @ x + 1
	var g: nat -> int = lambda x: nat @ x * 10
	var n: nat = 0
	event go: nat
	event first: int
	event second: int
	event third: int
	initial i
	state Idle { }
	transition t0 { from i to Idle }
	transition t1 { from Idle to Idle trigger go?n
		action f = g ; g = lambda x: nat @ x + 100 ; first!f(n) ; second!g(n) ; f = f ; third!f(n) }
}
"""


def test_a_function_variable_assigned_another_takes_the_value_it_holds(tmp_path):
    """Found by the model fuzzer: `f = f` (a function variable stored in itself) made code
    generation recurse without end. `f = g` copies the function g holds then: go(2) gives
    f = x * 10 (20), g = x + 100 (102), f unchanged by f = f (20); go(3): f takes g's x + 100."""
    scenario = Scenario([Instant(True, early=(Tick("go", {"go.value": v}),)) for v in (2, 3)], half=False)
    got, _ = _run(tmp_path, "copies", COPIES, scenario)
    outputs = {}
    for s in got.steps:
        for clock, values in s.outputs.items():
            outputs.setdefault(clock, []).append(values[f"{clock}.value"])
    assert outputs == {"first": [20, 103], "second": [102, 103], "third": [20, 103]}


OPERATION_FUNCTIONS = """\
interface Ops { twice(n: int) }
operation twice(n: int) {
	event first: int
	event second: int
	var f: int -> int = lambda x: int @ x * 2
	var g: int -> int
	initial i
	final F
	transition t { from i to F action first!f(n) ; g = f ; f = lambda x: int @ x + 1 ; second!(f(n) + g(n)) }
}
stm S {
	requires Ops
	event go: int
	event first: int
	event second: int
	var k: int = 0
	initial i
	state A { }
	transition t0 { from i to A }
	transition t1 { from A to A trigger go?k action twice(k) }
}
"""


def test_an_operation_has_function_variables_of_its_own(tmp_path):
    """Found by the model fuzzer: a function variable declared by an operation was "not supported"
    (its initial lambda, its assignments). Each call starts f as x * 2: go(5) sends f(5) = 10,
    then (g = the old f, f = x + 1) 6 + 10; go(3) sends 6, then 4 + 6."""
    scenario = Scenario([Instant(True, early=(Tick("go", {"go.value": v}),)) for v in (5, 3)], half=False)
    got, _ = _run(tmp_path, "opfun", OPERATION_FUNCTIONS, scenario)
    sent = [(c, v[f"{c}.value"]) for s in got.steps for c, v in sorted(s.outputs.items())]
    assert sent == [("first", 10), ("second", 16), ("first", 6), ("second", 10)]


MIXED = (Path(__file__).resolve().parent / "models" / "mixed.rct")


def test_tuples_of_structures_relations_of_collections_and_a_folded_zero(tmp_path):
    """Found by the model fuzzer, each a C compiler error: a tuple whose component is a matrix
    or a set had the C name of one whose component is an int; a conditional of tuple literals
    (nat * int * Set) as an int * int * Set; a tuple field of a record given a tuple of nats;
    min of a Set(nat) compared as an int; `x < (let z == 0 @ z)` of a nat (-Wtype-limits);
    maplet of a vector and a sequence ("not supported"). cell = t[2][2, 1] = 3;
    low = min({1, 100}) + p[1] + r.f2[1] = 1 + 2 + 7 % 5 = 5; decided = 0 < 0."""
    scenario = Scenario([Instant(True, early=(Tick("go", {}),))], half=False)
    got, _ = _run(tmp_path, "mixed", MIXED.read_text(), scenario)
    sent = {k: v for s in got.steps for c, values in s.outputs.items() for k, v in values.items()}
    assert sent["cell.value"] == 3 and sent["low.value"] == 5 and sent["decided.value"] is False
    assert sent["pair._1"] == [2, 2] and sent["pair._2.size"] == 1 and sent["pair._2.elements"][0] == 7


KNOWN = """\
import sequence_toolkit::*
import relation_toolkit::*
stm U {
	var q: Seq(boolean)
	var b: boolean = true
	event go
	event n: nat
	event fresh: boolean
	event grown: nat
	event kept: nat
	event keys: nat
	event picked: nat
	event imaged: nat
	event overridden: nat
	initial i
	state A { }
	transition t0 { from i to A }
	transition t1 { from A to A trigger go action q = (if b then <> else <true> end) ^ (<> ^ <false, true>) ; n!size(q) ;
		fresh!prefix((lambda x: boolean @ <>)(b), extract({1}, <false>)) ; grown!size(if b then <> else <true> end) ;
		kept!size(filter(<-100, 5>, {0, 5})) ; keys!size(dom(if b then {} else {(| 2, 0 |)} end)) ; b = not b ;
		q = extract({1}, let l == 1 @ <>) ; picked!size(q) ;
		imaged!size(rimage((lambda x: nat @ {})(1), {1})) ; overridden!size(dom(override({}, {(| 1, 2 |), (| 3, 4 |)}))) }
}
"""


def test_an_empty_branch_or_operand_takes_the_type_of_the_other(tmp_path):
    """Found by the model fuzzer: `if b then <> else <true> end` and `<> ^ <false, true>` have, for
    the checker, elements of no known type; `prefix((lambda x: boolean @ <>)(b), extract(...))` was "not
    supported" (a Seq(boolean) as a Seq(int)). They are sequences of booleans: q holds 2, then 3
    elements; <> is a prefix of <false>; the conditional holds 0, then 1 element. A Seq(int)
    filtered by a Set(nat) did not compile (the set was made a sequence): 5 is kept. The domain of
    `if b then {} else {(| 2, 0 |)} end` was "a set of ?X" (the checker typed the conditional by
    its empty branch): it has 0, then 1 key. `extract({1}, let l == 1 @ <>)` stored in the
    Seq(boolean) q was "using a Seq(int) as a Seq(boolean)": it is empty. The image of the empty
    relation a lambda gives was "'rimage' of Set(int)": empty; override({}, r) is r, 2 keys."""
    scenario = Scenario([Instant(True, early=(Tick("go", {}),)) for _ in range(2)], half=False)
    got, _ = _run(tmp_path, "known", KNOWN, scenario)
    sent = [{c: v[f"{c}.value"] for c, v in s.outputs.items()} for s in got.steps if s.outputs]
    assert sent == [{"n": 2, "fresh": True, "grown": 0, "kept": 1, "keys": 0, "picked": 0, "imaged": 0, "overridden": 2},
                    {"n": 3, "fresh": True, "grown": 1, "kept": 1, "keys": 1, "picked": 0, "imaged": 0, "overridden": 2}]


EMPTY = """\
import set_toolkit::*
import sequence_toolkit::*
datatype P { x: nat }
stm Empty {
	event go
	event seq: Seq(P)
	event count: nat
	event same: boolean
	var s: Set(int) = {5}
	var b: boolean = true
	initial i
	state Idle { }
	transition t0 { from i to Idle }
	transition t1 { from Idle to Idle trigger go action seq!(let q == if b then <> else <> end @ reverse(q)) ;
		s = union({}, inter({}, {})) ; count!(size(union({}, {})) + 7) ; same!({} != {}) ; b = not b }
}
"""


def test_empty_enumerations_that_nothing_types_are_empty_sets_and_sequences(tmp_path):
    """Found by the model fuzzer: `{} != {}` and `if b then <> else <> end` (elements of no known
    type) crashed code generation (no C type for <unknown>). They are empty: seq sends no
    element, count is 0 + 7, the two empty sets are equal, s becomes empty."""
    scenario = Scenario([Instant(True, early=(Tick("go", {}),)) for _ in range(2)], half=False)
    got, _ = _run(tmp_path, "empty", EMPTY, scenario)
    sent = [s.outputs for s in got.steps if s.outputs]
    assert [o["seq"]["seq.value.size"] for o in sent] == [0, 0]
    assert [o["count"]["count.value"] for o in sent] == [7, 7]
    assert [o["same"]["same.value"] for o in sent] == [False, False]
    assert got.steps[-1].variables["Empty.s.size"] == 0


PAIRS = """\
import sequence_toolkit::*
stm Pairs {
	var p: Seq(nat * nat) = <(| 1, 2 |), (| 3, 4 |)>
	var q: Seq(int * int)
	var s: Set(nat * real) = {(| 2, 0.5 |), (| 1, 1.5 |)}
	var u: Set(real * real)
	event go
	event first: int
	event count: nat
	event member: boolean
	initial i
	state Idle { }
	transition t0 { from i to Idle }
	transition t1 { from Idle to Idle trigger go
		action q = reverse(p) ; first!(q[1][1] - 10) ; u = s ; count!size(u) ; member!((| 1.0, 1.5 |) in u) }
}
"""


def test_a_collection_of_tuples_is_used_as_one_of_wider_numbers(tmp_path):
    """Found by the model fuzzer: a Seq(nat * nat) used as a Seq(int * int) was "not supported"; its
    tuples are converted field by field: q[1] is (| 3, 4 |), so first is 3 - 10; u holds the two
    pairs of s as reals, (| 1.0, 1.5 |) among them."""
    scenario = Scenario([Instant(True, early=(Tick("go", {}),))], half=False)
    got, _ = _run(tmp_path, "pairs", PAIRS, scenario)
    sent = {c: v[f"{c}.value"] for s in got.steps for c, v in s.outputs.items()}
    assert sent == {"first": -7, "count": 2, "member": True}


STRINGS = """\
stm Str {
	const greeting: string = "hello"
	var name: string = "world"
	event flip
	event eq: boolean
	initial i
	state Idle { }
	transition t0 { from i to Idle }
	transition t1 { from Idle to Idle trigger flip
		action if name == "world" then name = "hello" else name = "world" end ; eq!(name == greeting) }
}
"""


def test_strings_are_literals_compared_for_equality(tmp_path):
    scenario = Scenario([Instant(True, early=(Tick("flip", {}),)) for _ in range(3)], half=False)
    got, _ = _run(tmp_path, "strings", STRINGS, scenario)
    assert [s.outputs["eq"]["eq.value"] for s in got.steps if "eq" in s.outputs] == [True, False, True]


EXTRACT = """\
import sequence_toolkit::*
stm Ex {
	var q: Seq(nat) = <10, 20, 30, 40>
	event go
	event picked: Seq(nat)
	initial i
	state Idle { }
	transition t0 { from i to Idle }
	transition t1 { from Idle to Idle trigger go action picked!extract({4, 1, 9, 2}, q) ; q = extract({2, 3}, q) }
}
"""


def test_extract_keeps_the_elements_at_the_positions_in_the_set_in_order(tmp_path):
    # <10, 20, 30, 40> at {1, 2, 4, 9}: <10, 20, 40> (position 9 is none); q becomes <20, 30>,
    # then <30>, then <> (it has no position 2 or 3)
    scenario = Scenario([Instant(True, early=(Tick("go", {}),)) for _ in range(3)], half=False)
    got, _ = _run(tmp_path, "ex", EXTRACT, scenario, LoweringOptions(capacity=4))
    picked = [s.outputs["picked"] for s in got.steps if "picked" in s.outputs]
    assert [p["picked.value.elements"][:p["picked.value.size"]] for p in picked] == [[10, 20, 40], [20, 30], [30]]
    assert got.steps[-1].variables["Ex.q.size"] == 0


CONVERSIONS = """\
import set_toolkit::*
import sequence_toolkit::*
stm Conv {
	var a: Set(nat) = {3, 1}
	var b: Set(int)
	var q: Seq(nat) = <2, 1>
	var r: Seq(real)
	event go
	event n: nat
	event sum: real
	initial i
	state Idle { }
	transition t0 { from i to Idle }
	transition t1 { from Idle to Idle trigger go
		action b = a ; b = union(b, {-1}) ; n!size(b) ; r = q ; sum!(r[1] + r[2] / 4.0) }
}
"""


def test_a_set_of_nat_is_used_as_a_set_of_int(tmp_path):
    scenario = Scenario([Instant(True, early=(Tick("go", {}),))], half=False)
    got, _ = _run(tmp_path, "conv", CONVERSIONS, scenario)
    step = next(s for s in got.steps if "n" in s.outputs)
    assert step.outputs["n"]["n.value"] == 3  # {-1, 1, 3}
    assert step.outputs["sum"]["sum.value"] == 2.25  # 2 + 1 / 4
    assert step.variables["Conv.b.elements"][:3] == [-1, 1, 3] and step.variables["Conv.b.size"] == 3


RELATIONS = """\
import relation_toolkit::*
import sequence_toolkit::*
import set_toolkit::*
stm Rel {
	var r: nat <-> int = {(| 1, 10 |), (| 2, 20 |), (| 3, 30 |)}
	var s: Set(nat * int)
	var t: int <-> nat
	var q: Seq(int)
	event go
	event n1: nat
	event n2: nat
	event n3: nat
	initial i
	state Idle { }
	transition t0 { from i to Idle }
	transition t1 { from Idle to Idle trigger go
		action s = override(r, {(| 2, -2 |)}) ; n1!size(dres({1, 2}, s)) ; q = squash(s) ;
			t = relcomp(rinv(s), {(| 1, 100 |), (| 3, 300 |)}) ; n2!size(rimage(t, {10, -2})) ; n3!size(ran(t)) }
}
"""


def test_relations_are_sets_of_pairs(tmp_path):
    """override(r, {(2, -2)}) = {(1, 10), (2, -2), (3, 30)}; its dres to {1, 2} has 2 pairs; squash
    gives <10, -2, 30>; rinv then relcomp with {(1, 100), (3, 300)} gives {(10, 100), (30, 300)},
    whose rimage of {10, -2} is {100} and whose ran is {100, 300}."""
    scenario = Scenario([Instant(True, early=(Tick("go", {}),))], half=False)
    got, _ = _run(tmp_path, "rel", RELATIONS, scenario)
    step = next(s for s in got.steps if "n1" in s.outputs)
    sizes = [step.outputs[n][f"{n}.value"] for n in ("n1", "n2", "n3")]
    assert sizes == [2, 1, 2]
    v = step.variables
    assert v["Rel.q.elements"][:v["Rel.q.size"]] == [10, -2, 30]


USER_FUNCTION = """\
import sequence_toolkit::*
function total(q: Seq(int), p: nat * int): int { }
stm U {
	var q: Seq(int) = <1, 2, 3>
	event go
	event out: int
	initial i
	state Idle { }
	transition t0 { from i to Idle }
	transition t1 { from Idle to Idle trigger go action out!total(q, (| 2, 5 |)) ; q = q ^ <4> }
}
"""

TOTAL_C = """\
static int64_t rg_user_total(rg_seq_i q, rg_tup2_u_i p)
{
    int64_t s = 0;
    uint64_t i;
    for (i = 0; i < q.n; i++) s += q.a[i];
    return s * (int64_t)p._1 + p._2;
}
"""


def test_a_user_function_takes_a_sequence_and_a_tuple(tmp_path):
    """total(<1, 2, 3>, (2, 5)) = 6 * 2 + 5 = 17, then total(<1, 2, 3, 4>, (2, 5)) = 25."""
    def total(q, p):
        return sum(q) * p["_1"] + p["_2"]

    scenario = Scenario([Instant(True, early=(Tick("go", {}),)) for _ in range(2)], half=False)
    got, _ = _run(tmp_path, "user", USER_FUNCTION, scenario, c_functions=TOTAL_C, functions={"total": total})
    assert [s.outputs["out"]["out.value"] for s in got.steps if "out" in s.outputs] == [17, 25]


RECORD_DEFAULTS = """\
datatype DT {
	q: nat
	p: nat
	s: Set(int)
}
stm R {
	var i: DT = DT(| p = 2 |)
	event go
	event out: nat
	initial i0
	state Idle { }
	transition t0 { from i0 to Idle }
	transition t1 { from Idle to Idle trigger go action out!(i.q + i.p + size(i.s)) ; i = DT(| q = 5, p = i.p |) }
}
"""


def test_a_record_literal_that_leaves_out_fields_gives_them_their_default(tmp_path):
    """RoboTool warns about DT(| p = 2 |); q is 0 and s empty: 0 + 2 + 0 = 2, then 5 + 2 + 0 = 7."""
    scenario = Scenario([Instant(True, early=(Tick("go", {}),)) for _ in range(2)], half=False)
    got, _ = _run(tmp_path, "defaults", "import sequence_toolkit::*\n" + RECORD_DEFAULTS, scenario)
    assert [s.outputs["out"]["out.value"] for s in got.steps if "out" in s.outputs] == [2, 7]


OVERRIDDEN = """\
import relation_toolkit::*
function add(x: nat, y: nat): nat { }
stm O {
	event go: nat
	event out: nat
	var k: nat = 0
	initial i
	state Idle { }
	transition t0 { from i to Idle }
	transition t1 { from Idle to Idle trigger go?k action out!((override(add, { (| (| 0, k |), 7 |) }) as (nat * nat) -> nat)(0, 1)) }
}
"""

ADD_C = "static uint64_t rg_user_add(uint64_t x, uint64_t y) { return x + y; }\n"


def test_a_function_overridden_at_a_pair_compares_the_arguments_as_a_tuple(tmp_path):
    """override(add, {(0, k) |-> 7}) applied to (0, 1): the pair (0, 1) is compared with the key
    (0, k), a tuple type the model names nowhere else: k = 1 gives 7, k = 2 gives add(0, 1) = 1."""
    scenario = Scenario([Instant(True, early=(Tick("go", {"go.value": k}),)) for k in (1, 2)], half=False)
    got, _ = _run(tmp_path, "overridden", OVERRIDDEN, scenario, c_functions=ADD_C, functions={"add": lambda x, y: x + y})
    assert [s.outputs["out"]["out.value"] for s in got.steps if "out" in s.outputs] == [7, 1]


UNTYPED_NESTED = """\
import sequence_toolkit::*
import set_toolkit::*
stm Flat {
	var qq: Seq(Seq(nat)) = <<1>>
	var ss: Set(Set(int)) = {{1}}
	event go
	event deep: nat
	event sets: nat
	event joined: nat
	initial i
	state A { }
	transition t0 { from i to A }
	transition t1 { from A to A trigger go action qq = dconcat(<<>, (let l == 1 @ <>)>) ; deep!size(qq) ;
		ss = Union({{}, (let l == 2 @ {})}) ; sets!size(ss) ; qq = <<2>> ^ dconcat(<<>>) ; joined!size(qq) }
}
"""


def test_dconcat_and_union_of_collections_nothing_typed_take_the_type_they_are_used_as(tmp_path):
    """Found by the model fuzzer: `dconcat(<<>, (let l == 1 @ <>)>)` stored in a Seq(Seq(nat)) was
    "using a Seq(int) as a Seq(Seq(int))" (its elements nothing typed); likewise Union of empty
    sets. Both are empty: 0 and 0; `<<2>> ^ dconcat(<<>>)` holds one sequence: 1."""
    scenario = Scenario([Instant(True, early=(Tick("go", {}),))], half=False)
    got, _ = _run(tmp_path, "flat", UNTYPED_NESTED, scenario, LoweringOptions(capacities=(8, 4, 2)))
    sent = [(c, v[f"{c}.value"]) for s in got.steps for c, v in s.outputs.items()]
    assert sorted(sent) == [("deep", 0), ("joined", 1), ("sets", 0)]
