"""Built-in and user metrics over a results table written by hand."""

from __future__ import annotations

import pytest

from robogen.campaign.metrics import MetricError, Table, builtin, compute, enumeration_names
from robogen.campaign.spec import Metric
from robogen.cosim import SimulationResult

# time, superdense, a clock c (ticks at 0.5 and 1.5), the command clock k (tick at 1.0), a value
# v, a clocked value w (present only while c ticks) and an Enumeration-coded state s.
COLUMNS = ["time", "superdense", "m.c", "m.k", "m.v", "m.w", "m.s"]
ROWS = [
    [0.0, 0, 0, 0, 3.0, None, 1],
    [0.5, 0, 1, 0, 5.0, 7, 2],
    [0.5, 1, 0, 0, 5.0, None, 2],
    [1.0, 0, 0, 1, -1.0, None, 3],
    [1.5, 0, 1, 0, 2.0, 9, 1],
    [2.0, 0, 0, 0, 4.0, None, 1],
]
ENUMS = {"m.s": {1: "Idle", 2: "Moving", 3: "Stopped"}}


def value(kind: str, source: str, **options):
    return builtin(Metric("x", kind, source, options), Table(COLUMNS, ROWS), ENUMS)


def test_values_over_the_run():
    assert value("final", "m.v") == 4.0
    assert value("final", "m.w") == 9  # the last value the clocked variable had
    assert value("min", "m.v") == -1.0 and value("max", "m.v") == 5.0
    assert value("min", "m.w") == 7


def test_value_held_at_a_time():
    assert value("at", "m.v", time=0.75) == 5.0  # the last row at or before 0.75
    assert value("at", "m.v", time=1.0) == -1.0
    assert value("at", "m.w", time=1.2) == 7
    assert value("at", "m.v", time=-1.0) is None


def test_clock_ticks():
    assert value("ticks", "m.c") == 2
    assert value("first_tick", "m.c") == 0.5
    assert value("first_tick", "m.k") == 1.0
    assert value("first_tick", "m.c", since="m.k") == 0.5  # the first tick of c at or after k's: 1.5 - 1.0
    assert value("first_tick", "m.k", since="m.c") == 0.5


def test_enumerations_by_name_and_equality():
    assert value("final", "m.s") == "Idle"
    assert value("at", "m.s", time=1.0) == "Stopped"
    assert value("final", "m.s", equals="Idle") is True
    assert value("at", "m.s", time=0.5, equals="Idle") is False


def test_a_variable_that_was_not_recorded_is_the_runs_failure():
    with pytest.raises(MetricError, match=r"'m\.q' is not recorded in the results"):
        value("final", "m.q")


def test_user_metrics_become_columns_and_their_failures_are_reported():
    result = SimulationResult(COLUMNS, ROWS, None)
    metrics = (Metric("v_end", "final", "m.v"), Metric("mine", "function", "mod:f"))

    def f(results):
        return {"peak": max(results.column("m.v")), "nothing": float("nan")}

    assert compute(metrics, result, ENUMS, {"mod:f": f}) == {"v_end": 4.0, "peak": 5.0, "nothing": None}
    with pytest.raises(MetricError, match=r"mod:f raised ZeroDivisionError: division by zero"):
        compute(metrics, result, ENUMS, {"mod:f": lambda r: 1 / 0})
    with pytest.raises(MetricError, match=r"mod:f must return a dict of name -> value, not list"):
        compute(metrics, result, ENUMS, {"mod:f": lambda r: [1]})
    with pytest.raises(MetricError, match=r"'v_end', which is also the name of another metric"):
        compute(metrics, result, ENUMS, {"mod:f": lambda r: {"v_end": 1}})


def test_enumeration_names_come_from_the_model_description(tmp_path):
    from robogen.fmu.archive import write_fmu

    xml = """<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="3.0" modelName="e" instantiationToken="t">
  <TypeDefinitions><EnumerationType name="Node"><Item name="Idle" value="1"/><Item name="Busy" value="4"/></EnumerationType></TypeDefinitions>
  <ModelVariables><Enumeration name="m.state" valueReference="1" declaredType="Node" causality="output"/></ModelVariables>
</fmiModelDescription>
"""
    fmu = write_fmu(tmp_path / "e.fmu", {"modelDescription.xml": xml})
    assert enumeration_names({"d": fmu}) == {"d.m.state": {1: "Idle", 4: "Busy"}}
