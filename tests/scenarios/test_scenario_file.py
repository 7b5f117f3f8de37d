"""Scenario files against a model description written here: payloads of every shape, repeats,
parameters, input courses, the player's answers to the master, and located errors."""

from __future__ import annotations

from pathlib import Path

import pytest

from robogen.cosim.player import ScenarioBinding, player_description
from robogen.cosim.scenario import load_scenario, timeline
from robogen.diagnostics import RobogenError
from robogen.fmu.modeldesc import CoSimulation, Dimension, EnumerationType, Item, ModelDescription, Variable


def _md() -> ModelDescription:
    v = []

    def add(name, type_, **kw):
        v.append(Variable(name, len(v), type_, **kw))
        return len(v) - 1

    add("time", "Float64", causality="independent")
    add("tock", "Clock", causality="input", variability="discrete", interval_variability="constant", interval_decimal="1")
    add("smoke", "Clock", causality="input", variability="discrete", interval_variability="triggered")
    temp = add("temperature", "Clock", causality="input", variability="discrete", interval_variability="triggered")
    add("temperature.value", "Float64", causality="input", variability="discrete", clocks=(temp,))
    fire = add("fire", "Clock", causality="input", variability="discrete", interval_variability="triggered")
    add("fire.x", "Int64", causality="input", variability="discrete", clocks=(fire,))
    add("fire.y", "Int64", causality="input", variability="discrete", clocks=(fire,))
    cleared = add("cleared", "Clock", causality="input", variability="discrete", interval_variability="triggered")
    add("cleared.value.elements", "UInt64", causality="input", variability="discrete", clocks=(cleared,),
        dimensions=(Dimension(start=4),))
    add("cleared.value.size", "UInt64", causality="input", variability="discrete", clocks=(cleared,))
    gas = add("gas", "Clock", causality="input", variability="discrete", interval_variability="triggered")
    add("gas.value.elements.c", "Enumeration", causality="input", variability="discrete", clocks=(gas,),
        dimensions=(Dimension(start=3),), declared_type="Chem")
    add("gas.value.elements.at.x", "Float64", causality="input", variability="discrete", clocks=(gas,),
        dimensions=(Dimension(start=3),))
    add("gas.value.size", "UInt64", causality="input", variability="discrete", clocks=(gas,))
    add("u", "Float64", causality="input", variability="continuous", start=("0.5",))
    add("alarm", "Clock", causality="output", variability="discrete", interval_variability="triggered")
    chem = EnumerationType("Chem", (Item("Chem.co2", 0), Item("Chem.smoke", 1)))
    return ModelDescription("M", "{x}", CoSimulation("m", has_event_mode=True), tuple(v), type_definitions=(chem,))


MD = _md()


def _scenario(tmp_path: Path, text: str, name: str = "s.toml"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return load_scenario(path)


def _errors(tmp_path: Path, text: str, stop: float = 10.0) -> list[str]:
    with pytest.raises(RobogenError) as caught:
        timeline(_scenario(tmp_path, text), MD, 0.0, stop)
    return [f"{d.span.line}:{d.span.column}: {d.message}" for d in caught.value.diagnostics]


def test_payloads_of_every_shape_set_the_fmu_variables(tmp_path):
    plan = timeline(_scenario(tmp_path, """
events = [
  { at = 3.0, event = "fire", value = { x = 2, y = -1 } },
  { at = 1.0, event = "smoke" },
  { at = 2.0, event = "temperature", value = 42 },
  { at = 4.0, event = "cleared", value = [3, 1] },
  { at = 5.0, event = "gas", value = [{ c = "smoke", at = { x = 1.5 } }, { c = "co2", at = { x = -2 } }] },
]
"""), MD, 0.0, 10.0)
    got = [(o.time, o.clock.name, {v.name: x for v, x in o.values}) for o in plan.occurrences]
    assert got == [
        (1.0, "smoke", {}),
        (2.0, "temperature", {"temperature.value": 42.0}),  # an integer given for a Float64
        (3.0, "fire", {"fire.x": 2, "fire.y": -1}),
        (4.0, "cleared", {"cleared.value.size": 2, "cleared.value.elements": [3, 1, 0, 0]}),  # padded to 4
        (5.0, "gas", {"gas.value.size": 2, "gas.value.elements.c": [1, 0, 0], "gas.value.elements.at.x": [1.5, -2.0, 0.0]}),
    ]
    assert isinstance(got[1][2]["temperature.value"], float)


def test_repeats_and_parameters(tmp_path):
    plan = timeline(_scenario(tmp_path, """
events = [
  { at = "${first}", event = "smoke", every = "${period}", until = 2.0 },
  { at = 0.25, event = "temperature", value = "${hot}", every = 4.0 },
]
[parameters]
first = 0.5
period = 0.5
hot = 60.5
"""), MD, 0.0, 10.0)
    smoke = [o.time for o in plan.occurrences if o.clock.name == "smoke"]
    temp = [(o.time, o.values[0][1]) for o in plan.occurrences if o.clock.name == "temperature"]
    assert smoke == [0.5, 1.0, 1.5, 2.0]  # until is included
    assert temp == [(0.25, 60.5), (4.25, 60.5), (8.25, 60.5)]  # every: up to the stop time, 10
    # a run with other parameter values (what a campaign sets)
    plan = timeline(_scenario(tmp_path, "events = [{ at = \"${first}\", event = \"smoke\" }]\n[parameters]\nfirst = 1.0\n"),
                    MD, 0.0, 10.0, {"first": 7.0})
    assert [o.time for o in plan.occurrences] == [7.0]


def test_located_errors(tmp_path):
    errors = _errors(tmp_path, """events = [
  { at = 1.0, event = "smok" },
  { at = 2.0, event = "temperature", value = "hot" },
  { at = -1.0, event = "smoke" },
  { at = 3.0, event = "fire", value = { x = 2, z = 1 } },
  { at = 4.0, event = "cleared", value = [1, 2, 3, 4, 5] },
  { at = 5.0, event = "tock" },
  { at = 6.0, event = "smoke", value = 1 },
  { at = 7.0, event = "fire" },
  { at = "${nope}", event = "smoke" },
  { at = 8.0, event = "gas", value = [{ c = "ozone", at = { x = 1.0 } }] },
]
""")
    assert errors == [
        "2:15: the FMU has no input event 'smok' (did you mean 'smoke'?)",
        "3:38: 'temperature.value' is a Float64 (a number), not 'hot'",
        "4:5: event 'smoke' at t=-1 is before the start of the run (t=0)",
        "5:31: 'fire' has no field 'z'",
        "6:34: 'cleared.value' holds at most 4 elements (--capacity), not 5",
        "7:15: 'tock' is a constant clock: it ticks on its own, a scenario ticks only triggered input clocks (events)",
        "8:32: event 'smoke' carries no value",
        "9:15: event 'fire' carries a value: give value = ... (fire.x (Int64), fire.y (Int64))",
        "10:5: unknown parameter 'nope'",
        "11:30: 'gas.value.elements.c' has no literal 'ozone'",
    ]


def test_schema_errors_and_two_ticks_in_one_instant(tmp_path):
    with pytest.raises(RobogenError) as caught:
        _scenario(tmp_path, "stop = 5.0\nevent = []\n[[events]]\nat = 1.0\nevnt = \"smoke\"\n")
    found = [f"{d.span.line}:{d.span.column}: {d.message}" for d in caught.value.diagnostics]
    assert found == ["2:1: unknown key 'event' (did you mean 'events'?)",
                     "3:1: this entry of 'events' needs 'event'",
                     "5:1: unknown key 'evnt' in events (did you mean 'event'?)"]
    errors = _errors(tmp_path, "events = [\n  { at = 1.0, event = \"smoke\" },\n  { at = 0.5, event = \"smoke\", every = 0.5 },\n]\n")
    assert errors == ["3:3: event 'smoke' occurs twice at t=1: an input clock ticks once per instant"]
    with pytest.raises(RobogenError) as caught:
        _scenario(tmp_path, "events = [\n  { at = 1.0, event = \"smoke\" \n")
    assert caught.value.diagnostics[0].message.startswith("invalid TOML")


def test_input_courses_steps_and_ramps(tmp_path):
    scenario = _scenario(tmp_path, """
inputs = [
  { at = 2.0, input = "u", ramp = [1.0, 3.0], until = 4.0 },
  { at = 6.0, input = "u", value = -1.0 },
]
""")
    plan = timeline(scenario, MD, 0.0, 10.0)
    md = player_description("d_scenario", scenario, plan, MD)
    player = ScenarioBinding("d_scenario", scenario, MD, md)
    player.fmi3EnterInitializationMode(None, 0.0, 10.0)
    player.fmi3ExitInitializationMode()
    u = md.by_name()["u"].value_reference
    values = {t: player.value_at("u", t) for t in (0.0, 2.0, 3.0, 3.5, 4.0, 5.0, 6.0, 9.0)}
    assert values == {0.0: 0.5, 2.0: 1.0, 3.0: 2.0, 3.5: 2.5, 4.0: 3.0, 5.0: 3.0, 6.0: -1.0, 9.0: -1.0}
    assert player.fmi3UpdateDiscreteStates().next_event_time == 2.0  # the changes are time events
    player.fmi3DoStep(0.0, 2.0)
    assert player.get_values("Float64", [u]) == [1.0]
    assert _errors(tmp_path, "inputs = [{ at = 1.0, input = \"uu\", value = 1 }, { at = 1.0, input = \"u\", ramp = [1, 2] }]\n") == [
        "1:23: the FMU has no input value 'uu' (did you mean 'u'?)",
        "1:75: a ramp needs 'until', the time it reaches its last value"]


def test_the_player_raises_each_occurrence_once_at_its_time(tmp_path):
    scenario = _scenario(tmp_path, """
events = [
  { at = 0.0, event = "smoke" },
  { at = 1.5, event = "fire", value = { x = 4, y = 5 } },
  { at = 1.5, event = "temperature", value = 20.0 },
]
""")
    plan = timeline(scenario, MD, 0.0, 3.0)
    md = player_description("d_scenario", scenario, plan, MD)
    names = {v.name: v for v in md.variables}
    assert [(v.name, v.causality) for v in md.variables] == [
        ("smoke", "output"), ("fire", "output"), ("fire.x", "output"), ("fire.y", "output"),
        ("temperature", "output"), ("temperature.value", "output")]
    assert names["fire.x"].clocks == (names["fire"].value_reference,)
    player = ScenarioBinding("d_scenario", scenario, MD, md)
    player.fmi3EnterInitializationMode(None, 0.0, 3.0)
    player.fmi3ExitInitializationMode()  # Event Mode at the start: smoke is due
    clocks = [names[c].value_reference for c in ("smoke", "fire", "temperature")]
    active = [False] * 3
    player.fmi3GetClock(clocks, 3, active)
    assert active == [True, False, False]
    states = player.fmi3UpdateDiscreteStates()
    assert (states.next_event_time_defined, states.next_event_time) == (True, 1.5)
    player.fmi3GetClock(clocks, 3, active)
    assert active == [False, False, False]  # the update closed the instant
    player.fmi3EnterStepMode()
    player.fmi3DoStep(0.0, 1.5)
    player.fmi3EnterEventMode()
    player.fmi3GetClock(clocks, 3, active)
    assert active == [False, True, True]
    assert player.get_values("Int64", [names["fire.x"].value_reference, names["fire.y"].value_reference]) == [4, 5]
    assert player.fmi3UpdateDiscreteStates().next_event_time_defined is False
    assert player.stop == 3.0
