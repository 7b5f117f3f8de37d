"""robogen's rules of the SSP schemas (robogen.cosim.ssp_schema) against the schemas themselves:
on valid files and on files broken one way each, robogen's verdict is the XSD's (lxml), for SSP
2.0 (../shared/ssp-2.0/schema) and SSP 1.0 (the schemas FMPy installs); and robogen says where."""

from __future__ import annotations

import re
from pathlib import Path

import fmpy
import pytest
import ssp_samples
from lxml import etree
from test_ssp_import import CLOCKS_SSD

from robogen.cosim import ssp_schema
from robogen.cosim.xmltree import parse
from support import SHARED

SCHEMA_2 = SHARED / "ssp-2.0" / "schema"
SCHEMA_1 = Path(fmpy.__file__).parent / "ssp" / "schema"
FILES = {"SSD": "SystemStructureDescription.xsd", "SSV": "SystemStructureParameterValues.xsd",
         "SSM": "SystemStructureParameterMapping.xsd"}

VALID = {
    "clocks (2.0)": ("SSD", CLOCKS_SSD),
    "omsimulator (1.0)": ("SSD", ssp_samples.OMS_SSD),
    "ecos (1.0)": ("SSD", ssp_samples.ECOS_SSD),
    "sample (1.0)": ("SSD", ssp_samples.SAMPLE_SSD),
    "ssv (1.0)": ("SSV", ssp_samples.OMS_SSV),
    "ssv with names (1.0)": ("SSV", ssp_samples.SAMPLE_SSV),
    "ssm (1.0)": ("SSM", ssp_samples.OMS_SSM),
}

#: (file, what to replace, with what): each breaks one rule of the schema
BROKEN = {
    "no name": (CLOCKS_SSD, ' name="relay">\n  <ssd:System', '>\n  <ssd:System'),
    "bad kind": (CLOCKS_SSD, 'name="x_in" kind="input"', 'name="x_in" kind="sideways"'),
    "order": (CLOCKS_SSD, re.compile(r"(    <ssd:Elements>.*?</ssd:Elements>\n)(    <ssd:Connections>.*?</ssd:Connections>\n)", re.S), r"\2\1"),
    "unknown element": (CLOCKS_SSD, "<ssd:Elements>", "<ssd:Bogus/>\n    <ssd:Elements>"),
    "twice": (CLOCKS_SSD, '<ssd:DefaultExperiment startTime="0" stopTime="2">',
              '<ssd:DefaultExperiment/><ssd:DefaultExperiment startTime="0" stopTime="2">'),
    "not a number": (CLOCKS_SSD, 'intervalDecimal="0.25"', 'intervalDecimal="fast"'),
    "unknown attribute": (CLOCKS_SSD, 'name="x_in" kind="input"', 'name="x_in" kind="input" color="red"'),
    "text": (CLOCKS_SSD, "<ssd:Connectors>", "<ssd:Connectors>hello"),
    "version": (CLOCKS_SSD, 'version="2.0"', 'version="3.0"'),
    "empty connectors": (ssp_samples.OMS_SSD, re.compile(r"<ssd:Connectors>\s*<ssd:Connector name=\"counter\".*?</ssd:Connectors>", re.S),
                         "<ssd:Connectors></ssd:Connectors>"),
    "unit without base unit": (ssp_samples.OMS_SSD, '<ssc:BaseUnit m="1" factor="0.01" />', ""),
    "bad factor": (ssp_samples.OMS_SSD, 'factor="2" offset="1"', 'factor="two" offset="1"'),
    "clock in 1.0": (ssp_samples.OMS_SSD, '<ssc:Integer />', '<ssc:Integer />\n            <ssd:Clock name="period" />'),
    "float64 in 1.0": (ssp_samples.OMS_SSD, '<ssc:Real unit="mm" />', '<ssc:Float64 unit="mm" />'),
    "kind local in 1.0": (ssp_samples.OMS_SSD, 'name="result" kind="output"', 'name="result" kind="local"'),
    "boolean map": (ssp_samples.SAMPLE_SSD, '<ssc:MapEntry source="true" target="false"/>', '<ssc:MapEntry source="maybe" target="false"/>'),
    "integer value": (ssp_samples.SAMPLE_SSD, '<ssv:Integer value="42"/>', '<ssv:Integer value="4.2"/>'),
    "two types": (ssp_samples.SAMPLE_SSV, '<ssv:Real value="10"/>', '<ssv:Real value="10"/><ssv:Real value="11"/>'),
    "no parameters": (ssp_samples.OMS_SSV, re.compile(r"<ssv:Parameters>.*</ssv:Parameters>", re.S), ""),
    "mapping entry without target": (ssp_samples.OMS_SSM, 'target="offset" ', ""),
}


def xsd(text: str, what: str) -> bool:
    """The schema's verdict: the 1.0 schema for a file of version 1.x, else the 2.0 one."""
    doc = etree.fromstring(text.encode())
    folder = SCHEMA_1 if doc.get("version", "").startswith("1.") else SCHEMA_2
    schema = etree.XMLSchema(etree.parse(str(folder / FILES[what])))
    if not schema.validate(doc):
        return False
    # what the SSD schema leaves lax, the SSV and SSM schemas check: inline parameter sets and mappings
    for ns, tag, kind in ((ssp_schema.SSV, "ParameterSet", "SSV"), (ssp_schema.SSM, "ParameterMapping", "SSM")):
        for el in list(doc.iter(f"{{{ns}}}{tag}")):
            if el is not doc and not etree.XMLSchema(etree.parse(str(folder / FILES[kind]))).validate(etree.ElementTree(el)):
                return False
    return True


def robogen(text: str, what: str) -> list:
    root, _assumed = parse(text.encode(), "file.xml", ssp_schema.PREFIXES)
    return ssp_schema.check(root, what)


def what_of(text: str) -> str:
    return "SSV" if "<ssv:ParameterSet" in text.split("\n", 2)[1] else "SSM" if "<ssm:ParameterMapping" in text.split("\n", 2)[1] else "SSD"


needs_schemas = pytest.mark.skipif(not SCHEMA_2.is_dir(), reason="../shared/ssp-2.0 is not present")


@needs_schemas
@pytest.mark.parametrize("name", sorted(VALID))
def test_a_valid_file_is_valid_to_both(name):
    what, text = VALID[name]
    assert xsd(text, what)
    assert robogen(text, what) == []


@needs_schemas
@pytest.mark.parametrize("name", sorted(BROKEN))
def test_a_broken_file_is_invalid_to_both(name):
    text, old, new = BROKEN[name]
    broken = old.sub(new, text, count=1) if isinstance(old, re.Pattern) else text.replace(old, new, 1)
    assert broken != text
    what = what_of(broken)
    assert not xsd(broken, what)
    problems = robogen(broken, what)
    assert problems, "robogen's rules accept what the schema refuses"
    assert all(p.span.path == "file.xml" and p.span.line >= 1 for p in problems)


def test_the_problems_are_said_where_they_are():
    text, old, new = BROKEN["bad kind"]
    broken = text.replace(old, new)
    [problem] = robogen(broken, "SSD")
    line = broken[:broken.index('kind="sideways"')].count("\n") + 1
    column = broken.index('kind="sideways"') - broken.rfind("\n", 0, broken.index('kind="sideways"'))
    assert (problem.span.line, problem.span.column) == (line, column)
    text, old, new = BROKEN["order"]
    problems = robogen(old.sub(new, text, count=1), "SSD")
    assert problems[0].message.startswith("<ssd:Elements> is out of order in <ssd:System> (expected here: ")
