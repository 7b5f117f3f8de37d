"""The model description of a Python FMU, built from the class's declarations (no compiling):
what fmi3.md §3 asks of it, written by robogen's one writer and read back unchanged."""

from __future__ import annotations

from dataclasses import replace

from pyfmu_fixture_models import Counter
from robogen.fmu.modeldesc import Unit, Unknown, instantiation_token, read_model_description
from robogen.fmu.modeldesc_writer import write_model_description
from robogen.pyfmu.description import model_description


def test_counter_description_from_its_declarations():
    md = model_description(Counter, "counter")
    by_name = md.by_name()
    assert [v.name for v in md.variables][:2] == ["time", "tick"] and by_name["time"].causality == "independent"
    assert md.co_simulation.has_event_mode and md.co_simulation.might_return_early
    assert md.co_simulation.can_handle_variable_step and not md.co_simulation.can_get_and_set_state
    tick = by_name["tick"]
    assert (tick.interval_variability, tick.interval_decimal, tick.shift_decimal) == ("constant", "0.5", "0.0")
    assert by_name["ticked.count"].clocks == (by_name["ticked"].value_reference,)
    assert by_name["speed"].start == ("1.0",) and by_name["label"].start == ("counter",)  # a String: <Start>
    assert by_name["ticked.count"].start == ()  # calculated: no start
    assert md.unit_definitions == (Unit("m/s", (("m", 1), ("s", -1))), Unit("s", (("s", 1),)))
    assert [c.name for c in md.log_categories] == ["logEvents", "logStatusWarning", "logStatusError"]
    vr = {name: v.value_reference for name, v in by_name.items()}
    assert Unknown("Output", vr["ticked"], (vr["tick"],)) in md.unknowns
    assert Unknown("Output", vr["position"], ()) in md.unknowns  # depends on nothing
    assert Unknown("InitialUnknown", vr["ticked"]) in md.unknowns
    assert not [u for u in md.unknowns if u.value_reference == vr["ticked.count"] and u.kind == "InitialUnknown"]


def test_the_written_description_reads_back_as_built():
    md = model_description(Counter, "counter")
    assert read_model_description(write_model_description(md).encode()) == md


def test_the_token_hashes_the_rest_of_the_description():
    md = model_description(Counter, "counter")
    assert md.instantiation_token == instantiation_token(write_model_description(replace(md, instantiation_token="")))
    assert model_description(Counter.configured({"period": 0.25}), "counter").instantiation_token != md.instantiation_token
