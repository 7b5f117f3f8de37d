"""Reading modelDescription.xml into the dataclasses, with located errors, and the token."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from robogen.diagnostics import RobogenError
from robogen.fmu.modeldesc import (
    CoSimulation, DefaultExperiment, Dimension, EnumerationType, Item, LogCategory, ModelDescription, Unit, Unknown,
    Variable, instantiation_token, read_model_description,
)

# One file with every kind of element the dataclasses hold, written by hand the way other tools
# write them (attributes in another order, a comment, start tags over several lines).
EVERYTHING = (Path(__file__).resolve().parent / "everything.xml").read_bytes()


def test_every_element_is_read_into_its_dataclass():
    md = read_model_description(EVERYTHING, "all.xml")
    assert md == ModelDescription(
        model_name="All", instantiation_token="{tok}", description="every type", generation_tool="hand",
        variable_naming_convention="structured",
        co_simulation=CoSimulation("all", has_event_mode=True, can_handle_variable_step=True,
                                   can_get_and_set_state=True, fixed_internal_step="1e-3"),
        unit_definitions=(Unit("rad/s", (("s", -1), ("rad", 1))), Unit("furlong")),
        type_definitions=(EnumerationType("Mode", (Item("Off", 0), Item("On", 7, "running"))),),
        log_categories=(LogCategory("logEvents", "events"), LogCategory("logStatusError")),
        default_experiment=DefaultExperiment("0", "10.0", "1e-6", "0.5"),
        variables=(
            Variable("time", 0, "Float64", "independent", "continuous"),
            Variable("f32", 1, "Float32", "parameter", "tunable", start=("1.5",)),
            Variable("w", 2, "Float64", "output", "continuous", unit="rad/s", description="speed"),
            Variable("i8", 3, "Int8", "input", "discrete", start=("-8",)),
            Variable("u8", 4, "UInt8", "local", "discrete", start=("8",)),
            Variable("i16", 5, "Int16", "local", "discrete", start=("-16",)),
            Variable("u16", 6, "UInt16", "local", "discrete", start=("16",)),
            Variable("i32", 7, "Int32", "local", "discrete", start=("-32",)),
            Variable("u32", 8, "UInt32", "local", "discrete", start=("32",)),
            Variable("v", 9, "Int64", "parameter", "fixed", start=("1", "2", "3", "4", "5", "6"),
                     dimensions=(Dimension(start=2), Dimension(value_reference=8))),
            Variable("u64", 10, "UInt64", "local", "discrete", start=("18446744073709551615",)),
            Variable("b", 11, "Boolean", "input", "discrete", start=("true",), clocks=(14,)),
            Variable("s", 12, "String", "parameter", "fixed", start=("hello world",)),
            Variable("blob", 13, "Binary", "parameter", "fixed", start=("0a0b", "ff"), dimensions=(Dimension(2),)),
            Variable("tick", 14, "Clock", "input", "discrete", interval_variability="constant",
                     interval_decimal="0.25", shift_decimal="0.0", can_be_deactivated=True),
            Variable("done", 15, "Clock", "output", "discrete", interval_variability="triggered", clocks=(14,)),
            Variable("mode", 16, "Enumeration", "output", "discrete", declared_type="Mode", clocks=(15,),
                     previous=17, initial="exact", start=("0",)),
            Variable("previous_mode", 17, "Enumeration", "local", "discrete", declared_type="Mode"),
        ),
        unknowns=(Unknown("Output", 2), Unknown("Output", 15, (14, 11)), Unknown("Output", 16, (15,)),
                  Unknown("ClockedState", 16), Unknown("InitialUnknown", 2, ())),
    )


def test_clock_timing_as_numbers_and_as_written():
    tick = read_model_description(EVERYTHING).by_name()["tick"]
    assert (tick.interval, tick.shift) == (0.25, 0.0)
    assert (tick.interval_decimal, tick.shift_decimal) == ("0.25", "0.0")
    assert tick.is_clock and not tick.is_clocked
    done = read_model_description(EVERYTHING).by_name()["done"]
    assert (done.interval, done.shift) == (None, None) and done.is_clocked


def test_elements_are_located_at_the_line_where_they_open():
    md = read_model_description(EVERYTHING)
    by_name = md.by_name()
    lines = EVERYTHING.decode().splitlines()
    for name in ("time", "f32", "v", "blob", "tick", "mode"):
        line = by_name[name].line
        assert f'name="{name}"' in lines[line - 1], name
    assert lines[md.co_simulation.line - 1].lstrip().startswith("<CoSimulation")  # the tag spans two lines
    assert [lines[u.line - 1].strip()[:18] for u in md.unknowns[:2]] == ['<Output valueRefer'] * 2


@pytest.mark.parametrize("old, new, line, message", [
    ('valueReference="3"', 'valueReference="three"', 26, "valueReference: 'three' is not an integer"),
    ('intervalDecimal="0.25"', 'intervalDecimal="quarter"', 46, "intervalDecimal: 'quarter' is not a number"),
    ('dependencies="14 11"', 'dependencies="14 b"', 55, "dependencies: '14 b' is not a list of value references"),
    ('<Item name="On" value="7"', '<Item name="On" value="seven"', 13, "value: 'seven' is not an integer"),
    ('fmiVersion="3.0"', 'fmiVersion="1.0"', 2, "fmiVersion is '1.0': robogen imports FMI 2.0 and 3.0 only"),
])
def test_bad_values_are_reported_where_the_element_opens(old, new, line, message):
    with pytest.raises(RobogenError) as exc:
        read_model_description(EVERYTHING.replace(old.encode(), new.encode()), "all.xml")
    diagnostic = exc.value.diagnostics[0]
    assert (diagnostic.span.path, diagnostic.span.line, diagnostic.message) == ("all.xml", line, message)


def test_malformed_xml_and_a_wrong_root_are_located():
    with pytest.raises(RobogenError) as exc:
        read_model_description(b'<?xml version="1.0"?>\n<fmiModelDescription fmiVersion="3.0">\n<a></b>', "m.xml")
    assert exc.value.diagnostics[0].message.startswith("malformed XML")
    assert exc.value.diagnostics[0].span.line == 3
    with pytest.raises(RobogenError, match="root element is <fmiBuildDescription>"):
        read_model_description(b'<fmiBuildDescription fmiVersion="3.0"/>')


def test_the_token_is_the_sha256_of_the_content_written_like_a_guid():
    # sha256 of the empty string: e3b0c442 98fc1c14 9afbf4c8 996fb924 27ae41e4 649b934c a495991b 7852b855
    assert instantiation_token("") == instantiation_token(b"") == "{e3b0c442-98fc-1c14-9afb-f4c8996fb924}"
    token = instantiation_token("machine Arm")
    assert re.fullmatch(r"\{[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}\}", token)
    assert token == instantiation_token("machine Arm") != instantiation_token("machine Arm ")
