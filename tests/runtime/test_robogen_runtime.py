"""Behaviour of the runtime (robogen_runtime.c) through fmpy's FMU3Slave.

The test model "counter" (models/counter/model.c) is a RoboSim d-model in miniature:
- the constant input clock `cycle` (interval 0.1 s, shift 0) runs one cycle per tick:
  count += 1, flag = count is odd;
- the triggered input clock `command` latches `command.value` into an input register; the next
  cycle consumes it: last_command = value, tick.value = value * gains[1] + offset + level, and the
  output clock `tick` ticks;
- `evaluations` / `latches` count the calls of rg_model_evaluate / rg_model_latch;
- update: terminateSimulation = count > limit; nextEventTime = early_at while early_at > t;
- DoStep: if early_at lies inside the step, `tick` ticks with tick.value = early_at, the step
  reports eventHandlingNeeded and returns early at early_at when allowed.
Start values: gains = [1, 2, 3], offset = 0.5, level = 0, early_at = -1, limit = 1000.
"""

from __future__ import annotations

import ctypes

import pytest
from fmpy import simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi3 import fmi3Float64, fmi3IntervalQualifier, fmi3IntervalUnchanged, fmi3ValueReference

ERROR = 3


@pytest.fixture
def v(counter_fmu):
    """Value references of the counter model, by name (from its modelDescription.xml)."""
    return counter_fmu.vr


def first_tick(slave, v, start_time=0.0, stop_time=None):
    """Initialize, then run the instant (t_start, 0) with the first tick of `cycle`."""
    slave.enterInitializationMode(startTime=start_time, stopTime=stop_time)
    slave.exitInitializationMode()
    slave.setClock([v("cycle")], [True])
    return slave.updateDiscreteStates()


def step_to_next_tick(slave, v, t, h=0.1, clocks=("cycle",)):
    """From Step Mode at t: step h, then run one Event Mode instant with `clocks` active."""
    assert slave.doStep(t, h) == (False, False, False, t + h)
    slave.enterEventMode()
    slave.setClock([v(name) for name in clocks], [True] * len(clocks))
    return slave.updateDiscreteStates()


def in_step_mode_with_early_at(slave, v, early_at):
    """Initialize with an internal event at early_at, run the first tick, enter Step Mode at 0."""
    slave.enterInitializationMode(startTime=0.0)
    slave.setFloat64([v("early_at")], [early_at])
    slave.exitInitializationMode()
    slave.setClock([v("cycle")], [True])
    slave.updateDiscreteStates()
    slave.enterStepMode()


def failing(call, *args):
    """Run a call that must fail with fmi3Error."""
    with pytest.raises(FMICallException) as caught:
        call(*args)
    assert caught.value.status == ERROR


# --------------------------------------------------------------------------------------------
# Initialization, first tick, lazy evaluation


def test_initialization_mode_reads_clocked_variables_and_inactive_clocks(counter_fmu, open_slave, v):
    slave, _ = open_slave(counter_fmu)
    slave.enterInitializationMode(startTime=0.0)
    assert slave.getClock([v("tick"), v("cycle"), v("command")]) == [False, False, False]
    assert slave.getFloat64([v("tick.value")]) == [0.0]  # clocked: readable in Initialization Mode
    slave.setInt64([v("command.value")], [9])  # clocked input: settable in Initialization Mode
    assert slave.getInt64([v("command.value")]) == [9]
    assert slave.getFloat64([v("gains")], nValues=3) == [1.0, 2.0, 3.0]


def test_exit_initialization_enters_event_mode_where_the_first_tick_runs_once(counter_fmu, open_slave, v):
    slave, _ = open_slave(counter_fmu)
    slave.enterInitializationMode(startTime=0.0)
    slave.exitInitializationMode()  # Event Mode at (0, 0), shift 0: cycle is due now
    slave.setClock([v("cycle")], [True])
    assert slave.getUInt64([v("count"), v("evaluations")]) == [1, 1]  # the first Get evaluates
    assert slave.getUInt64([v("count"), v("evaluations")]) == [1, 1]  # ... once per instant
    assert slave.getBoolean([v("flag")]) == [True]  # count 1 is odd
    assert slave.updateDiscreteStates() == (False, False, False, False, False, 0.0)
    slave.enterStepMode()
    assert slave.getUInt64([v("count")]) == [1]
    assert slave.doStep(0.0, 0.1) == (False, False, False, 0.1)


def test_update_evaluates_when_no_get_came(counter_fmu, open_slave, v):
    slave, _ = open_slave(counter_fmu)
    slave.enterInitializationMode(startTime=0.0)
    slave.exitInitializationMode()
    slave.setClock([v("cycle")], [True])
    slave.updateDiscreteStates()  # evaluation happens here
    # This Get opens instant (0, 1): no clock active, so the model's evaluation changes nothing.
    assert slave.getUInt64([v("count"), v("evaluations")]) == [1, 2]


def test_start_time_shifts_the_tick_grid(counter_fmu, open_slave, v):
    slave, log = open_slave(counter_fmu)
    first_tick(slave, v, start_time=0.25)  # tick k=0 at 0.25
    slave.enterStepMode()
    step_to_next_tick(slave, v, 0.25)  # tick k=1 at 0.35
    slave.enterStepMode()
    assert slave.getUInt64([v("count")]) == [2]
    slave.doStep(0.35, 0.05)
    slave.enterEventMode()
    failing(slave.setClock, [v("cycle")], [True])  # 0.4 is not on the grid 0.25 + k * 0.1
    assert "next tick (k=2) is at t=0.45" in log.texts()[-1]


def test_ticks_follow_the_integer_grid_despite_accumulated_time(counter_fmu, open_slave, v):
    slave, _ = open_slave(counter_fmu)
    first_tick(slave, v)
    slave.enterStepMode()
    t = 0.0
    for _ in range(10):  # the master's running sum drifts: 0.1 * 10 summed is 0.9999999999999999
        step_to_next_tick(slave, v, t)
        slave.enterStepMode()
        t += 0.1
    assert t != 1.0
    assert slave.getUInt64([v("count")]) == [11]


def test_intervals_and_shifts_of_the_constant_clock(counter_fmu, open_slave, v):
    slave, _ = open_slave(counter_fmu)
    vrs = (fmi3ValueReference * 1)(v("cycle"))
    intervals = (fmi3Float64 * 1)()
    shifts = (fmi3Float64 * 1)()
    qualifiers = (fmi3IntervalQualifier * 1)()
    slave.enterInitializationMode(startTime=0.0)
    slave.getIntervalDecimal(vrs, intervals, qualifiers)
    slave.getShiftDecimal(vrs, shifts)
    assert (intervals[0], qualifiers[0], shifts[0]) == (0.1, fmi3IntervalUnchanged, 0.0)
    slave.exitInitializationMode()
    intervals[0] = 0.0
    slave.getIntervalDecimal(vrs, intervals, qualifiers)  # also allowed in Event Mode
    assert (intervals[0], qualifiers[0]) == (0.1, fmi3IntervalUnchanged)


# --------------------------------------------------------------------------------------------
# Input clocks, latching, output clocks


def test_command_is_latched_and_consumed_by_the_next_cycle(counter_fmu, open_slave, v):
    slave, _ = open_slave(counter_fmu)
    first_tick(slave, v)
    # instant (0, 1): only the command; the cycle that consumes it comes at t = 0.1
    slave.setClock([v("command")], [True])
    slave.setInt64([v("command.value")], [5])
    assert slave.getClock([v("command"), v("cycle"), v("tick")]) == [True, False, False]
    assert slave.getUInt64([v("latches")]) == [2]  # cycle at (0, 0), command now
    assert slave.updateDiscreteStates()[0] is False
    slave.enterStepMode()
    slave.doStep(0.0, 0.1)
    slave.enterEventMode()
    slave.setClock([v("cycle")], [True])
    assert slave.getClock([v("tick")]) == [True]
    assert slave.getFloat64([v("tick.value")]) == [5 * 2.0 + 0.5 + 0.0]
    assert slave.getInt64([v("last_command")]) == [5]
    assert slave.getClock([v("tick")]) == [True]  # repeatable within the instant
    slave.updateDiscreteStates()
    assert slave.getClock([v("tick")]) == [False]  # inactive once the instant is closed
    failing(slave.getFloat64, [v("tick.value")])


def test_output_clock_is_inactive_in_the_next_event_mode(counter_fmu, open_slave, v):
    slave, _ = open_slave(counter_fmu)
    slave.enterInitializationMode(startTime=0.0)
    slave.exitInitializationMode()
    slave.setClock([v("cycle"), v("command")], [True, True])
    slave.setInt64([v("command.value")], [1])
    assert slave.getClock([v("tick")]) == [True]  # latched first, then the cycle consumed it
    slave.updateDiscreteStates()
    slave.enterStepMode()
    step_to_next_tick(slave, v, 0.0)  # a cycle without a command
    slave.enterStepMode()
    slave.doStep(0.1, 0.05)
    slave.enterEventMode()
    assert slave.getClock([v("tick")]) == [False]


def test_an_activation_after_the_evaluation_reaches_the_next_cycle(counter_fmu, open_slave, v):
    slave, _ = open_slave(counter_fmu)
    slave.enterInitializationMode(startTime=0.0)
    slave.exitInitializationMode()
    slave.setClock([v("cycle")], [True])
    assert slave.getUInt64([v("count")]) == [1]  # evaluated without a command
    slave.setClock([v("command")], [True])  # e.g. forwarded from another FMU's output clock
    slave.setInt64([v("command.value")], [7])
    assert slave.getClock([v("tick")]) == [False]  # not re-evaluated
    slave.updateDiscreteStates()  # the command is latched here, for the next cycle
    slave.enterStepMode()
    slave.doStep(0.0, 0.1)
    slave.enterEventMode()
    slave.setClock([v("cycle")], [True])
    assert slave.getClock([v("tick")]) == [True]
    assert slave.getFloat64([v("tick.value")]) == [7 * 2.0 + 0.5]
    assert slave.getInt64([v("last_command")]) == [7]


def test_input_clocks_read_back_their_activation(counter_fmu, open_slave, v):
    slave, _ = open_slave(counter_fmu)
    slave.enterInitializationMode(startTime=0.0)
    slave.exitInitializationMode()
    slave.setClock([v("command")], [True])
    slave.setClock([v("cycle")], [True])
    slave.setClock([v("command")], [True])  # setting an active clock again is harmless
    assert slave.getClock([v("command"), v("cycle")]) == [True, True]
    slave.updateDiscreteStates()
    slave.setClock([v("command")], [True])  # triggered: again in the next instant
    assert slave.getClock([v("command"), v("cycle")]) == [True, False]


# --------------------------------------------------------------------------------------------
# Update outputs: terminateSimulation, nextEventTime


def test_update_reports_terminate_and_next_event_time(counter_fmu, open_slave, v):
    slave, _ = open_slave(counter_fmu)
    slave.enterInitializationMode(startTime=0.0)
    slave.setInt32([v("limit")], [1])
    slave.setFloat64([v("early_at")], [0.35])
    slave.exitInitializationMode()
    slave.setClock([v("cycle")], [True])
    assert slave.updateDiscreteStates() == (False, False, False, False, True, 0.35)  # count 1 <= limit 1
    slave.enterStepMode()
    assert step_to_next_tick(slave, v, 0.0) == (False, True, False, False, True, 0.35)  # count 2 > 1


# --------------------------------------------------------------------------------------------
# DoStep: early return, event handling


def test_early_return_at_an_internal_event_and_continue_from_there(counter_fmu, open_slave, v):
    slave, _ = open_slave(counter_fmu, early_return_allowed=True)
    in_step_mode_with_early_at(slave, v, 0.05)
    assert slave.doStep(0.0, 0.1) == (True, False, True, 0.05)
    slave.enterEventMode()
    assert slave.getClock([v("tick")]) == [True]  # raised inside the step
    assert slave.getFloat64([v("tick.value")]) == [0.05]
    slave.updateDiscreteStates()
    slave.enterStepMode()
    assert slave.doStep(0.05, 0.05) == (False, False, False, 0.1)  # continues at lastSuccessfulTime


def test_no_early_return_unless_allowed(counter_fmu, open_slave, v):
    slave, _ = open_slave(counter_fmu, early_return_allowed=False)
    in_step_mode_with_early_at(slave, v, 0.05)
    assert slave.doStep(0.0, 0.1) == (True, False, False, 0.1)


def test_a_step_after_an_early_return_must_start_at_last_successful_time(counter_fmu, open_slave, v):
    slave, log = open_slave(counter_fmu, early_return_allowed=True)
    in_step_mode_with_early_at(slave, v, 0.05)
    slave.doStep(0.0, 0.1)
    slave.enterEventMode()
    slave.updateDiscreteStates()
    slave.enterStepMode()
    failing(slave.doStep, 0.1, 0.1)  # the master's own grid, not lastSuccessfulTime
    assert "differs from the FMU's time 0.05" in log.texts()[-1]


def test_event_mode_not_used_never_reports_events(plain_fmu, open_slave):
    slave, log = open_slave(plain_fmu, event_mode_used=False, early_return_allowed=True)
    y, event_at = plain_fmu.vr("y"), plain_fmu.vr("event_at")
    slave.enterInitializationMode(startTime=0.0)
    slave.setFloat64([event_at], [0.3])
    slave.exitInitializationMode()  # straight to Step Mode
    assert slave.doStep(0.0, 0.25) == (False, False, False, 0.25)
    assert slave.doStep(0.25, 0.25) == (False, False, True, 0.3)  # early, but no event handling
    assert slave.getFloat64([y]) == [pytest.approx(0.3, abs=1e-15)]  # y' = u = 1
    assert slave.doStep(0.3, 0.2) == (False, False, False, 0.5)
    assert any("handled inside the FMU" in text for text in log.texts("logEvents"))
    failing(slave.enterEventMode)


def test_fmpy_simulate_fmu_runs_the_clockless_model(plain_fmu):
    result = simulate_fmu(
        str(plain_fmu.unzip_dir),
        start_values={"event_at": 0.3},
        stop_time=1.0,
        output_interval=0.25,
        use_event_mode=True,
        early_return_allowed=True,
        output=["y"],
    )
    assert 0.3 in list(result["time"])  # the early return at the internal event was recorded
    for t, y in zip(result["time"], result["y"]):
        assert y == pytest.approx(t, abs=1e-12)
    assert result["time"][-1] == pytest.approx(1.0)


# --------------------------------------------------------------------------------------------
# Get/Set rules, types, arrays


def test_get_after_set_in_step_mode_needs_a_step_in_between(counter_fmu, open_slave, v):
    slave, log = open_slave(counter_fmu)
    first_tick(slave, v)
    slave.enterStepMode()
    slave.setFloat64([v("level")], [2.0])
    failing(slave.getUInt64, [v("count")])
    assert "without an fmi3DoStep in between" in log.texts()[-1]

    other, _ = open_slave(counter_fmu)
    first_tick(other, v)
    other.enterStepMode()
    other.setFloat64([v("level")], [2.0])
    other.doStep(0.0, 0.05)
    assert other.getFloat64([v("level")]) == [2.0]


def test_array_parameter_and_values_used_by_the_cycle(counter_fmu, open_slave, v):
    slave, _ = open_slave(counter_fmu)
    slave.enterInitializationMode(startTime=0.0)
    slave.setFloat64([v("gains")], [4.0, 5.0, 6.0])
    slave.setFloat64([v("offset"), v("level")], [0.25, 1.0])
    assert slave.getFloat64([v("level"), v("gains"), v("offset")], nValues=5) == [1.0, 4.0, 5.0, 6.0, 0.25]
    slave.exitInitializationMode()
    slave.setClock([v("cycle"), v("command")], [True, True])
    slave.setInt64([v("command.value")], [3])
    assert slave.getFloat64([v("tick.value")]) == [3 * 5.0 + 0.25 + 1.0]


def test_every_numeric_type_round_trips(plain_fmu, open_slave):
    slave, _ = open_slave(plain_fmu, event_mode_used=False)
    vr = plain_fmu.vr
    slave.enterInitializationMode(startTime=0.0)
    assert slave.getFloat32([vr("f32")]) == [1.5]
    assert [slave.getInt8([vr("i8")]), slave.getUInt8([vr("u8")])] == [[-8], [8]]
    slave.setFloat32([vr("f32")], [2.5])
    slave.setInt8([vr("i8")], [-100])
    slave.setUInt8([vr("u8")], [200])
    slave.setInt16([vr("i16")], [-30000])
    slave.setUInt16([vr("u16")], [60000])
    slave.setUInt32([vr("u32")], [4_000_000_000])
    slave.setInt32([vr("misbehave")], [0])
    assert slave.getFloat32([vr("f32")]) == [2.5]
    assert slave.getInt8([vr("i8")]) == [-100]
    assert slave.getUInt8([vr("u8")]) == [200]
    assert slave.getInt16([vr("i16")]) == [-30000]
    assert slave.getUInt16([vr("u16")]) == [60000]
    assert slave.getUInt32([vr("u32")]) == [4_000_000_000]
    assert slave.getInt32([vr("misbehave")]) == [0]


def test_tunable_parameters_can_be_set_in_event_and_step_mode(counter_fmu, open_slave, v):
    slave, _ = open_slave(counter_fmu)
    first_tick(slave, v)
    slave.setFloat64([v("offset")], [1.5])  # Event Mode
    slave.enterStepMode()
    slave.setInt32([v("limit")], [7])  # Step Mode
    slave.doStep(0.0, 0.1)
    assert slave.getInt32([v("limit")]) == [7]
    assert slave.getFloat64([v("offset")]) == [1.5]


# --------------------------------------------------------------------------------------------
# Errors, Terminated, Reset


def test_an_error_leads_to_terminated_and_reset_recovers(counter_fmu, open_slave, v):
    slave, log = open_slave(counter_fmu)
    slave.enterInitializationMode(startTime=0.0)
    slave.setFloat64([v("gains")], [7.0, 8.0, 9.0])
    slave.exitInitializationMode()
    slave.setClock([v("cycle")], [True])
    slave.updateDiscreteStates()
    slave.enterStepMode()
    failing(slave.doStep, 0.0, -1.0)
    assert log.messages[-1][:2] == (ERROR, "logStatusError")
    assert slave.getUInt64([v("count")]) == [1]  # Terminated: non-clocked Gets still work
    failing(slave.doStep, 0.0, 0.1)
    slave.reset()
    slave.enterInitializationMode(startTime=0.0)  # back in Instantiated, so this is legal again
    assert slave.getFloat64([v("gains")], nValues=3) == [1.0, 2.0, 3.0]  # start values
    assert slave.getUInt64([v("count")]) == [0]


def test_terminate_then_read_final_values(counter_fmu, open_slave, v):
    slave, _ = open_slave(counter_fmu)
    first_tick(slave, v)
    slave.enterStepMode()
    slave.doStep(0.0, 0.1)
    slave.terminate()
    assert slave.getUInt64([v("count")]) == [1]
    failing(slave.getFloat64, [v("tick.value")])  # clocked: never in Terminated


# --------------------------------------------------------------------------------------------
# Logging


def test_logging_categories(counter_fmu, open_slave, v):
    slave, log = open_slave(counter_fmu)  # loggingOn: all four categories
    first_tick(slave, v)
    assert "counter0: cycle 1" in log.texts("logTransitions")
    assert any("'cycle' activated at t=0" in text for text in log.texts("logEvents"))

    slave.setDebugLogging(True, ["logEvents"])
    log.clear()
    slave.enterStepMode()
    step_to_next_tick(slave, v, 0.0)
    assert log.texts("logTransitions") == [] and log.texts("logEvents") != []

    slave.setDebugLogging(False, [])
    log.clear()
    slave.enterStepMode()
    step_to_next_tick(slave, v, 0.1)
    assert log.messages == []
    failing(slave.doStep, 0.2, 0.1)  # still in Event Mode; errors are logged even with logging off
    assert log.messages == [(ERROR, "logStatusError", log.messages[0][2])]
    assert "fmi3DoStep: not allowed in Event Mode" in log.messages[0][2]


def test_logging_off_at_instantiation_logs_only_errors(counter_fmu, open_slave, v):
    slave, log = open_slave(counter_fmu, logging_on=False)
    first_tick(slave, v)
    slave.enterStepMode()
    step_to_next_tick(slave, v, 0.0)
    assert log.messages == []
    failing(slave.enterEventMode)  # already in Event Mode
    assert [status for status, _, _ in log.messages] == [ERROR]


# --------------------------------------------------------------------------------------------
# FMU state


def test_fmu_state_rolls_back_data_time_and_clock_bookkeeping(counter_fmu, open_slave, v):
    slave, _ = open_slave(counter_fmu)
    first_tick(slave, v)
    slave.enterStepMode()
    saved = slave.getFMUState()  # Step Mode at t = 0, count 1, next tick k = 1
    step_to_next_tick(slave, v, 0.0)
    slave.setClock([v("command")], [True])
    slave.setInt64([v("command.value")], [4])
    slave.updateDiscreteStates()
    slave.enterStepMode()
    step_to_next_tick(slave, v, 0.1)
    assert slave.getInt64([v("last_command")]) == [4]
    assert slave.getUInt64([v("count")]) == [3]

    slave.setFMUState(saved)
    assert slave.getUInt64([v("count")]) == [1]
    assert slave.getInt64([v("last_command")]) == [0]
    assert slave.doStep(0.0, 0.1) == (False, False, False, 0.1)  # time is 0 again, in Step Mode
    slave.enterEventMode()
    slave.setClock([v("cycle")], [True])  # tick k = 1 may run again after the roll-back
    assert slave.getUInt64([v("count")]) == [2]
    slave.freeFMUState(saved)


def test_fmu_state_taken_inside_an_instant_keeps_the_clocks(counter_fmu, open_slave, v):
    slave, _ = open_slave(counter_fmu)
    slave.enterInitializationMode(startTime=0.0)
    slave.exitInitializationMode()
    slave.setClock([v("cycle"), v("command")], [True, True])
    slave.setInt64([v("command.value")], [2])
    assert slave.getClock([v("tick")]) == [True]
    inside = slave.getFMUState()
    slave.updateDiscreteStates()
    slave.enterStepMode()
    slave.setFMUState(inside)  # back in Event Mode, tick active, evaluated
    assert slave.getClock([v("tick")]) == [True]
    assert slave.getFloat64([v("tick.value")]) == [2 * 2.0 + 0.5]
    assert slave.getUInt64([v("evaluations")]) == [1]


def test_serialized_state_restores_in_another_instance(counter_fmu, open_slave, v):
    slave, _ = open_slave(counter_fmu)
    first_tick(slave, v)
    slave.enterStepMode()
    step_to_next_tick(slave, v, 0.0)
    slave.enterStepMode()
    state = slave.getFMUState()
    data = slave.serializeFMUState(state)
    size = ctypes.c_size_t()
    slave.fmi3SerializedFMUStateSize(slave.component, state, ctypes.byref(size))
    assert len(data) == size.value and data[:8] == b"RGSTATE1"

    other, _ = open_slave(counter_fmu)  # still Instantiated
    restored = other.deserializeFMUState(data)
    other.setFMUState(restored)
    assert other.getUInt64([v("count")]) == [2]
    assert other.doStep(0.1, 0.1) == (False, False, False, pytest.approx(0.2))
    other.enterEventMode()
    other.setClock([v("cycle")], [True])
    assert other.getUInt64([v("count")]) == [3]
    assert other.serializeFMUState(other.getFMUState()) != data


def test_a_restored_state_keeps_its_start_time_and_stop_time(counter_fmu, open_slave, v):
    slave, _ = open_slave(counter_fmu)
    first_tick(slave, v, start_time=0.25, stop_time=0.5)  # tick grid 0.25 + k * 0.1
    slave.enterStepMode()
    data = slave.serializeFMUState(slave.getFMUState())

    other, log = open_slave(counter_fmu)  # fresh: start time 0, no stop time
    other.setFMUState(other.deserializeFMUState(data))
    step_to_next_tick(other, v, 0.25)  # tick k=1 at 0.35 is due, on the restored grid
    other.enterStepMode()
    assert other.getUInt64([v("count")]) == [2]
    failing(other.doStep, 0.35, 0.2)  # 0.55 is past the restored stopTime 0.5
    assert "past stopTime 0.5" in log.texts()[-1]


def test_an_event_mode_state_needs_an_event_mode_instance(plain_fmu, open_slave):
    with_events, _ = open_slave(plain_fmu, event_mode_used=True)
    with_events.enterInitializationMode(startTime=0.0)
    with_events.exitInitializationMode()  # Event Mode
    data = with_events.serializeFMUState(with_events.getFMUState())
    without, log = open_slave(plain_fmu, event_mode_used=False)
    failing(without.setFMUState, without.deserializeFMUState(data))
    assert "eventModeUsed=false" in log.texts()[-1]


def test_serialized_state_of_another_fmu_is_rejected(counter_fmu, plain_fmu, open_slave, v):
    plain, _ = open_slave(plain_fmu, event_mode_used=False)
    foreign = plain.serializeFMUState(plain.getFMUState())
    slave, log = open_slave(counter_fmu)
    failing(slave.deserializeFMUState, foreign)
    assert "serialized by another FMU" in log.texts()[-1]


# --------------------------------------------------------------------------------------------
# Several instances and FMUs in one process


def test_instances_and_fmus_are_independent(counter_fmu, plain_fmu, open_slave, v):
    first, _ = open_slave(counter_fmu)
    second, _ = open_slave(counter_fmu)
    plain, _ = open_slave(plain_fmu, event_mode_used=False)
    first_tick(first, v)
    first.enterStepMode()
    step_to_next_tick(first, v, 0.0)
    first_tick(second, v)
    plain.enterInitializationMode(startTime=0.0)
    plain.exitInitializationMode()
    plain.doStep(0.0, 0.5)
    assert first.getUInt64([v("count")]) == [2]
    assert second.getUInt64([v("count")]) == [1]
    assert plain.getFloat64([plain_fmu.vr("y")]) == [0.5]
