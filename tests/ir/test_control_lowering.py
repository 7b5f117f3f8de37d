"""Control constructs of issue 10 in the IR, run by the reference interpreter on small models
written here (the FMU runs the same constructs in tests/codegen/test_control.py): let scoping,
applied lambdas, trigger filters, nondeterministic waits, probabilistic junctions, e.v sends,
bidirectional connections and the located errors for what is not supported. Expected values are
worked out by hand from the models."""

from __future__ import annotations

from pathlib import Path

import pytest

from robogen.codegen.api import lower_paths
from robogen.diagnostics import RobogenError
from robogen.ir import model as ir
from robogen.ir.interp import Interpreter


def lower_text(tmp_path: Path, text: str, name: str = "m.rct", **kw) -> ir.Fmu:
    path = tmp_path / name
    path.write_text(text)
    fmu, _ = lower_paths([path], **kw)
    return fmu


def machine(body: str, events: str = "") -> str:
    return f"stm S {{\n{events}\n{body}\n}}\n"


def run(fmu: ir.Fmu, instants: list[dict[str, dict] | None], parameters=None) -> tuple[Interpreter, list[dict]]:
    """Tick the periodic clock once per instant, latching the inputs given (clock -> payload),
    and run every instant to its end; the outputs of each instant."""
    it = Interpreter(fmu, parameters)
    it.exit_initialization()
    seen = []
    for inputs in instants:
        for clock, payload in (inputs or {}).items():
            it.latch(clock, payload)
        outputs: dict = {}
        periodic = True
        while True:
            outputs.update(it.evaluate(periodic).outputs)
            periodic = False
            if not it.update():
                break
        seen.append(outputs)
    return it, seen


LETS = machine("""
	var a: int = 0, b: int = 0, c: int = 0, d: int = 0, e: int = 0
	initial i
	state S0 {
		entry a = let x == 2, y == x * 3 @ y + x ;
		      b = let x == 1 @ (let x == x + 10 @ x * 2) ;
		      c = let x == 5 @ a + x ;
		      d = (lambda p: int, q: int @ p - q)(10, 3) ;
		      e = let f == lambda p: int @ p * p, k == 4 @ f(k + 1)
	}
	transition t0 { from i to S0 }
""")


def test_let_names_are_seen_by_later_definitions_and_hide_outer_names(tmp_path):
    it, _ = run(lower_text(tmp_path, LETS), [None])
    v = it.variables()
    assert v["S.a"] == 8  # y = 2 * 3, y + x = 6 + 2
    assert v["S.b"] == 22  # the inner x is the outer x + 10 = 11, doubled
    assert v["S.c"] == 13  # a (8) is the variable, x the let name
    assert v["S.d"] == 7  # the lambda's parameters in order
    assert v["S.e"] == 25  # a let-bound lambda applied to a let name


LET_OVERRIDE = "import relation_toolkit::*\n" + machine("""
	var a: int = 0, b: int = 0, c: int = 0
	initial i
	state S0 {
		entry a = let f == (lambda x: nat @ x + 1) @ (override(f, {(| 1, 0 |)}) as nat -> nat)(1) ;
		      b = let f == (lambda x: nat @ x + 1) @ (override(f, {(| 1, 0 |)}) as nat -> nat)(4) ;
		      c = let k == 10, f == (lambda x: nat @ x * k) @ let k == 1 @ (override(f, {(| 2, 7 |)}) as nat -> nat)(3 + k)
	}
	transition t0 { from i to S0 }
""")


def test_a_let_bound_lambda_is_a_function_value_override_takes(tmp_path):
    it, _ = run(lower_text(tmp_path, LET_OVERRIDE), [None])
    v = it.variables()
    assert v["S.a"] == 0  # the pair (1, 0) overrides f at 1
    assert v["S.b"] == 5  # elsewhere f: 4 + 1
    assert v["S.c"] == 40  # f reads the k of where it was defined (10), applied to 3 + 1 (the inner k)


FILTER = machine("""
	var x: int = 0, n: nat = 0, m: nat = 0
	initial i
	state Idle { }
	transition t0 { from i to Idle }
	transition t1 { from Idle to Idle trigger value[| x > 3 |]?x action n = n + 1 }
	transition t2 { from Idle to Idle trigger poke[| n >= 2 |] action m = m + 1 }
""", events="event value: int\n\tevent poke")


def test_a_trigger_filter_takes_only_values_that_satisfy_it(tmp_path):
    fmu = lower_text(tmp_path, FILTER)
    value = lambda v: {"value": {"value.value": v}}  # noqa: E731
    it, _ = run(fmu, [None, value(3), {"poke": {}}, value(4), value(9), {"poke": {}}])
    v = it.variables()
    # 3 is refused and not bound; 4 and 9 are taken; poke is refused while n < 2 (it waits in the
    # buffer, and is taken once 9 makes n = 2: m = 1), then taken again
    assert v["S.x"] == 9 and v["S.n"] == 2 and v["S.m"] == 2


WAITS = machine("""
	var k: nat = 0
	initial i
	state A { entry wait((0, 3]) ; k = k + 1 ; wait({4}) ; out }
	transition t0 { from i to A }
""", events="event out")


def test_a_wait_on_a_range_draws_its_length_from_the_seeded_generator(tmp_path):
    fmu = lower_text(tmp_path, WAITS)
    assert [p.fmi_name for p in fmu.params] == ["random_seed"] and fmu.params[0].value == ir.RANDOM_SEED
    # seed 0: the first output 0xe220a8397b1dcdaf mod 3 = 1, so (0, 3] = [1, 3] gives 1 + 1 = 2;
    # then wait({4}) is 4: out at 2 + 4 = 6
    _, seen = run(fmu, [None] * 8)
    assert [t for t, o in enumerate(seen) if o] == [6]
    # seed 0 - 0x9E3779B97F4A7C15: the first output is mix(0) = 0, a wait of 1: out at 5
    _, seen = run(fmu, [None] * 8, parameters={"random_seed": (-0x9E3779B97F4A7C15) % 2**64})
    assert [t for t, o in enumerate(seen) if o] == [5]


EMPTY = machine("""
	initial i
	state A { entry wait([3, 2]) }
	transition t0 { from i to A }
""")


def test_an_empty_range_is_a_run_time_error(tmp_path):
    from robogen.ir.interp import RuntimeFault

    with pytest.raises(RuntimeFault, match="empty range: 3 to 2"):
        run(lower_text(tmp_path, EMPTY), [None])


COIN = machine("""
	var heads: nat = 0, tails: nat = 0
	initial i
	state Toss { }
	probabilistic P
	transition t0 { from i to Toss }
	transition t1 { from Toss to P condition since(C) >= 1 action #C }
	transition h { from P to Toss probability 0.3 action heads = heads + 1 }
	transition t { from P to Toss probability 0.7 action tails = tails + 1 }
	clock C
""")


def test_a_probabilistic_junction_follows_its_probabilities(tmp_path):
    fmu = lower_text(tmp_path, COIN)
    it, _ = run(fmu, [None] * 2000)
    v = it.variables()
    assert v["S.heads"] + v["S.tails"] == 2000  # one toss per tock
    # 2000 draws: 600 expected heads, standard deviation sqrt(2000 * 0.3 * 0.7) = 20.5
    assert 520 < v["S.heads"] < 680
    # the same seed, the same run
    again, _ = run(fmu, [None] * 2000)
    assert again.variables() == v


UNSUPPORTED = [
    ("event value: int", "var x: int = 0, y: boolean = false",
     "trigger value[| y = from |]?x", "the sender in 'y' of type boolean (robogen gives the sender as a number, nat or int, "
                                      "or as a name, string) is not supported"),
    ("event value: int", "var x: int = 0",
     "action value[| x > 1 |]!x", "a filter on an output or synchronisation is not supported"),
]


@pytest.mark.parametrize("events, variables, clause, message", UNSUPPORTED)
def test_what_is_not_supported_is_reported_where_it_is(tmp_path, events, variables, clause, message):
    text = machine(f"""
	{variables}
	initial i
	state A {{ }}
	transition t0 {{ from i to A }}
	transition t1 {{ from A to A {clause} }}
""", events=events)
    with pytest.raises(RobogenError) as info:
        lower_text(tmp_path, text)
    assert message in str(info.value)
    assert "m.rct:8:" in str(info.value)
