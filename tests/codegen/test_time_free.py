"""RoboChart time for free (issue 22): an FMU compiled with ``--time skip`` (the default) has no
``tock`` clock, counts its tocks and announces the next tock at which anything can happen as
nextEventTime (robogen.ir.lookahead); ``--time tick`` keeps the clock. Both must show the same
trace - every transition, output tick, state and variable change, with its time - which
:func:`robogen.differential.run_in_time` records driving each as a master would: the ticking one
in Event Mode at every tock, the skipping one only at its next event times and at input events."""

from __future__ import annotations

import random
from pathlib import Path

import pytest

from robogen.differential import Tick, Timed, build, first_time_difference, run_in_time, timed_events
from robogen.diagnostics import RobogenError
from robogen.fuzz.features import DEFAULT
from robogen.fuzz.model import generate, model_seed
from robogen.ir.interp import Interpreter
from robogen.ir.lower import LoweringOptions
from support.codegen_models import ROOT, TEST_MODELS

# A machine that waits 5 time units and says so, then waits for 'go' (an event, no time); 3 time
# units after entering Armed it goes back to Idle, which waits 5 units again.
WAITER = """
package waiter
interface Outs { event done }
interface Ins { event go }
stm Waiter {
	uses Outs uses Ins
	initial i
	state Idle { entry wait(5) ; send done }
	state Armed { }
	transition t0 { from i to Idle }
	transition t1 { from Idle to Armed trigger go }
	transition t2 { from Armed to Idle condition sinceEntry(Armed) >= 3 }
}
"""


@pytest.fixture(scope="module")
def waiter(tmp_path_factory):
    work = tmp_path_factory.mktemp("waiter")
    model = work / "waiter.rct"
    model.write_text(WAITER, encoding="utf-8")
    return {t: build([model], work / t, machine="Waiter", options=LoweringOptions(time=t)) for t in ("tick", "skip")}


def test_wait_five_then_output_at_five(waiter):
    """By hand: tock 0 (t=0) enters Idle and starts wait(5); tocks 1..4 count it down; at tock 5
    the wait is over and 'done' ticks, at t=5, in both variants. 'go' at t=7.5 enters Armed (with
    8 tocks counted); sinceEntry(Armed) >= 3 holds at tock 10 (t=10), back to Idle, whose wait(5)
    ends with 'done' at t=15. The skipping FMU is in Event Mode at 0, 5, 7.5, 10, 15 only."""
    events = [Timed(15, (Tick("go", {}),))]
    traces = {t: run_in_time(b.folder, events, 20) for t, b in waiter.items()}
    assert first_time_difference(traces["tick"], traces["skip"]) is None
    outputs = [(r[1] / 2, r[3]) for r in traces["skip"].records if r[0] == "step" and r[3]]
    assert outputs == [(5.0, {"done": {}}), (15.0, {"done": {}})]
    states = []
    for r in traces["skip"].records:
        if r[0] == "step" and (not states or states[-1][1] != r[4]["Waiter.state"]):
            states.append((r[1] / 2, r[4]["Waiter.state"]))
    nodes = {n.label: n.id for n in waiter["skip"].fmu.machines[0].nodes}
    assert states == [(0.0, nodes["Idle"]), (7.5, nodes["Armed"]), (10.0, nodes["Idle"])]
    transitions = [(r[1] / 2, r[3].split(": ", 1)[1]) for r in traces["skip"].records if r[0] == "transition"]
    assert transitions == [(0.0, "Waiter: t0: i -> Idle"), (7.5, "Waiter: t1: Idle -> Armed"), (10.0, "Waiter: t2: Armed -> Idle")]
    assert traces["skip"].instants == 6  # 0, 5, 7.5, 10, 15 and the end, 20: none at the 15 other tocks
    assert traces["tick"].instants == 22  # 21 tocks (0..20) and the event at 7.5


def test_next_event_time_announced(waiter):
    """The skipping FMU announces 5 after the first instant (wait(5) from t=0); the reference
    interpreter looks ahead the same 5 tocks, then none (waiting for 'go' only)."""
    from robogen.differential import FmuRunner

    runner = FmuRunner(waiter["skip"].folder)
    try:
        runner.inst.fmi3EnterInitializationMode(None, 0.0, None)
        runner.inst.fmi3ExitInitializationMode()
        states = runner.inst.fmi3UpdateDiscreteStates()
        assert (states.next_event_time_defined, states.next_event_time) == (True, 5.0)
        assert runner.desc.periodic is None and "tock" not in runner.desc.by_name
    finally:
        runner.close()
    it = Interpreter(waiter["skip"].fmu)
    it.exit_initialization()
    it.evaluate(True)
    assert not it.update()
    assert it.idle_tocks() == 5
    it.pass_idle(4)
    it.evaluate(True)  # tock 5: the wait is over, 'done'
    assert not it.update()
    assert it.idle_tocks() is None and it.cycles == 6


def test_ticking_fmu_keeps_its_tock_clock(waiter):
    desc = waiter["tick"].desc
    assert desc.periodic == "tock" and desc.interval == 1.0
    assert desc.by_name["go"].vr == waiter["skip"].desc.by_name["go"].vr  # both number their variables alike


def _started(folder: Path):
    from robogen.differential import FmuRunner

    runner = FmuRunner(folder)
    runner.inst.fmi3EnterInitializationMode(None, 0.0, None)
    runner.inst.fmi3ExitInitializationMode()
    runner.inst.fmi3UpdateDiscreteStates()
    runner.inst.fmi3EnterStepMode()
    return runner


def test_a_step_past_the_next_event_time_is_warned_and_taken_late(waiter):
    """An importer that ignores nextEventTime (fmpy's simulate_fmu): the step from 0 to 6 passes
    the wait's end at 5, with a warning; the machine takes it at the next Event Mode, at 6."""
    from robogen.differential import FmuRunner

    runner = FmuRunner(waiter["skip"].folder, logging=True)
    try:
        runner.inst.fmi3EnterInitializationMode(None, 0.0, None)
        runner.inst.fmi3ExitInitializationMode()
        runner.inst.fmi3UpdateDiscreteStates()
        runner.inst.fmi3EnterStepMode()
        runner.inst.fmi3DoStep(0.0, 6.0)
        assert any("passes the next event time t=5" in m for m in runner.messages), runner.messages
        runner.inst.fmi3EnterEventMode()
        step = runner.observe(0, 0)
        assert step.outputs == {"done": {}} and step.cycles == 7
        assert not runner.inst.fmi3UpdateDiscreteStates().next_event_time_defined
    finally:
        runner.close()


def test_idle_tocks_are_counted_in_the_step(waiter):
    """Up to the next event time (5), then 100 units with nothing announced: 'cycles' counts every
    tock the step passes, 0 to 104, as the ticking FMU does. The tock at the step's end (105)
    belongs to an Event Mode there, where an event may come with it (the ticking FMU runs its
    machines at that tock after the event's machine): counted by that Event Mode, 106, or by the
    next step."""
    from robogen.cosim import fmi3

    runner = _started(waiter["skip"].folder)

    def cycles() -> int:
        value = fmi3.value_array("UInt64", 1)
        runner.inst.get("UInt64", fmi3.vr_array([runner.desc.by_name["cycles"].vr]), 1, value, n_values=1)
        return value[0]

    try:
        runner.inst.fmi3DoStep(0.0, 5.0)
        runner.inst.fmi3EnterEventMode()
        runner.inst.fmi3UpdateDiscreteStates()  # 'done' at 5; nothing announced after it
        runner.inst.fmi3EnterStepMode()
        runner.inst.fmi3DoStep(5.0, 100.0)
        assert cycles() == 105
        runner.inst.fmi3EnterEventMode()
        runner.inst.fmi3UpdateDiscreteStates()
        assert cycles() == 106
        runner.inst.fmi3EnterStepMode()
        runner.inst.fmi3DoStep(105.0, 10.0)  # 105 counted, 106 to 114 passed, 115 left to an Event Mode
        assert cycles() == 115
    finally:
        runner.close()


def _pair(work: Path, paths: list[Path], semantics: str, functions: Path | None = None, **options):
    return {t: build(paths, work / t, functions=functions, options=LoweringOptions(semantics=semantics, time=t, **options))
            for t in ("tick", "skip")}


def _same_traces(pair, rng: random.Random, units: int = 40, runs: int = 3, choices=None) -> None:
    for _ in range(runs):
        events = timed_events(rng, pair["skip"].desc, units, rate=0.04, choices=choices)
        ticking = run_in_time(pair["tick"].folder, events, units)
        skipping = run_in_time(pair["skip"].folder, events, units)
        assert first_time_difference(ticking, skipping) is None, (events, first_time_difference(ticking, skipping))
        assert skipping.instants <= ticking.instants


ROBOCHART = sorted(n for n, m in TEST_MODELS.items() if m.path.suffix == ".rct")
STEPWISE = ["timers", "control", "senders", "ur5e_rct"]


@pytest.mark.slow
@pytest.mark.parametrize("name,semantics", [(n, "exhaustive") for n in ROBOCHART] + [(n, "stepwise") for n in STEPWISE])
def test_ticking_and_skipping_agree_on_the_repository_models(name, semantics, tmp_path):
    m = TEST_MODELS[name]
    pair = _pair(tmp_path, [m.path], semantics, settings=dict(m.settings), capacity=m.capacity,
                 capacities=m.capacities, max_steps=m.max_steps)
    _same_traces(pair, random.Random(name), choices=m.choices)


@pytest.mark.slow
@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_ticking_and_skipping_agree_on_the_sprinkler(semantics, tmp_path):
    _same_traces(_pair(tmp_path, [ROOT / "examples" / "scenarios" / "sprinkler.rct"], semantics), random.Random(7))


POLLING = """
interface Outs { event done: nat }
interface Ins { event kick }
stm Busy {
	uses Outs uses Ins
	var n: nat = 0
	clock C
	initial i
	state Counting { during n = n + 1 ; send done!n }
	state Waiting { entry wait([1, 3]) ; wait(2) ; send done!0 }
	state Polling { }
	transition t0 { from i to Waiting }
	transition t1 { from Waiting to Counting trigger kick }
	transition t2 { from Counting to Polling condition sinceEntry(Counting) >= 4 action #C }
	transition t3 { from Polling to Counting condition since(C) % 3 == 1 /\\ n > 2 }
	transition t4 { from Polling to Waiting trigger kick }
}
"""


def test_ticking_and_skipping_agree_where_time_is_read_otherwise(tmp_path):
    """A resume point that tests since(C) % 3 (not monotone) runs at every tock in both; the
    others are skipped: same trace, fewer instants."""
    model = tmp_path / "busy.rct"
    model.write_text(POLLING, encoding="utf-8")
    pair = _pair(tmp_path, [model], "exhaustive")
    events = [Timed(3, (Tick("kick", {}),)), Timed(40, (Tick("kick", {}),)), Timed(51, (Tick("kick", {}),))]
    ticking, skipping = run_in_time(pair["tick"].folder, events, 40), run_in_time(pair["skip"].folder, events, 40)
    assert first_time_difference(ticking, skipping) is None
    assert any(r[0] == "step" and r[3] for r in skipping.records if r[1] > 20)  # Polling -> Counting again
    assert skipping.instants < ticking.instants


FUZZED = [i for i in range(40) if generate(model_seed(22, i), DEFAULT).language == "robochart"][:12]


@pytest.mark.slow
@pytest.mark.parametrize("index", FUZZED)
def test_ticking_and_skipping_agree_on_fuzzed_models(index, tmp_path):
    """Models of the fuzzer (robogen.fuzz, seed 22): what it generates that compiles, in the
    semantics chosen by the model's number."""
    g = generate(model_seed(22, index), DEFAULT)
    path = tmp_path / Path(g.path).name
    path.write_text(g.text(), encoding="utf-8")
    functions = None
    if g.c_functions is not None:
        functions = tmp_path / "functions.c"
        functions.write_text(g.c_functions, encoding="utf-8")
    try:
        pair = _pair(tmp_path, [path], ("exhaustive", "stepwise")[index % 2], functions, capacity=g.capacity)
    except RobogenError as exc:  # a construct code generation refuses (the fuzzer's table counts them); anything else fails
        if "is not supported for code generation" not in str(exc):
            raise
        pytest.skip(f"not supported: {exc}")
    _same_traces(pair, random.Random(index), units=30, runs=2)


SCENARIO = """
model = "timers.rct"
stop = 40.0
step = 40.0
events = [
  { at = 1.5, event = "press" },
  { at = 5.5, event = "set", value = 3 },
  { at = 12.0, event = "press" },
  { at = 19.5, event = "press" },
  { at = 27.0, event = "cancel" },
]
[[expect]]          # by hand: armed at 1.5 (since(D) = 1), C reset there (2 tocks counted), since(C) >= 2 at tock 3
event = "ring"
within = [3.0, 3.0]
value = 1
"""


def test_the_reference_interpreter_announces_the_same_next_event_times(tmp_path, monkeypatch, capsys):
    """robogen test --compare runs the scenario on the time-free FMU and on the reference
    interpreter (robogen.scenarios.reference, which counts tocks and looks ahead in Python) under
    the master, whose communication step is the whole run: every row is an event iteration at an
    input event or an announced next event time, so different announcements give different rows."""
    from robogen.cli import main

    monkeypatch.setenv("ROBOGEN_CACHE", str(tmp_path / "cache"))
    (tmp_path / "timers.rct").write_text(TEST_MODELS["timers"].path.read_text(encoding="utf-8"), encoding="utf-8")
    scenario = tmp_path / "alarm.toml"
    scenario.write_text(SCENARIO, encoding="utf-8")
    assert main(["test", str(scenario), "--compare"]) == 0
    assert f"{scenario}:1:1: PASS  the FMU and the reference interpreter give the same results" in capsys.readouterr().out
    out = tmp_path / "alarm.csv"
    assert main(["simulate", str(scenario), "-o", str(out), "--no-progress"]) == 0
    times = sorted({float(line.split(",")[0]) for line in out.read_text().splitlines()[1:]})
    assert len(times) < 25 and 40.0 in times  # not one row per time unit: idle time was skipped


# Two machines sharing a variable: Setter stores the value of 'go' in 'armed'; Watcher, declared
# after it, leaves Waiting at the first tock at which 'armed' holds.
SHARED = """
package share
interface Flag { var armed: boolean }
robotic platform P { event go: boolean }
stm Setter {
	event go: boolean
	requires Flag
	initial i
	state Idle { }
	state Done { }
	transition t0 { from i to Idle }
	transition t1 { from Idle to Done trigger go?armed }
}
stm Watcher {
	requires Flag
	initial i
	state Waiting { }
	state Seen { }
	transition t0 { from i to Waiting }
	transition t1 { from Waiting to Seen condition armed }
}
module Mod {
	rref p = P
	controller Ctl {
		event go: boolean
		sref s = Setter
		sref w = Watcher
		connection Ctl on go to s on go
	}
	connection p on go to Ctl on go ( _async )
}
"""


def test_an_event_at_a_tock_is_taken_with_that_tock(tmp_path):
    """By hand: 'go' (true) comes at t=3, a tock's time. The ticking FMU runs both machines at
    that tock: Setter takes t1 and stores true in 'armed', then Watcher, at the same tock, sees
    'armed' and takes t1, at t=3. Watcher was idle (its test false, no time in it), so the step
    to 3 must not pass the tock at 3 as idle: it belongs to the Event Mode the event opens there
    (it did, and Watcher moved at the next tock, t=4: found by make fuzz SEED=1, models 1.523 and
    1.692, regressions differential_difference_1_523 and 1_692)."""
    model = tmp_path / "share.rct"
    model.write_text(SHARED, encoding="utf-8")
    pair = _pair(tmp_path, [model], "exhaustive")
    events = [Timed(6, (Tick("go", {"go.value": True}),))]
    traces = {t: run_in_time(pair[t].folder, events, 10) for t in ("tick", "skip")}
    assert first_time_difference(traces["tick"], traces["skip"]) is None
    for trace in traces.values():
        moves = [(r[1] / 2, r[3].split(": ", 1)[1]) for r in trace.records if r[0] == "transition"]
        assert moves == [(0.0, "Setter: t0: i -> Idle"), (0.0, "Watcher: t0: i -> Waiting"),
                         (3.0, "Setter: t1: Idle -> Done"), (3.0, "Watcher: t1: Waiting -> Seen")]
