"""Writing modelDescription.xml: byte for byte what code generation emits, valid against the
FMI 3.0 schema, read back unchanged, and deterministic."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from lxml import etree

from robogen.fmu.headers import schema_dir
from robogen.fmu.modeldesc import (
    CoSimulation, ModelDescription, Unknown, Variable, instantiation_token, read_model_description,
)
from robogen.fmu.modeldesc_writer import with_content_token, write_model_description

HERE = Path(__file__).resolve().parent
GOLDEN = HERE.parent / "codegen" / "golden"
EVERYTHING = (HERE / "everything.xml").read_bytes()  # every element the dataclasses hold


@pytest.mark.parametrize("path", sorted(GOLDEN.glob("*/modelDescription.xml")), ids=lambda p: p.parent.name)
def test_golden_model_descriptions_are_written_back_byte_for_byte(path):
    data = path.read_bytes()
    assert write_model_description(read_model_description(data, str(path))).encode("utf-8") == data


def test_there_are_golden_model_descriptions():
    assert len(list(GOLDEN.glob("*/modelDescription.xml"))) >= 2


def test_every_element_survives_a_write_and_a_read():
    md = read_model_description(EVERYTHING)
    text = write_model_description(md)
    assert read_model_description(text.encode()) == md
    assert write_model_description(read_model_description(text.encode())) == text


def test_the_text_is_valid_against_the_fmi3_schema():
    schema = etree.XMLSchema(etree.parse(str(schema_dir() / "fmi3ModelDescription.xsd")))
    text = write_model_description(read_model_description(EVERYTHING))
    assert schema.validate(etree.fromstring(text.encode())), schema.error_log


def small(**changes) -> ModelDescription:
    md = ModelDescription(
        model_name="M", instantiation_token="{t}", co_simulation=CoSimulation("m", has_event_mode=True),
        variables=(Variable("time", 0, "Float64", "independent", "continuous"),
                   Variable("x", 1, "Int64", "output", "discrete"),
                   Variable("c", 2, "Clock", "output", "discrete", interval_variability="triggered")),
        unknowns=(Unknown("InitialUnknown", 2), Unknown("Output", 1), Unknown("Output", 2, ())))
    return replace(md, **changes)


def test_layout_one_attribute_per_line_in_the_head_one_line_per_variable():
    assert write_model_description(small()) == (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        "<fmiModelDescription\n"
        '  fmiVersion="3.0"\n'
        '  modelName="M"\n'
        '  instantiationToken="{t}">\n'
        "  <CoSimulation\n"
        '    modelIdentifier="m"\n'
        '    hasEventMode="true"/>\n'
        "  <ModelVariables>\n"
        '    <Float64 name="time" valueReference="0" causality="independent" variability="continuous"/>\n'
        '    <Int64 name="x" valueReference="1" causality="output" variability="discrete"/>\n'
        '    <Clock name="c" valueReference="2" causality="output" variability="discrete" intervalVariability="triggered"/>\n'
        "  </ModelVariables>\n"
        "  <ModelStructure>\n"  # Output before InitialUnknown, whatever order the description has
        '    <Output valueReference="1"/>\n'
        '    <Output valueReference="2" dependencies=""/>\n'
        '    <InitialUnknown valueReference="2"/>\n'
        "  </ModelStructure>\n"
        "</fmiModelDescription>\n")


def test_attribute_values_are_escaped():
    md = small(description='a < b & "c" > d\nnext line')
    text = write_model_description(md)
    assert '  description="a &lt; b &amp; &quot;c&quot; &gt; d&#10;next line"' in text
    assert read_model_description(text.encode()).description == md.description


def test_content_token_hashes_the_description_written_without_a_token():
    md = with_content_token(small(instantiation_token="anything"))
    assert md.instantiation_token == instantiation_token(write_model_description(small(instantiation_token="")))
    other = with_content_token(small(model_name="N"))
    assert other.instantiation_token != md.instantiation_token
