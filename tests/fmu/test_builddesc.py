"""robogen.fmu.builddesc: the one reader of sources/buildDescription.xml (packaging a compiled
folder takes its modelIdentifier from it; validation checks it against the model description)."""

from __future__ import annotations

import pytest

from robogen.codegen.api import model_identifier_of
from robogen.diagnostics import RobogenError
from robogen.fmu.builddesc import read_build_description

TWO = b"""<?xml version="1.0" encoding="UTF-8"?>
<fmiBuildDescription fmiVersion="3.0">
  <BuildConfiguration modelIdentifier="first">
    <SourceFileSet language="C99">
      <SourceFile name="a.c"/>
      <PreprocessorDefinition name="X" value="1"/>
      <PreprocessorDefinition name="Y"/>
    </SourceFileSet>
  </BuildConfiguration>
  <BuildConfiguration modelIdentifier="second" platform="x86_64-windows"/>
</fmiBuildDescription>
"""


def test_configurations_source_sets_and_lines():
    bd = read_build_description(TWO, "bd.xml")
    assert bd.fmi_version == "3.0" and bd.line == 2
    first, second = bd.configurations
    assert (first.model_identifier, first.platform, first.line) == ("first", None, 3)
    assert (second.model_identifier, second.platform, second.line) == ("second", "x86_64-windows", 10)
    (sources,) = first.source_sets
    assert sources.files == (("a.c", 5),) and sources.line == 4
    assert [(d.name, d.value, d.line) for d in sources.definitions] == [("X", "1", 6), ("Y", None, 7)]
    assert bd.model_identifier == "first"  # the configuration fmpy compile builds


def test_no_identifier_and_malformed_xml_are_located(tmp_path):
    with pytest.raises(RobogenError) as exc:
        read_build_description(b'<fmiBuildDescription fmiVersion="3.0"/>', "bd.xml").model_identifier
    assert str(exc.value.diagnostics[0].message) == "no BuildConfiguration with a modelIdentifier"
    (tmp_path / "sources").mkdir()
    (tmp_path / "sources" / "buildDescription.xml").write_text('<fmiBuildDescription>\n  <Build\n')
    with pytest.raises(RobogenError) as exc:
        model_identifier_of(tmp_path)
    d = exc.value.diagnostics[0]
    assert d.message.startswith("malformed XML") and d.span.path.endswith("buildDescription.xml") and d.span.line >= 2
