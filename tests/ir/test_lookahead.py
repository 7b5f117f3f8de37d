"""robogen.ir.lookahead: which resume points a time-free RoboChart FMU can look ahead of, and the
search for the first tock at which a monotone comparison changes."""

from __future__ import annotations

from robogen.codegen.api import front_end
from robogen.ir import model as ir
from robogen.ir.dump import expr
from robogen.ir.lookahead import HORIZON, first_change, lookaheads, monotone
from robogen.ir.lower import lower
from robogen.semantics import types as T
from support.codegen_models import TEST_MODELS


def test_first_change_finds_the_first_tock_where_the_outcome_changes():
    assert first_change(lambda k: -1 if k < 5 else 1) == 5
    assert first_change(lambda k: -1 if k < 2 else 0) == 2
    assert first_change(lambda k: 1 if k <= 1000 else 0) == 1001
    assert first_change(lambda k: 0) == HORIZON  # never: as far as it looks
    calls = []
    first_change(lambda k: calls.append(k) or (-1 if k < 700_000 else 1))
    assert len(calls) < 45  # doubling then bisection: about 2 log2(k) evaluations


def test_monotone_quantities():
    since = ir.Since(T.NAT, 0)
    one = ir.Lit(T.NAT, 1)
    assert monotone(since) and monotone(ir.Conv(T.INT, since)) and monotone(ir.Bin(T.NAT, "add", since, one))
    assert not monotone(ir.Bin(T.NAT, "sub", since, one))  # wraps below 1: not monotone
    assert monotone(ir.Bin(T.INT, "sub", ir.Conv(T.INT, since), ir.Lit(T.INT, 3)))
    assert not monotone(ir.Bin(T.NAT, "mod", since, ir.Lit(T.NAT, 2)))


def test_the_alarm_is_looked_ahead_of_at_every_resume_point():
    """timers.rct: every resume point (the EVALs of its states, its waits) tests only events and
    comparisons of clocks, sinceEntry and wait_left with what does not change with time."""
    model, boundary = front_end([TEST_MODELS["timers"].path])
    m = lower(model, boundary).machines[0]
    found = lookaheads(m)
    labels = {b: m.blocks[b].label for b in found}
    assert sorted(labels.values()) == sorted(["EVAL Off", "EVAL Armed", "EVAL Ringing", "EVAL Snooze", "wait", "wait", "wait", "wait"])
    armed = next(la for b, la in found.items() if labels[b] == "EVAL Armed")
    assert [expr(a) for a in armed.atoms] == ["(int(sinceEntry(n2)) > 3)", "(since(c0) >= delay)"]
    assert len(armed.tests) == 3  # the deadline check, then the guards of t3 and t4


def test_time_read_otherwise_runs_at_every_tock(tmp_path):
    """since(C) % 3 == 1 is not monotone in time: the state that tests it runs at every tock (its
    resume point is not looked ahead of); a during action runs once, after the entry, so the state
    that has one is looked ahead of like any other; so is a wait of a drawn length (drawn when it
    starts)."""
    path = tmp_path / "busy.rct"
    path.write_text("""
interface Outs { event done }
stm Busy {
	uses Outs
	var n: nat = 0
	clock C
	initial i
	state Counting { during n = n + 1 }
	state Waiting { entry wait([1, 3]) ; wait(2) ; send done }
	state Polling { }
	transition t0 { from i to Waiting }
	transition t1 { from Waiting to Counting }
	transition t2 { from Counting to Polling condition sinceEntry(Counting) >= 4 action #C }
	transition t3 { from Polling to Counting condition since(C) % 3 == 1 /\\ n > 2 }
}
""", encoding="utf-8")
    model, boundary = front_end([path])
    m = lower(model, boundary).machines[0]
    found = {m.blocks[b].label for b in lookaheads(m)}
    assert {"EVAL Counting", "EVAL Waiting", "wait"} <= found and "EVAL Polling" not in found
