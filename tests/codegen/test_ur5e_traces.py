"""The UR5e d-model (models/ur5e/ur5e.rst) against traces written by hand from the model and
RoboSim's cycle semantics and robogen's FMI mapping (README: How a model becomes an FMU).

The story: the cycle clock ticks every second; the platform sends moveDiscreteCommand(0, 23, 1)
at t=1, the feasibility verdict at t=2, moveCompleted at t=4 and robotStopped at t=5. The
machine calls movediscrete with the command's arguments (again each cycle it waits in ArmMove,
whose exec self-loop re-enters it), moves, calls stop when the move completes, and is back in
Idle when the robot has stopped.

Each expected instant is a list of its super-dense steps, each (state, outputs): exhaustive
semantics shows one step per instant (the whole cycle); stepwise one step per transition, the
last one deciding exec.
"""

from __future__ import annotations

import pytest

from support.codegen_driver import FmuRunner, Instant, Scenario, Tick, interpret

MOVE = {"movediscrete": {"movediscrete.target_X": 0, "movediscrete.target_Y": 23, "movediscrete.target_Z": 1}}
STOP = {"stop": {}}
COMMAND = Tick("moveDiscreteCommand", {"moveDiscreteCommand.target_X": 0, "moveDiscreteCommand.target_Y": 23,
                                       "moveDiscreteCommand.target_Z": 1})
FEASIBLE = Tick("feasibleMoveDiscreteCommand", {})
COMPLETED = Tick("moveCompleted", {})
STOPPED = Tick("robotStopped", {})

# inputs by second, t = 0..6
INPUTS = {1: COMMAND, 2: FEASIBLE, 4: COMPLETED, 5: STOPPED}

EXHAUSTIVE = [
    [("Idle", {})],            # t=0: i1 -> Idle; t1_1 (exec) decided
    [("ArmMove", MOVE)],       # t=1: t1_1 completes, t2 binds the command: movediscrete; t0 decided
    [("ArmMoving", MOVE)],     # t=2: t0 completes (ArmMove re-entered: movediscrete again), t2_1
    [("ArmMoving", {})],       # t=3: t2_2 completes to J2, nothing new: t2_3 back to ArmMoving
    [("ArmStopping", STOP)],   # t=4: J2 sees moveCompleted: ArmStop (stop), t3 to ArmStopping
    [("Idle", {})],            # t=5: J3 sees robotStopped: t3_3 to Idle
    [("Idle", {})],            # t=6: waiting in Idle
]

STEPWISE = [
    [("Idle", {})],
    [("Idle", {}), ("ArmMove", MOVE)],
    [("ArmMove", MOVE), ("ArmMoving", {})],
    [("J2", {}), ("ArmMoving", {})],
    [("J2", {}), ("ArmStop", STOP), ("ArmStopping", {})],
    [("J3", {}), ("Idle", {})],
    [("Idle", {})],
]


def observed(built_fmu, scenario: Scenario):
    runner = FmuRunner(built_fmu.folder)
    try:
        trace = runner.run(scenario)
    finally:
        runner.close()
    assert trace.error is None, trace.error
    assert trace.comparable() == interpret(built_fmu.fmu, scenario, runner.desc).comparable()
    nodes = built_fmu.fmu.machines[0].nodes
    out: dict[int, list] = {}
    for s in trace.steps:
        (state,) = s.states.values()
        out.setdefault(s.instant, []).append((nodes[state].label, s.outputs))
    return out, trace


@pytest.mark.parametrize("trigger", ["cycle", "on-input"])
@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_move_stop_and_back_to_idle(builds, semantics, trigger):
    """Inputs arrive with the cycle ticks: both triggers give the same trace (an input latched
    in the instant of a tick is sampled by that tick's cycle, docs §7.3)."""
    b = builds.get("ur5e", semantics, trigger)
    scenario = Scenario([Instant(True, (INPUTS[t],) if t in INPUTS else ()) for t in range(7)], half=False)
    steps, trace = observed(b, scenario)
    expected = EXHAUSTIVE if semantics == "exhaustive" else STEPWISE
    assert [steps[t] for t in range(7)] == expected
    # discreteStatesNeedUpdate: true exactly while another transition of the cycle follows
    assert all(s.need == (s.k < len(expected[s.instant]) - 1) for s in trace.steps)
    assert trace.steps[-1].cycles == 7
    # the command's value is bound to margs by t2's guard, evaluated (stepwise: in the step
    # before t2 is taken) at t=1
    assert [s.variables["SimDiscreteGrippingArmMovement.margs.target_Y"] for s in trace.steps if s.k == 0] == \
        [0, 23, 23, 23, 23, 23, 23]


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_inputs_between_ticks(builds, semantics):
    """The same inputs half a second early (t = 0.5, 1.5, 3.5, 4.5). With trigger 'cycle' they are
    latched and sampled by the next tick: the trace at the ticks is the one above. With
    'on-input' each input starts a cycle at once: the command is answered at t=0.5; at t=1 the
    machine, waiting in ArmMove, re-enters it (movediscrete) and at t=1.5 the verdict moves it."""
    early = {1: COMMAND, 3: FEASIBLE, 7: COMPLETED, 9: STOPPED}  # half-second instants
    scenario = Scenario([Instant(i % 2 == 0, (early[i],) if i in early else ()) for i in range(14)], half=True)

    steps, _ = observed(builds.get("ur5e", semantics, "cycle"), scenario)
    expected = EXHAUSTIVE if semantics == "exhaustive" else STEPWISE
    assert [steps[2 * t] for t in range(7)] == expected  # at the ticks
    assert all(all(out == {} for _, out in steps[2 * t + 1]) for t in range(6))  # nothing between them

    steps, _ = observed(builds.get("ur5e", semantics, "on-input"), scenario)
    last = {i: steps[i][-1] for i in steps}
    assert last[1] == ("ArmMove", MOVE)            # t=0.5: the command starts a cycle at once
    assert last[2] == ("ArmMove", MOVE)            # t=1: no verdict: t0 re-enters ArmMove
    assert last[3][0] == "ArmMoving"               # t=1.5: feasible
    assert last[7] == ("ArmStopping", {}) if semantics == "stepwise" else last[7] == ("ArmStopping", STOP)
    assert last[9][0] == "Idle"                    # t=4.5: robotStopped
    assert any(STOP == out for _, out in steps[7])
