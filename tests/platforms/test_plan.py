"""The controller's plan file: the scenario's command times, and located errors."""

from __future__ import annotations


import pytest

from robogen.diagnostics import RobogenError
from robogen.platforms.plan import Command, load_plan, parse_plan
from support import ROOT

PLAN = ROOT / "models" / "ur5e" / "plan.toml"


def test_scenario_plan_gives_the_sixteen_commands_of_the_case_study():
    events = list(load_plan(PLAN).events())
    assert [c.time for c in events] == [5.0, 10.5, 15.0, 23.5, 30.0, 35.5, 40.0, 48.5,
                                        55.0, 60.5, 65.0, 73.5, 80.0, 85.5, 90.0, 98.5]
    targets = [(0, 23, 1), (3, 20, 2), (8, 10, 0), (1, 13, 0)]
    assert [c.target for c in events] == targets * 4


def test_until_bounds_a_repeating_plan_and_times_do_not_drift():
    plan = parse_plan("repeat_period = 0.1\n[[command]]\ntime = 0.0\ntarget = [1, 2, 3]\n")
    events = list(plan.events(until=1000.0))
    assert len(events) == 10001
    assert events[-1] == Command(1000.0, (1, 2, 3))  # 0 + 10000 * 0.1, not a running sum


def test_a_plan_without_repeat_plays_once():
    plan = parse_plan("[[command]]\ntime = 2.5\ntarget = [0, 0, 0]\n")
    assert list(plan.events(until=100.0)) == [Command(2.5, (0, 0, 0))]


def error_of(text: str) -> str:
    with pytest.raises(RobogenError) as failure:
        parse_plan(text, "plan.toml")
    return "\n".join(f"{d.span}: {d.message}" for d in failure.value.diagnostics)


def test_toml_syntax_errors_are_located():
    assert error_of("repeat_period = \n").startswith("plan.toml:1:")


def test_semantic_errors_are_located_at_their_key():
    text = ("repeat_perod = 25.0\n"
            "[[command]]\n"
            "time = 5.0\n"
            "target = [0, 23]\n"
            "[[command]]\n"
            "time = 30.0\n"
            "target = [1, 2, 3]\n"
            "speed = 3\n")
    message = error_of(text)
    assert "plan.toml:1:1: unknown key 'repeat_perod' (did you mean 'repeat_period'?)" in message
    assert "plan.toml:4:1: 'target' must be three integers [X, Y, Z] (grid indices)" in message
    assert "plan.toml:8:1: unknown key 'speed' in a command" in message


def test_times_outside_the_period_and_missing_fields():
    text = "repeat_period = 10.0\n[[command]]\ntime = 12.0\ntarget = [1, 2, 3]\n[[command]]\ntarget = [1, 2, 3]\n"
    message = error_of(text)
    assert "plan.toml:3:1: 'time' 12.0 s is not within the repeat period (10.0 s)" in message
    assert "plan.toml:5:1: this command has no 'time'" in message
    assert error_of("end_time = 10\n").endswith("the plan has no [[command]]")
    assert "'target' must be three integers" in error_of("[[command]]\ntime = 1.0\ntarget = [1.5, 2, 3]\n")
