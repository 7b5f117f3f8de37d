"""Hand-written expected behaviour of lowered machines, checked on the FMU and the interpreter.

The differential tests prove that the C does what the IR says; these prove that the IR says what
the RoboChart and RoboSim semantics and robogen's FMI mapping (README) say, with traces worked out by hand from the models.
Scenarios tick the periodic clock at every instant (one period apart).
"""

from __future__ import annotations

import re

import pytest

from support.codegen_driver import FmuRunner, Instant, Scenario, Tick, interpret, run_checked


def scenario(*instants: Instant) -> Scenario:
    return Scenario(instants, half=False)


def at(*ticks: Tick) -> Instant:
    return Instant(True, tuple(ticks))


def tick(clock: str, **payload) -> Tick:
    return Tick(clock, {f"{clock}.{k}" if k != "value" else f"{clock}.value": v for k, v in payload.items()})


def run_both(b, s: Scenario):
    """The FMU's trace, after checking that the interpreter's is the same."""
    return run_checked(b, s)


def last_steps(trace) -> dict[int, object]:
    """The last super-dense step of each instant (the end of each cycle)."""
    return {s.instant: s for s in trace.steps}


def state_names(b, step) -> list[str]:
    return [b.fmu.machines[i].nodes[v].label for i, v in enumerate(step.states.values())]


def test_junction_default_branch_is_tried_last_and_integer_division_truncates(built):
    """data.rst: 'condition else' (t5) is declared first at the junction Dispatch, yet the
    guarded branch t2 wins; -7 / 2 = -3 and -7 % 2 = -1 (C99), 1.0 / 2.0 = 0.5."""
    b = built("data", "exhaustive")
    sample = tick("sample", **{"at.px": -7, "at.py": 0, "gain": 1.0, "mode": 0})
    trace = run_both(b, scenario(at(), at(tick("divisor", value=2), sample), at()))
    steps = last_steps(trace)
    assert steps[0].outputs == {}
    assert steps[1].outputs == {"quotient": {"quotient.value": -3}, "remainder": {"remainder.value": -1},
                                "ratio": {"ratio.value": 0.5}}
    assert steps[2].outputs == {}
    assert state_names(b, steps[1]) == ["Wait"]


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_machines_see_what_others_sent_in_the_next_cycle_whatever_their_order(built, semantics):
    """pipeline.rst (machines declared Consumer, Producer, Sink): item 5 in cycle 2; Producer
    decides t1 (exec) in cycle 2 and sends part 10 in cycle 3; Consumer samples it in cycle 4
    (decides), acts in cycle 5 (ack 1 to Producer, forward 10 to Sink); both sample them in cycle
    6 and emit acked 1 and outcome 10 in cycle 7 (instant 6). Sink comes after Consumer in the
    declaration order, yet it does not see 'forward' in the cycle it was sent."""
    b = built("pipeline", semantics)
    trace = run_both(b, scenario(at(), at(tick("item", value=5)), *[at() for _ in range(6)]))
    outputs = {}
    for s in trace.steps:
        for clock, values in s.outputs.items():
            outputs[(s.instant, clock)] = values
    assert outputs == {(6, "acked"): {"acked.value": 1}, (6, "outcome"): {"outcome.value": 10}}
    steps = last_steps(trace)
    assert steps[4].variables["Consumer.sum"] == 10 and steps[3].variables["Consumer.sum"] == 0
    assert steps[6].variables["Sink.last"] == 10


def test_operation_calls_run_inline_and_return_to_the_callers_state(built):
    """ops.rst: start 2 enters Busy, whose entry calls settle(2) (waits a cycle inside it: the
    state output names the operation's node), then scale(2, 3) (acc = 6); back from the calls
    the state output is Busy again. Each call site has its own variables (settle(1) in Again)."""
    b = built("ops", "exhaustive")
    trace = run_both(b, scenario(at(), at(tick("start", value=2)), at(), at(), at()))
    steps = last_steps(trace)
    assert [state_names(b, steps[i]) for i in range(5)] == [["Idle"], ["settle#1.Loop"], ["Busy"], ["Again"], ["Idle"]]
    assert steps[1].outputs == {"tick": {"tick.value": 1}}
    assert steps[2].outputs == {"tick": {"tick.value": 2}, "report": {"report.value": 6}}
    assert steps[3].outputs == {"tick": {"tick.value": 1}}
    assert steps[2].variables["Worker.acc"] == 6 and steps[4].variables["Worker.calls"] == 1


def test_robochart_buffer_keeps_an_event_until_a_transition_takes_it(built):
    """timers.rct: press at t=0 finds Off with since(D) = 0 < 1, so t1 is not enabled; the press
    stays in the buffer (docs §7.7) and t1 takes it at the next tock (armed 2). Two tocks later
    since(C) = delay = 2: Ringing (ring 1, then wait(1): tick one tock later)."""
    b = built("timers", "exhaustive")
    trace = run_both(b, scenario(at(tick("press")), at(), at(), at(), at()))
    steps = last_steps(trace)
    assert [s.outputs for s in trace.steps] == [{}, {"armed": {"armed.value": 2}}, {}, {"ring": {"ring.value": 1}},
                                                {"tick": {}}]
    assert [state_names(b, steps[i]) for i in range(5)] == [["Off"], ["Armed"], ["Armed"], ["Ringing"], ["Ringing"]]
    assert all(s.dropped == 0 for s in trace.steps)


def test_robochart_deadlines_are_counted_not_enforced(built):
    """timers.rct with delay set to 5: Armed (entered at t=1) waits for 'cancel' at most 3 units
    (t4 <{ 3 }): missed at t=5, when it has been active 4 units; Ringing comes at t=6 anyway.
    Press at t=8 leads (after wait(1)) to Snooze at t=9, whose wait(5) <{ 2 } ends, late, at
    t=14 (a miss); since(C) = 5 then, so t8 rings again at once (ring 2)."""
    b = built("timers", "exhaustive")
    instants = [at(tick("set", value=5)), at(tick("press"))] + [at() for _ in range(6)] + [at(tick("press"))] + \
        [at() for _ in range(6)]
    trace = run_both(b, scenario(*instants))
    steps = last_steps(trace)
    assert [steps[i].misses for i in range(15)] == [0] * 5 + [1] * 9 + [2]
    assert steps[1].outputs == {"armed": {"armed.value": 5}}
    assert steps[6].outputs == {"ring": {"ring.value": 1}}
    assert [state_names(b, steps[i]) for i in (8, 9, 13, 14)] == [["Ringing"], ["Snooze"], ["Snooze"], ["Ringing"]]
    assert steps[14].outputs == {"ring": {"ring.value": 2}}


def test_an_input_trigger_binds_its_variable_only_when_its_transition_is_taken(built):
    """binding.rct: button 7 and level 4 arrive at t=0 and wait in the buffer. t1 (button?last,
    since(C) >= 3) is taken at t=3: 'last' stays 0 until then, becomes 7, shown!7 is sent. t2's
    condition reads level before the communication (0), so t2 is never taken and level stays 0."""
    b = built("binding", "exhaustive")
    trace = run_both(b, scenario(at(tick("button", value=7), tick("level", value=4)), at(), at(), at(), at()))
    steps = last_steps(trace)
    assert [steps[i].variables["Latch.last"] for i in range(5)] == [0, 0, 0, 7, 7]
    assert [steps[i].variables["Latch.taken"] for i in range(5)] == [0, 0, 0, 1, 1]
    assert [steps[i].variables["Latch.level"] for i in range(5)] == [0] * 5
    assert steps[3].outputs == {"shown": {"shown.value": 7}}
    assert all(steps[i].outputs == {} for i in (0, 1, 2, 4))


def test_stepwise_runaway_bound_counts_the_whole_cycle(built):
    """arith.rst (max_steps 40): n = 7 sends Idle to Spin, which loops without exec. Stepwise
    takes one transition per instant, so the bound must count across the instants of the cycle:
    the error comes in the same time instant, after about 40 super-dense steps."""
    b = built("arith", "stepwise")
    trace = run_both(b, scenario(at(), at(tick("n", value=7)), at()))
    assert trace.error is not None and trace.error.instant == 1
    assert 38 <= trace.error.k <= 43
    assert "runaway" in trace.error.where


def test_a_controller_variable_is_one_variable_for_its_machines_and_operations(built):
    """relay.rct: Relay provides 'served'; Front requires it and resets it, the operation process
    (called by Back, which does not name it) counts answers in it: one variable. Request 2 at
    t=0: Front sends job 2; Back (after Front in the same instant) runs process(2, 2): answer 4,
    served 1; pause(1) waits since(W) >= 2 then wait(1): at t=3 process(20, 1) answers 20
    (served 2) and Back sends done 3, which Front takes one super-dense step later."""
    b = built("relay", "exhaustive")
    trace = run_both(b, scenario(at(tick("request", value=2)), at(), at(), at()))
    by_step = {(s.instant, s.k): s for s in trace.steps}
    assert by_step[0, 0].outputs == {"answer": {"answer.value": 4}, "busy": {}}
    assert by_step[0, 0].variables["Front.served"] == 1
    assert state_names(b, by_step[0, 0]) == ["Waiting", "pause#2.Waiting"]
    assert by_step[3, 0].outputs == {"answer": {"answer.value": 20}}
    assert by_step[3, 0].variables["Front.served"] == 2
    assert state_names(b, by_step[3, 0]) == ["Waiting", "Idle"] and by_step[3, 0].need
    assert state_names(b, by_step[3, 1]) == ["Ready", "Idle"] and by_step[3, 1].variables["Front.back"] == 3
    assert "Back.served" not in by_step[0, 0].variables


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_robochart_inputs_inside_actions_wait_for_their_event(built, semantics):
    """inputs.rct: confirm at t=0 finds Parked, which does not take it: it stays buffered. go
    (East, 5) at t=1 enters Driving, whose sub-state Confirming's entry 'confirm?ok' takes the
    buffered confirm at once and goes on (log digits 1 Parked, 2 Driving, 4 and 5 Confirming),
    through the junction to Moving: heading East, total 5, during (6). abort at t=3 leaves the
    composite state: exits inner first (7, then 3), report (East, 5), Parked (1). amount 3 at
    t=4 starts t3, whose action waits for a second amount: 4 at t=5, moved 7."""
    b = built("inputs", semantics)
    go = tick("go", dir=1, steps=5)
    trace = run_both(b, scenario(at(tick("confirm", value=True)), at(go), at(), at(tick("abort")),
                                 at(tick("amount", value=3)), at(tick("amount", value=4))))
    steps = last_steps(trace)
    outputs = {s.instant: s.outputs for s in trace.steps if s.outputs}
    assert outputs == {1: {"heading": {"heading.value": 1}}, 3: {"report": {"report.dir": 1, "report.steps": 5}},
                       5: {"moved": {"moved.value": 7}}}
    assert [state_names(b, steps[i])[0] for i in range(6)] == ["Parked", "Driving.Moving", "Driving.Moving", "Parked",
                                                              "Parked", "Parked"]
    assert [steps[i].variables["Rover.log"] for i in (0, 1, 3, 5)] == [1, 12456, 12456731, 124567311]
    assert steps[5].variables["Rover.total"] == 7 and steps[1].variables["Rover.ok"] is True


def test_parameters_set_in_initialization_mode_reach_the_machine(built):
    """arith.rst: the constant k (3 in the model) is a fixed FMU parameter; set to 5 before
    fmi3ExitInitializationMode, it also decides the initial value of base = k * 10 - 1 = 49.
    beacon.rst's step has no value in the model: the generation setting gives it (0.25)."""
    b = built("arith", "exhaustive")
    runner = FmuRunner(b.folder)
    try:
        s = scenario(at(), at(tick("a", value=2)), at())
        default = runner.run(s)
        five = runner.run(s, parameters={"Alu.k": 5})
        assert five.comparable() == interpret(b.fmu, s, runner.desc, parameters={"Alu.k": 5}).comparable()
    finally:
        runner.close()
    # s = a + b * k - -a + base with a = 7, b = -2 at t=0
    assert default.steps[0].outputs["sum"] == {"sum.value": 7 - 6 + 7 + 29}
    assert five.steps[0].outputs["sum"] == {"sum.value": 7 - 10 + 7 + 49}
    assert five.steps[0].variables["Alu.k"] == 5 and five.steps[0].variables["Alu.base"] == 49
    assert re.search(r'name="Beacon.step"[^>]*causality="parameter" variability="fixed" start="0.25"',
                     built("beacon", "exhaustive").sources["modelDescription.xml"])
