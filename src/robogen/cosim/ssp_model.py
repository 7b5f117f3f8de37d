"""An SSD file as the elements robogen reads: systems, components, connectors, connections,
parameter bindings, units and enumerations, the default experiment, annotations.

:func:`read_document` turns the tree of a schema-checked SSD (:mod:`robogen.cosim.ssp_schema`)
into these dataclasses, each holding its XML element for the spans of later messages, and reports
what the SSP standard forbids beyond the schema: two elements or connectors of one name, a unit
or enumeration named but not defined. What robogen does not run (components that are not FMUs,
signal dictionaries) is refused here, at the element.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from robogen.cosim.ssp_schema import SSC, SSD
from robogen.cosim.units import SI_BASE_UNITS, UnitDef
from robogen.cosim.xmltree import Element
from robogen.diagnostics import DiagnosticSink, Note, did_you_mean

FMU_TYPE = "application/x-fmu-sharedlibrary"
#: The type choice of a connector: SSP 1.0's generic types and SSP 2.0's FMI 3.0 types.
VALUE_TYPES = ("Real", "Float64", "Float32", "Integer", "Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32", "Int64",
               "UInt64", "Boolean", "String", "Enumeration", "Binary", "Clock")
TRANSFORMATIONS = {"LinearTransformation": "linear", "BooleanMappingTransformation": "boolean",
                   "IntegerMappingTransformation": "integer", "EnumerationMappingTransformation": "enumeration"}
#: A robogen annotation: <ssc:Annotation type="robogen"> holding elements of this namespace.
ROBOGEN_TYPE = "robogen"
ROBOGEN_NS = "urn:robogen:ssp"


@dataclass
class Connector:
    name: str
    kind: str
    type: str | None  # one of VALUE_TYPES, or None (not given)
    el: Element
    unit: str | None = None
    clock: Element | None = None  # the <ssc:Clock> type element: variability, interval, shift
    clocks: list[tuple[str, Element]] = field(default_factory=list)  # <ssd:Clock name=...>: its clocks


@dataclass
class Transformation:
    kind: str  # linear, boolean, integer, enumeration
    el: Element
    factor: float = 1.0
    offset: float = 0.0
    entries: dict = field(default_factory=dict)  # source -> target (mapping transformations)


@dataclass
class Connection:
    start: tuple[str | None, str]  # (element or None for the system's own connector, connector)
    end: tuple[str | None, str]
    el: Element
    transformation: Transformation | None = None
    suppress_units: bool = False


@dataclass
class Binding:
    el: Element
    source: str | None
    source_base: str
    prefix: str
    values: Element | None  # an inline <ssv:ParameterSet>
    mapping: Element | None = None  # the <ssd:ParameterMapping> element (inline content or source)


@dataclass
class Component:
    name: str
    el: Element
    source: str
    implementation: str
    connectors: dict[str, Connector]
    bindings: list[Binding]
    annotations: list[Element]  # the robogen annotations' content elements


@dataclass
class SystemNode:
    name: str
    el: Element
    connectors: dict[str, Connector]
    bindings: list[Binding]
    elements: dict[str, Component | SystemNode]
    connections: list[Connection]


@dataclass
class Document:
    version: str
    name: str
    root: SystemNode
    units: dict[str, UnitDef]
    el: Element
    experiment: Element | None  # <ssd:DefaultExperiment>
    settings: list[Element]  # the content of its robogen annotations


def read_document(root: Element, sink: DiagnosticSink) -> Document:
    """The SSD of ``root`` (schema-checked); every problem into ``sink``."""
    units = read_units(root.find(SSD, "Units"), sink)
    reader = _Reader(sink, units)
    system = reader.system(root.find(SSD, "System"))
    experiment = root.find(SSD, "DefaultExperiment")
    settings = robogen_annotations(experiment.find(SSD, "Annotations") if experiment is not None else None)
    return Document(root.get("version", ""), root.get("name", ""), system, units, root, experiment, settings)


def read_units(el: Element | None, sink: DiagnosticSink) -> dict[str, UnitDef]:
    """The ``<ssc:Unit>`` definitions under ``el`` (an SSD's or SSV's ``<Units>``), by name."""
    units: dict[str, UnitDef] = {}
    for unit in el.findall(SSC, "Unit") if el is not None else ():
        base = unit.find(SSC, "BaseUnit")
        name = unit.get("name", "")
        if name in units:
            sink.error(f"unit '{name}' is defined twice", unit.at("name"))
        exponents = tuple(int(base.get(k, "0")) for k in SI_BASE_UNITS) if base is not None else None
        factor = float(base.get("factor", "1")) if base is not None else 1.0
        offset = float(base.get("offset", "0")) if base is not None else 0.0
        units[name] = UnitDef(name, exponents, factor, offset)
    return units


def robogen_annotations(el: Element | None) -> list[Element]:
    """The content elements of the robogen annotations under ``el`` (an ``<Annotations>``); other
    tools' annotations are theirs (docs/ssp.md)."""
    return [child for annotation in (el.findall(SSC, "Annotation") if el is not None else ())
            if annotation.get("type") == ROBOGEN_TYPE for child in annotation.children]


def transformation(el: Element) -> Transformation | None:
    """The transformation among the children of ``el`` (a connection or a mapping entry), if any."""
    for child in el.children:
        kind = TRANSFORMATIONS.get(child.tag) if child.ns == SSC else None
        if kind == "linear":
            return Transformation(kind, child, float(child.get("factor", "1")), float(child.get("offset", "0")))
        if kind is not None:
            entries = {e.get("source", ""): e.get("target", "") for e in child.findall(SSC, "MapEntry")}
            return Transformation(kind, child, entries=entries)
    return None


class _Reader:
    def __init__(self, sink: DiagnosticSink, units: dict[str, UnitDef]):
        self.sink, self.units = sink, units

    def system(self, el: Element) -> SystemNode:
        elements: dict[str, Component | SystemNode] = {}
        for child in (c for group in el.findall(SSD, "Elements") for c in group.children):
            name = child.get("name", "")
            if name in elements:
                self.sink.error(f"two elements of system '{el.get('name')}' are named '{name}'", child.at("name"),
                                Note("the first is here", elements[name].el.span))
                continue
            if child.tag == "System":
                elements[name] = self.system(child)
            elif child.tag == "Component":
                component = self.component(child)
                if component is not None:
                    elements[name] = component
            else:
                self.sink.error("signal dictionaries are not supported: robogen runs systems of FMUs (connect the "
                                "FMUs to each other, or through a system's connectors)", child.span)
        connections = [self.connection(c) for c in el.path(SSD, "Connections", "Connection")]
        return SystemNode(el.get("name", ""), el, self.connectors(el), self.bindings(el), elements, connections)

    def component(self, el: Element) -> Component | None:
        kind = el.get("type", FMU_TYPE)
        if kind != FMU_TYPE:
            what = {"application/x-ssp-definition": "an SSD file", "application/x-ssp-package": "an SSP archive"}.get(kind)
            self.sink.error(f"component '{el.get('name')}' is {what or repr(kind)}: robogen runs components of type "
                            f"{FMU_TYPE} (FMUs) and nested <ssd:System> elements", el.at("type"))
            return None
        if el.get("source") is None:
            self.sink.error(f"component '{el.get('name')}' has no source: a component without an FMU describes an "
                            "architecture, which cannot be simulated", el.span)
            return None
        annotations = robogen_annotations(el.find(SSD, "Annotations"))
        return Component(el.get("name", ""), el, el.get("source", ""), el.get("implementation", "any"),
                         self.connectors(el), self.bindings(el), annotations)

    def connectors(self, el: Element) -> dict[str, Connector]:
        found: dict[str, Connector] = {}
        for c in el.path(SSD, "Connectors", "Connector"):
            name = c.get("name", "")
            if name in found:
                self.sink.error(f"'{el.get('name')}' has two connectors named '{name}'", c.at("name"),
                                Note("the first is here", found[name].el.span))
                continue
            typed = next((t for t in c.children if t.ns == SSC and t.tag in VALUE_TYPES), None)
            connector = Connector(name, c.get("kind", ""), typed.tag if typed is not None else None, c)
            if typed is not None:
                connector.unit = typed.get("unit")
                if connector.unit is not None and connector.unit not in self.units:
                    self.sink.error(f"unit '{connector.unit}' is not defined in the file's <ssd:Units>"
                                    f"{did_you_mean(connector.unit, self.units)}", typed.at("unit"))
                    connector.unit = None
                if typed.tag == "Clock":
                    connector.clock = typed
            connector.clocks = [(k.get("name", ""), k) for k in c.findall(SSD, "Clock")]
            found[name] = connector
        return found

    def bindings(self, el: Element) -> list[Binding]:
        found = []
        for b in el.path(SSD, "ParameterBindings", "ParameterBinding"):
            kind = b.get("type", "application/x-ssp-parameter-set")
            values = b.find(SSD, "ParameterValues")
            inline = [c for c in values.children] if values is not None else []
            if kind != "application/x-ssp-parameter-set":
                self.sink.error(f"parameter bindings of type '{kind}' are not supported (only SSP parameter sets, "
                                "application/x-ssp-parameter-set)", b.at("type"))
                continue
            if (b.get("source") is None) == (not inline):
                self.sink.error("a parameter binding gives its values either in a source file or inline in "
                                "<ssd:ParameterValues>, and one of them", b.span)
                continue
            found.append(Binding(b, b.get("source"), b.get("sourceBase", "SSD"), b.get("prefix", ""),
                                 inline[0] if inline else None, b.find(SSD, "ParameterMapping")))
        return found

    def connection(self, el: Element) -> Connection:
        for attr in ("startIndices", "endIndices"):
            if attr in el.attrib:
                self.sink.error("connections of single array elements are not supported: robogen connects whole "
                                "variables", el.at(attr))
        transform = transformation(el)
        return Connection((el.get("startElement"), el.get("startConnector", "")), (el.get("endElement"), el.get("endConnector", "")),
                          el, transform, el.get("suppressUnitConversion") in ("true", "1"))
