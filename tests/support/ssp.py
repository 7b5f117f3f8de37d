"""SSP archives checked against the SSP 2.0 schemas of ../shared (tests skip it where absent)."""

from __future__ import annotations

import zipfile
from pathlib import Path

from lxml import etree

from support import SHARED

SCHEMAS = SHARED / "ssp-2.0" / "schema"
SSV = "http://ssp-standard.org/SSP1/SystemStructureParameterValues"


def validate(ssp: Path) -> None:
    """The archive's SSD against the SSP 2.0 schema, and its inline parameter sets against the
    SSV schema (which the SSD schema leaves lax)."""
    ssd_schema = etree.XMLSchema(etree.parse(str(SCHEMAS / "SystemStructureDescription.xsd")))
    ssv_schema = etree.XMLSchema(etree.parse(str(SCHEMAS / "SystemStructureParameterValues.xsd")))
    root = etree.fromstring(zipfile.ZipFile(ssp).read("SystemStructure.ssd"))
    assert ssd_schema.validate(root), ssd_schema.error_log
    for parameter_set in root.iter(f"{{{SSV}}}ParameterSet"):
        assert ssv_schema.validate(etree.ElementTree(parameter_set)), ssv_schema.error_log
