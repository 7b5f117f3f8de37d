"""Quantifiers, definite descriptions, set comprehensions and ranges over finite domains
(robogen.ir.binders, robogen.ir.finite, robogen.codegen.quantifiers), the toolkit's Union, Inter,
dconcat and iter, conversions between the capacities of nesting levels, and strings passed to
user functions: through the FMU and the reference interpreter, with hand-calculated results."""

from __future__ import annotations

import pytest

from support.codegen_driver import Instant, Scenario, Tick, build, build_text, run_checked
from robogen.diagnostics import RobogenError
from robogen.ir.lower import LoweringOptions


def _run(tmp_path, name: str, text: str, ticks: list[Tick], options: LoweringOptions | None = None,
         c_functions: str | None = None, functions: dict | None = None):
    """One tick per instant; the FMU's trace, after checking that the interpreter's is the same."""
    built = build_text(tmp_path, name, text, options, c_functions)
    return run_checked(built, Scenario([Instant(True, early=(t,)) for t in ticks], half=False), functions=functions)


def _values(trace, clock: str):
    """The value of output ``clock`` at each tick: a scalar, or a collection's elements."""
    out = []
    for s in trace.steps:
        if clock in s.outputs:
            o = s.outputs[clock]
            out.append(o[f"{clock}.value"] if f"{clock}.value" in o else o[f"{clock}.value.elements"][:o[f"{clock}.value.size"]])
    return out


QUANTIFIERS = """\
import set_toolkit::*
import sequence_toolkit::*
enumeration Colour { Red Green Blue }
stm Q {
	var s: Set(int) = {3, -1, 4, 1, 5}
	var q: Seq(nat) = <2, 7, 1, 8>
	var n: nat
	event go: nat
	event all: boolean
	event any: boolean
	event one: boolean
	event squares: Set(int)
	event evens: Set(nat)
	event pick: int
	event cols: nat
	event rng: Set(int)
	initial i
	state Idle { }
	transition t0 { from i to Idle }
	transition t1 { from Idle to Idle trigger go?n action
		all!(forall x: int | x in s @ x < 6) ;
		any!(exists x: nat | x in q @ x > n) ;
		one!(exists1 x: int | 0 <= x /\\ x < 10 @ x * x == n) ;
		squares!{x: int | x in s /\\ x > 0 @ x * x} ;
		evens!{x: nat | x <= n /\\ x % 2 == 0} ;
		pick!(the x: int | x in s /\\ n <= x /\\ x <= n + 1 @ x + 100) ;
		cols!size({c: Colour | c != Colour::Green}) ;
		rng!union({1 to 3}, [n, n + 2))
	}
}
"""


def test_quantifiers_and_comprehensions_over_sets_ranges_and_enumerations(tmp_path):
    got = _run(tmp_path, "q", QUANTIFIERS, [Tick("go", {"go.value": n}) for n in (0, 2)])
    assert got.error is None
    # s = {-1, 1, 3, 4, 5}, q = <2, 7, 1, 8>
    assert _values(got, "all") == [True, True]  # every element of s is below 6
    assert _values(got, "any") == [True, True]  # 2, 7, 1, 8 exceed 0; 7 and 8 exceed 2
    assert _values(got, "one") == [True, False]  # 0 * 0 == 0 (x in 0..9); no square is 2
    assert _values(got, "squares") == [[1, 9, 16, 25]] * 2
    assert _values(got, "evens") == [[0], [0, 2]]
    assert _values(got, "pick") == [101, 103]  # the one element of s in 0..1, in 2..3
    assert _values(got, "cols") == [2, 2]  # Red, Blue
    assert _values(got, "rng") == [[0, 1, 2, 3], [1, 2, 3]]  # {1..3} with [0, 2), with [2, 4)


@pytest.mark.parametrize("n", [4, 10])
def test_the_without_exactly_one_value_is_a_located_run_time_error(tmp_path, n):
    # elements of s in n..n + 1: 4 and 5; none in 10..11
    got = _run(tmp_path, "q", QUANTIFIERS, [Tick("go", {"go.value": n})])
    assert got.error is not None and got.error.instant == 0
    assert "'the' without exactly one value in the x: int | x in s /\\ n <= x /\\ x <= n + 1 @ x + 100 at q.rct:26" \
        in got.error.where


RANGE = """\
stm R {
	var n: int
	event go: int
	event b: boolean
	initial i
	state Idle { }
	transition t0 { from i to Idle }
	transition t1 { from Idle to Idle trigger go?n action b!(exists x: int | x > n /\\ x < n + LIMIT @ x * x == 49) }
}
"""


def test_a_range_of_more_than_65536_integers_is_a_run_time_error(tmp_path):
    # n = -10: x in -10..65525 (x < n + 65536 taken as x <= n + 65536, 65537 integers)
    got = _run(tmp_path, "r", RANGE.replace("LIMIT", "65536"), [Tick("go", {"go.value": -10})])
    assert got.error is not None and "a range of more than 65536 integers in exists x: int" in got.error.where
    got = _run(tmp_path, "r2", RANGE.replace("LIMIT", "65535"), [Tick("go", {"go.value": -10})])
    assert got.error is None and _values(got, "b") == [True]  # -7 and 7 are in it


def test_a_quantifier_over_an_infinite_domain_is_a_located_error(tmp_path):
    path = tmp_path / "u.rct"
    path.write_text(RANGE.replace(" /\\ x < n + LIMIT", ""))
    with pytest.raises(RobogenError) as info:
        build([path], tmp_path / "u")
    message = str(info.value)
    assert "u.rct:8:66:" in message
    assert "'exists' over 'x: int' without a finite domain (int has infinitely many values; bound 'x' in the predicate" in message


TOOLKIT = """\
import set_toolkit::*
import sequence_toolkit::*
import relation_toolkit::*
enumeration Mode { Off Low High }
stm T {
	var A: Set(Set(int)) = {{1, 2}, {2, 3}, {2, 5}}
	var M: Set(Set(Mode))
	var qq: Seq(Seq(nat)) = <<1>, <>, <2, 3>>
	var r: Set(Mode * Mode) = {(| Mode::Off, Mode::Low |)}
	event go
	event u: Set(int)
	event it: Set(int)
	event all: Set(Mode)
	event dc: Seq(nat)
	event id: nat
	initial i
	state Idle { }
	transition t0 { from i to Idle }
	transition t1 { from Idle to Idle trigger go action
		u!Union(A) ; it!Inter(A) ; all!Inter(M) ; dc!dconcat(qq) ; id!size(iter(0, r)) }
}
"""


def test_union_inter_dconcat_and_iter_of_collections_of_collections(tmp_path):
    got = _run(tmp_path, "t", TOOLKIT, [Tick("go", {})])
    assert _values(got, "u") == [[1, 2, 3, 5]]
    assert _values(got, "it") == [[2]]
    # Inter of no set is every value: of an enumeration, its literals; iter(0, r) the identity on them
    assert _values(got, "all") == [[0, 1, 2]]
    assert _values(got, "dc") == [[1, 2, 3]]
    assert _values(got, "id") == [3]


def test_inter_of_no_set_of_integers_is_a_run_time_error(tmp_path):
    text = TOOLKIT.replace("all!Inter(M)", "it!Inter({x: Set(int) | x in A /\\ size(x) > 5})")
    got = _run(tmp_path, "t", text, [Tick("go", {})])
    assert got.error is not None
    assert "'Inter' of an empty set of sets: every value of an infinite type in Inter({x: Set(int) | x in A" in got.error.where


LEVELS = """\
import sequence_toolkit::*
stm L {
	var qq: Seq(Seq(int))
	var q: Seq(int)
	var v: int
	event add: int
	event n: nat
	initial i
	state Idle { }
	transition t0 { from i to Idle }
	transition t1 { from Idle to Idle trigger add?v action q = q ^ <v> ; qq = <q> ^ qq ; n!size(head(qq)) }
}
"""


def test_a_sequence_stored_in_a_nested_level_holds_at_most_that_levels_capacity(tmp_path):
    # --capacity 5,3: q holds 5 numbers, the sequences inside qq 3; the fourth add makes q
    # <1, 2, 3, 4>, which <q> cannot hold
    got = _run(tmp_path, "l", LEVELS, [Tick("add", {"add.value": v}) for v in (1, 2, 3, 4)],
               LoweringOptions(capacity=5, capacities=(5, 3)))
    assert _values(got, "n") == [1, 2, 3]
    assert got.error is not None and got.error.instant == 3
    assert "more than 3 elements (the capacity) in a Seq(int) stored at a nesting level of another capacity at l.rct:11" \
        in got.error.where


def test_a_value_larger_than_256_kib_is_a_located_error_naming_the_capacities_to_lower(tmp_path):
    path = tmp_path / "big.rct"
    path.write_text(LEVELS.replace("Seq(Seq(int))", "Seq(Seq(Seq(int)))").replace("<q> ^ qq", "qq"))
    with pytest.raises(RobogenError) as info:
        build([path], tmp_path / "big", options=LoweringOptions(capacity=32))
    message = str(info.value)
    assert "big.rct:3:6:" in message
    assert "a value of type Seq(Seq(Seq(int))) takes 270600 bytes in C at capacities 32" in message
    build([path], tmp_path / "small", options=LoweringOptions(capacity=32, capacities=(32, 8)))


STRING_FUNCTIONS = """\
import sequence_toolkit::*
function greet(who: string, n: nat): nat { }
function total(names: Seq(string)): nat { }
stm U {
	var q: Seq(string) = <"ab", "c">
	var name: string = "hello"
	event go: string
	event out: nat
	event len: nat
	initial i
	state Idle { }
	transition t0 { from i to Idle }
	transition t1 { from Idle to Idle trigger go?name action out!greet(name, 2) ; q = q ^ <name> ; len!total(q) }
}
"""

STRING_C = """\
#include <string.h>

static uint64_t rg_user_greet(const char *who, uint64_t n)
{
    return (uint64_t)strlen(who) * n;
}

static uint64_t rg_user_total(const rg_model_data *d, rg_seq_s names)
{
    uint64_t i, s = 0;
    for (i = 0; i < names.n; i++) s += (uint64_t)strlen(rg_text(d, names.a[i]));
    return s;
}
"""


def test_a_user_function_receives_a_string_as_its_text(tmp_path):
    """greet: bytes x n; total: the bytes of a sequence's strings (through rg_text). "été" is 5
    bytes in UTF-8: 10, then <"ab", "c", "hello", "été"> is 2 + 1 + 5 + 5 = 13."""
    functions = {"greet": lambda who, n: len(who.encode()) * n, "total": lambda q: sum(len(x.encode()) for x in q)}
    got = _run(tmp_path, "u", STRING_FUNCTIONS, [Tick("go", {"go.value": v}) for v in ("hello", "\u00e9t\u00e9")],
               c_functions=STRING_C, functions=functions)
    assert _values(got, "out") == [10, 10]
    assert _values(got, "len") == [8, 13]


RELATIONS = """\
import function_toolkit::*
import relation_toolkit::*
import set_toolkit::*
enumeration E { A B C }
stm F {
	var r: int <-> int = {(| 1, 2 |), (| 2, 3 |), (| 3, 4 |)}
	var s: Set(int * int) = {(| 1, 2 |), (| 5, 2 |)}
	var g: E <-> E
	event go
	event b1: boolean
	event b2: boolean
	event b3: boolean
	event b4: boolean
	event b5: boolean
	event b6: boolean
	event b7: boolean
	event b8: boolean
	event t1: int <-> int
	event t2: int <-> int
	event u: E <-> E
	initial i
	state Idle { }
	transition t0 { from i to Idle }
	transition t { from Idle to Idle trigger go action b1!isInjection(r) ; b2!isInjection(s) ; t1!tr_closure(r) ;
		t2!funcomp(r, r) ; b3!isFinite(r) ; g = id() ; b4!isTotal(g) ; b5!isBijection(g) ;
		u!refl_tr_closure({(| E::A, E::B |)}) ; b6!disjoint({(| 1, {2} |), (| 2, {3} |)}) ;
		b7!partitions({(| 1, {2} |), (| 2, {3, 2} |)}, {2, 3}) ; b8!isSurjection({(| E::A, E::B |)}) }
}
"""


def _pairs(trace, clock: str) -> list[tuple]:
    (o,) = [s.outputs[clock] for s in trace.steps if clock in s.outputs]
    n = o[f"{clock}.value.size"]
    return list(zip(o[f"{clock}.value.elements._1"][:n], o[f"{clock}.value.elements._2"][:n]))


def test_the_relation_and_function_toolkits_on_finite_relations(tmp_path):
    got = _run(tmp_path, "f", RELATIONS, [Tick("go", {})])
    # r = {1 -> 2, 2 -> 3, 3 -> 4} is injective; s = {1 -> 2, 5 -> 2} is not
    assert [_values(got, b)[0] for b in ("b1", "b2", "b3")] == [True, False, True]
    assert _pairs(got, "t1") == [(1, 2), (1, 3), (1, 4), (2, 3), (2, 4), (3, 4)]  # r, r;r, r;r;r
    assert _pairs(got, "t2") == [(1, 3), (2, 4)]  # funcomp(r, r) = relcomp(r, r)
    # id() on E (its type from where it is stored) is total and a bijection
    assert [_values(got, b)[0] for b in ("b4", "b5")] == [True, True]
    assert _pairs(got, "u") == [(0, 0), (0, 1), (1, 1), (2, 2)]  # {A -> B} with the identity on E
    # {2} and {3} are disjoint; {2} and {3, 2} are not, so no partition; {A -> B} does not reach A and C
    assert [_values(got, b)[0] for b in ("b6", "b7", "b8")] == [True, False, False]


def test_the_identity_relation_on_an_infinite_type_is_a_located_error(tmp_path):
    path = tmp_path / "f.rct"
    path.write_text(RELATIONS.replace("u!refl_tr_closure({(| E::A, E::B |)})", "t1!refl_tr_closure(r)"))
    with pytest.raises(RobogenError) as info:
        build([path], tmp_path / "f")
    assert "f.rct:26:6: 'refl_tr_closure' on int (the identity relation on an infinite type) is not supported" \
        in str(info.value)


BETWEEN_LEVELS = """\
import sequence_toolkit::*
stm C {
	var qq: Seq(Seq(int)) = <<1, 2, 3>>
	event go
	event b: boolean
	event c: boolean
	event d: boolean
	initial i
	state Idle { }
	transition t0 { from i to Idle }
	transition t1 { from Idle to Idle trigger go action b!(qq[1] == <1, 2, 3, 4>) ; c!(<1, 2, 3, 4> in qq) ;
		d!(<1, 2, 3> in qq) }
}
"""


def test_membership_and_equality_between_levels_never_overflow(tmp_path):
    # --capacity 4,3: <1, 2, 3, 4> cannot be an element of qq, and is not (the nested value is
    # converted to the literal's capacity, not the other way round)
    got = _run(tmp_path, "c", BETWEEN_LEVELS, [Tick("go", {})], LoweringOptions(capacity=4, capacities=(4, 3)))
    assert got.error is None
    assert [_values(got, x) for x in "bcd"] == [[False], [False], [True]]
