"""The FMI 3.0 state machine of a Python FMU (robogen.pyfmu.slave), without compiling: the call
rules of the FMI 3.0 standard (calling sequences, clocks, Event Mode), each checked on the fixture models."""

from __future__ import annotations

import pytest

from pyfmu_fixture_models import Counter, TwoInstants
from robogen.pyfmu.model import Float64, FmiUsageError, Model
from robogen.pyfmu.slave import Slave, State

VR = {v.name: v.vr for v in Counter.variables()}


def started(model=Counter, **kwargs) -> Slave:
    slave = Slave(model, **{"early_return_allowed": True, **kwargs})
    slave.enter_initialization_mode(None, 0.0, None)
    slave.exit_initialization_mode()
    return slave


def get(slave: Slave, name: str, type_name: str = "Int64"):
    return slave.get("fmi3Get" + type_name, type_name, [VR[name]])[0]


def test_a_clocked_model_refuses_event_mode_unused():
    with pytest.raises(FmiUsageError, match="eventModeUsed"):
        Slave(Counter, event_mode_used=False)


def test_exit_initialization_leads_to_event_mode_and_the_first_tick_is_counted_once():
    slave = started()
    assert slave.state is State.EVENT
    slave.set_clock([VR["tick"]], [True])
    slave.set_clock([VR["tick"]], [True])  # the same activation, in the same instant
    assert slave.get_clock([VR["ticked"]]) == [True]
    assert get(slave, "ticked.count") == 1
    slave.update_discrete_states()
    with pytest.raises(FmiUsageError, match="already active in this Event Mode"):
        slave.set_clock([VR["tick"]], [True])


def test_output_clocks_read_active_repeatedly_then_inactive_after_the_instant_closes():
    slave = started()
    slave.set_clock([VR["tick"]], [True])
    assert slave.get_clock([VR["ticked"]]) == [True]
    assert slave.get_clock([VR["ticked"]]) == [True]
    slave.update_discrete_states()
    assert slave.get_clock([VR["ticked"]]) == [False]
    slave.enter_step_mode()
    slave.do_step(0.0, 0.5)
    slave.enter_event_mode()
    assert slave.get_clock([VR["ticked"]]) == [False]  # not sticky across Event Modes either


def test_a_repeated_get_is_checked_like_the_first():
    # The slave keeps what it checked of a Get (types, value references); what depends on the
    # moment (clock activity, the instant's outputs) is checked at every call.
    slave = started()
    slave.set_clock([VR["tick"]], [True])
    both = [VR["ticked.count"], VR["total"]]
    assert slave.get("fmi3GetInt64", "Int64", both) == [1, 1]
    slave.update_discrete_states()
    for _ in range(2):
        with pytest.raises(FmiUsageError, match="clocked by 'ticked', which is not active"):
            slave.get("fmi3GetInt64", "Int64", both)
        with pytest.raises(FmiUsageError, match="unknown value reference 999"):
            slave.get("fmi3GetInt64", "Int64", [VR["total"], 999])
        with pytest.raises(FmiUsageError, match="is a Int64"):
            slave.get("fmi3GetFloat64", "Float64", [VR["total"]])
    assert slave.get("fmi3GetInt64", "Int64", [VR["total"]]) == [1]
    slave.set_clock([VR["bump"]], [True])
    slave.set("fmi3SetInt64", "Int64", [VR["bump.amount"]], [5])
    assert slave.get("fmi3GetInt64", "Int64", [VR["total"]]) == [6]  # the instant's reaction ran first


def test_clocked_variables_only_while_their_clock_is_active():
    slave = started()
    with pytest.raises(FmiUsageError, match="clocked by 'bump', which is not active"):
        slave.set("fmi3SetInt64", "Int64", [VR["bump.amount"]], [5])
    slave.set_clock([VR["bump"]], [True])
    slave.set("fmi3SetInt64", "Int64", [VR["bump.amount"]], [5])
    assert get(slave, "total") == 5
    with pytest.raises(FmiUsageError, match="not active"):
        get(slave, "ticked.count")  # its clock 'ticked' did not tick in this instant
    slave.update_discrete_states()
    slave.enter_step_mode()
    with pytest.raises(FmiUsageError, match="Step Mode"):
        get(slave, "ticked.count")
    with pytest.raises(FmiUsageError, match="not allowed in Step Mode"):
        slave.set_clock([VR["bump"]], [True])


def test_input_clock_arrivals_after_outputs_were_read_are_processed_too():
    slave = started()
    slave.set_clock([VR["tick"]], [True])
    assert get(slave, "total") == 1
    slave.set_clock([VR["bump"]], [True])
    slave.set("fmi3SetInt64", "Int64", [VR["bump.amount"]], [10])
    assert get(slave, "total") == 11


def test_clocks_cannot_be_deactivated_nor_output_clocks_set():
    slave = started()
    with pytest.raises(FmiUsageError, match="cannot be deactivated"):
        slave.set_clock([VR["bump"]], [False])
    with pytest.raises(FmiUsageError, match="output clock"):
        slave.set_clock([VR["ticked"]], [True])
    with pytest.raises(FmiUsageError, match="input clock"):
        slave.get_clock([VR["tick"]])


def test_enter_step_mode_needs_an_update_discrete_states():
    slave = started()
    with pytest.raises(FmiUsageError, match="at least once"):
        slave.enter_step_mode()


def test_do_step_continues_only_from_the_last_successful_time():
    slave = started()
    slave.update_discrete_states()
    slave.enter_step_mode()
    result = slave.do_step(0.0, 0.5)
    assert (result.last_successful_time, result.early_return) == (0.5, False)
    with pytest.raises(FmiUsageError, match="not the FMU's time"):
        slave.do_step(0.0, 0.5)
    with pytest.raises(FmiUsageError, match="> 0"):
        slave.do_step(0.5, 0.0)


def test_early_return_only_when_allowed_and_only_before_t_plus_h():
    slave = Slave(Counter, early_return_allowed=True)
    slave.set("fmi3SetFloat64", "Float64", [VR["alarm_time"]], [0.3])
    slave.enter_initialization_mode(None, 0.0, None)
    slave.exit_initialization_mode()
    slave.update_discrete_states()
    slave.enter_step_mode()
    result = slave.do_step(0.0, 0.5)
    assert (result.early_return, result.event_handling_needed, result.last_successful_time) == (True, True, 0.3)
    slave.enter_event_mode()
    assert slave.get_clock([VR["alarm"]]) == [True]

    late = Slave(Counter, early_return_allowed=False)
    late.set("fmi3SetFloat64", "Float64", [VR["alarm_time"]], [0.3])
    late.enter_initialization_mode(None, 0.0, None)
    late.exit_initialization_mode()
    late.update_discrete_states()
    late.enter_step_mode()
    result = late.do_step(0.0, 0.5)
    assert (result.early_return, result.event_handling_needed, result.last_successful_time) == (False, True, 0.5)


def test_a_model_returning_early_without_permission_is_an_error():
    class Sneaky(Counter):
        def do_step(self, t, h):
            from robogen.pyfmu import Step
            return Step(t + h / 2)

    slave = Slave(Sneaky, early_return_allowed=False)
    slave.enter_initialization_mode(None, 0.0, None)
    slave.exit_initialization_mode()
    slave.update_discrete_states()
    slave.enter_step_mode()
    with pytest.raises(RuntimeError, match="earlyReturnAllowed is false"):
        slave.do_step(0.0, 1.0)


def test_get_after_set_in_step_mode_needs_a_do_step():
    slave = started()
    slave.update_discrete_states()
    slave.enter_step_mode()
    slave.set("fmi3SetInt32", "Int32", [VR["small"]], [8])
    with pytest.raises(FmiUsageError, match="needs an fmi3DoStep"):
        slave.get("fmi3GetFloat64", "Float64", [VR["position"]])
    slave.do_step(0.0, 0.5)
    assert slave.get("fmi3GetFloat64", "Float64", [VR["position"]]) == [0.5]


def test_what_may_be_set_in_which_state():
    slave = Slave(Counter)
    slave.set("fmi3SetFloat64", "Float64", [VR["alarm_time"]], [1.0])  # fixed, exact: before init
    slave.enter_initialization_mode(None, 0.0, 10.0)
    slave.set("fmi3SetFloat64", "Float64", [VR["alarm_time"]], [2.0])
    slave.exit_initialization_mode()
    with pytest.raises(FmiUsageError, match="cannot be set in Event Mode"):
        slave.set("fmi3SetFloat64", "Float64", [VR["alarm_time"]], [3.0])  # fixed after init
    slave.set("fmi3SetFloat64", "Float64", [VR["speed"]], [2.0])  # tunable
    slave.set("fmi3SetString", "String", [VR["label"]], ["renamed"])
    with pytest.raises(FmiUsageError, match="cannot be set"):
        slave.set("fmi3SetFloat64", "Float64", [VR["position"]], [1.0])  # an output
    with pytest.raises(FmiUsageError, match="is a Int64"):
        slave.set("fmi3SetFloat64", "Float64", [VR["total"]], [1.0])
    with pytest.raises(FmiUsageError, match="unknown value reference"):
        slave.get("fmi3GetFloat64", "Float64", [999])
    with pytest.raises(FmiUsageError, match="out of the Int32 range"):
        slave.set("fmi3SetInt32", "Int32", [VR["small"]], [2**40])


def test_stop_time_is_respected():
    slave = Slave(Counter)
    slave.enter_initialization_mode(None, 0.0, 1.0)
    slave.exit_initialization_mode()
    slave.update_discrete_states()
    slave.enter_step_mode()
    slave.do_step(0.0, 0.5)
    slave.do_step(0.5, 0.5)  # lands on the stop time
    with pytest.raises(FmiUsageError, match="past stopTime"):
        slave.do_step(1.0, 0.5)


def test_constant_clock_interval_and_shift_come_from_the_declaration_and_settings():
    slave = Slave(Counter.configured({"period": 0.25}))
    slave.enter_initialization_mode(None, 0.0, None)
    assert slave.get_interval_decimal([VR["tick"]]) == ([0.25], [1])
    assert slave.get_shift_decimal([VR["tick"]]) == [0.0]
    slave.exit_initialization_mode()
    assert slave.get_interval_decimal([VR["tick"]]) == ([0.25], [1])
    with pytest.raises(FmiUsageError, match="fmi3GetShiftDecimal is not allowed in Event Mode"):
        slave.get_shift_decimal([VR["tick"]])  # a shift is known from Initialization Mode on
    with pytest.raises(FmiUsageError, match="triggered clock"):
        slave.get_interval_decimal([VR["bump"]])


def test_update_reports_another_instant_and_the_next_time_event():
    slave = started(TwoInstants)
    first = slave.update_discrete_states()
    assert (first.discrete_states_need_update, first.next_event_time_defined, first.next_event_time) == (True, True, 1.25)
    second = slave.update_discrete_states()
    assert second.discrete_states_need_update is False


def test_without_event_mode_events_are_handled_inside_the_step():
    class Eventful(TwoInstants):
        def do_step(self, t, h):
            from robogen.pyfmu import Step
            return Step(t + h, event=True)

    slave = Slave(Eventful, event_mode_used=False)
    slave.enter_initialization_mode(None, 0.0, None)
    slave.exit_initialization_mode()
    assert slave.state is State.STEP
    result = slave.do_step(0.0, 1.0)
    assert result.event_handling_needed is False
    # one internal event iteration: two instants, the first asking for the second
    assert slave.get("fmi3GetInt64", "Int64", [Eventful.variable("instants").vr]) == [2]
    with pytest.raises(FmiUsageError, match="eventModeUsed = false"):
        slave.enter_event_mode()


def test_terminate_then_reset_gives_a_fresh_instance():
    slave = started()
    slave.set_clock([VR["tick"]], [True])
    assert get(slave, "total") == 1
    slave.update_discrete_states()
    slave.terminate()
    assert slave.state is State.TERMINATED
    assert get(slave, "total") == 1  # non-clocked gets still allowed
    slave.reset()
    assert slave.state is State.INSTANTIATED
    slave.enter_initialization_mode(None, 0.0, None)
    assert get(slave, "total") == 0


class _Lazy(Model):
    """Outputs computed on demand through update_outputs: ``square`` of the input ``x``."""

    x = Float64(2.0, causality="input")
    gain = Float64(1.0, causality="parameter", variability="tunable")
    square = Float64(causality="output", depends_on=("x",))
    doubled = Float64(causality="output", depends_on=("x",))

    def setup(self) -> None:
        self.updates = 0
        self.outputs_stale = True

    def set(self, name, value) -> None:
        super().set(name, value)
        self.outputs_stale = True

    def update_outputs(self) -> None:
        self.updates += 1
        self.square, self.doubled = self.x * self.x, 2 * self.x
        self.outputs_stale = False


def test_update_outputs_runs_once_before_outputs_are_read_and_only_while_stale():
    slave = Slave(_Lazy, event_mode_used=False)
    slave.enter_initialization_mode(None, 0.0, None)
    vr = {v.name: v.vr for v in _Lazy.variables()}
    read = lambda *names: slave.get("fmi3GetFloat64", "Float64", [vr[n] for n in names])  # noqa: E731
    assert read("x", "gain") == [2.0, 1.0] and slave.model.updates == 0  # no output read: no update
    assert read("square", "doubled") == [4.0, 4.0] and slave.model.updates == 1
    assert read("doubled") == [4.0] and slave.model.updates == 1  # not stale: served as computed
    slave.set("fmi3SetFloat64", "Float64", [vr["x"]], [3.0])
    assert read("doubled", "square", "x") == [6.0, 9.0, 3.0] and slave.model.updates == 2
