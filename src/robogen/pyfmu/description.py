"""modelDescription.xml of a Python-implemented FMU, written from the class's declarations.

Rules followed (../shared/docs/fmi3.md §3): Co-Simulation only, ``hasEventMode`` whenever the
model has clocks, one independent ``time``, constant clocks with ``intervalDecimal`` and an
explicit ``shiftDecimal``, one clock per clocked variable, every output (output clocks
included) under ``<Output>``, unclocked output clocks and calculated outputs as
``<InitialUnknown>``, clocked variables never. The instantiation token is a UUID derived from
the rest of the description, so identical declarations give a byte-identical file.
"""

from __future__ import annotations

import uuid
import xml.etree.ElementTree as ET
from typing import Any

from robogen import __version__
from robogen.pyfmu.model import Clock, Model, Var
from robogen.fmu.fmi import LOG_CATEGORIES

# SI base-unit exponents of the units models commonly declare; others are listed without.
_BASE_UNITS = {
    "s": {"s": "1"},
    "m": {"m": "1"},
    "kg": {"kg": "1"},
    "rad": {"rad": "1"},
    "rad/s": {"rad": "1", "s": "-1"},
    "rad/s2": {"rad": "1", "s": "-2"},
    "m/s": {"m": "1", "s": "-1"},
    "N.m": {"kg": "1", "m": "2", "s": "-2"},
}

_TOKEN_NAMESPACE = uuid.UUID("6c1f4c1e-5b1d-4d0e-9a57-726f626f6765")
_TOKEN_PLACEHOLDER = "{00000000-0000-0000-0000-000000000000}"


def _text(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    return str(value)


def _variable_element(model: type[Model], var: Var) -> ET.Element:
    attrs: dict[str, str] = {"name": var.name, "valueReference": str(var.vr)}
    if var.description:
        attrs["description"] = var.description
    attrs["causality"] = var.causality
    if isinstance(var, Clock):
        attrs["intervalVariability"] = var.kind
        if var.periodic:
            attrs["intervalDecimal"] = _text(model.clock_seconds(var.interval))  # type: ignore[arg-type]
            attrs["shiftDecimal"] = _text(model.clock_seconds(var.shift))
        return ET.Element("Clock", attrs)
    attrs["variability"] = var.variability or ""
    if var.initial is not None and var.causality != "input":
        attrs["initial"] = var.initial
    if var.clock is not None:
        attrs["clocks"] = str(model.variable(var.clock).vr)
    has_start = var.start is not None and var.needs_start
    if has_start and var.type_name != "String":
        attrs["start"] = _text(var.start)
    if var.unit is not None and var.type_name == "Float64":
        attrs["unit"] = var.unit
    element = ET.Element(var.type_name, attrs)
    if has_start and var.type_name == "String":  # a String's start is a child element in FMI 3.0
        ET.SubElement(element, "Start", {"value": var.start})
    return element


def _dependencies(model: type[Model], var: Var) -> dict[str, str]:
    if var.depends_on is None:
        if var.clock is not None:
            return {"dependencies": str(model.variable(var.clock).vr)}
        return {}
    return {"dependencies": " ".join(str(model.variable(n).vr) for n in var.depends_on)}


def model_description(model: type[Model], model_identifier: str) -> str:
    """The modelDescription.xml text for ``model`` (a configured Model subclass)."""
    variables = model.variables()
    has_clocks = any(isinstance(v, Clock) for v in variables)
    root = ET.Element("fmiModelDescription", {
        "fmiVersion": "3.0",
        "modelName": model.model_name or model.__name__,
        "instantiationToken": _TOKEN_PLACEHOLDER,
        **({"description": model.description} if model.description else {}),
        "generationTool": f"robogen {__version__} package-py",
        "variableNamingConvention": "structured",
    })
    cs = {
        "modelIdentifier": model_identifier,
        "canHandleVariableCommunicationStepSize": "true",
        "canBeInstantiatedOnlyOncePerProcess": "false",
    }
    if has_clocks:
        cs["hasEventMode"] = "true"
    if model.might_return_early:
        cs["mightReturnEarlyFromDoStep"] = "true"
    ET.SubElement(root, "CoSimulation", cs)
    units = sorted({v.unit for v in variables if v.unit is not None and v.type_name == "Float64"})
    if units:
        definitions = ET.SubElement(root, "UnitDefinitions")
        for unit in units:
            element = ET.SubElement(definitions, "Unit", {"name": unit})
            if unit in _BASE_UNITS:
                ET.SubElement(element, "BaseUnit", _BASE_UNITS[unit])
    categories = ET.SubElement(root, "LogCategories")
    for name in LOG_CATEGORIES:
        ET.SubElement(categories, "Category", {"name": name})
    if model.default_experiment:
        ET.SubElement(root, "DefaultExperiment", {k: _text(float(v)) for k, v in model.default_experiment.items()})
    mv = ET.SubElement(root, "ModelVariables")
    ET.SubElement(mv, "Float64", {"name": "time", "valueReference": "0", "causality": "independent",
                                  "variability": "continuous", "description": "simulation time"})
    for var in variables:
        mv.append(_variable_element(model, var))
    ms = ET.SubElement(root, "ModelStructure")
    outputs = [v for v in variables if v.causality == "output"]
    for var in outputs:
        ET.SubElement(ms, "Output", {"valueReference": str(var.vr), **_dependencies(model, var)})
    for var in variables:
        initial_unknown = var.clock is None and (
            (var.causality == "output" and (isinstance(var, Clock) or var.initial in ("approx", "calculated")))
            or var.causality == "calculatedParameter")
        if initial_unknown:
            ET.SubElement(ms, "InitialUnknown", {"valueReference": str(var.vr)})
    ET.indent(root, space="  ")
    text = '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"
    token = "{" + str(uuid.uuid5(_TOKEN_NAMESPACE, text)) + "}"
    return text.replace(_TOKEN_PLACEHOLDER, token, 1)


def instantiation_token(description_xml: str) -> str:
    root = ET.fromstring(description_xml)
    return root.attrib["instantiationToken"]
