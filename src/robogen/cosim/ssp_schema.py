"""The SSP 2.0 XML schemas' rules, as robogen checks them on the SSD, SSV and SSM files it reads.

The schemas (System Structure and Parameterization 2.0, Modelica Association) cannot ship with
robogen, and lxml reports a violation at a line but not at its column, so the rules that matter
are written here as data: per element, its attributes (with their types, and which are
required) and its content model (a sequence of positions, each a choice of elements with
bounds); :func:`check` walks a tree of :mod:`robogen.cosim.xmltree` and reports every violation
at the element or attribute. A file that says ``version="1.0"`` must also keep to SSP 1.0: an
element, attribute or value that SSP 2.0 added is reported as such. Content the schemas leave
open (annotations, signal dictionaries, meta data) is not looked into; the SSV and SSM content of
``<ParameterValues>`` and ``<ParameterMapping>`` is. tests/cosim/test_ssp_schema.py holds these
rules against the schemas themselves (../shared/ssp-2.0/schema, and FMPy's SSP 1.0 schemas).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from robogen.cosim.xmltree import Element
from robogen.diagnostics import Diagnostic, error, warning

SSD = "http://ssp-standard.org/SSP1/SystemStructureDescription"
SSC = "http://ssp-standard.org/SSP1/SystemStructureCommon"
SSV = "http://ssp-standard.org/SSP1/SystemStructureParameterValues"
SSM = "http://ssp-standard.org/SSP1/SystemStructureParameterMapping"
SSB = "http://ssp-standard.org/SSP1/SystemStructureSignalDictionary"
XSI = "http://www.w3.org/2001/XMLSchema-instance"
XML = "http://www.w3.org/XML/1998/namespace"
PREFIX = {SSD: "ssd", SSC: "ssc", SSV: "ssv", SSM: "ssm", SSB: "ssb"}
#: The namespaces of the prefixes SSP files use (for files that use them without declaring them)
PREFIXES = {prefix: ns for ns, prefix in PREFIX.items()}

_DOUBLE = r"[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?|[+-]?INF|NaN"
_INTEGER = r"[+-]?\d+"
_PATTERNS = {
    "double": _DOUBLE, "float": _DOUBLE, "boolean": r"true|false|1|0", "hex": r"([0-9a-fA-F]{2})*",
    "dateTime": r"-?\d{4,}-\d\d-\d\dT\d\d:\d\d:\d\d(\.\d+)?(Z|[+-]\d\d:\d\d)?",
}
#: integer types: (smallest, largest)
_RANGES = {
    "byte": (-2**7, 2**7 - 1), "unsignedByte": (0, 2**8 - 1), "short": (-2**15, 2**15 - 1),
    "unsignedShort": (0, 2**16 - 1), "int": (-2**31, 2**31 - 1), "unsignedInt": (0, 2**32 - 1),
    "long": (-2**63, 2**63 - 1), "unsignedLong": (0, 2**64 - 1), "generic": (-2**63, 2**64 - 1),
}
VERSIONS = ("1.0", "2.0")


@dataclass(frozen=True)
class Attr:
    type: str | tuple[str, ...] = "string"  # a type name, or the values allowed
    required: bool = False
    list: bool = False  # a whitespace-separated list of values of the type
    since: tuple[str, ...] = ()  # values (or, with "*", the attribute) that SSP 2.0 added


@dataclass(frozen=True)
class Rule:
    attrs: dict[str, Attr] = field(default_factory=dict)
    #: the content: a sequence of (elements allowed here, at least, at most); "*" allows any element
    content: tuple[tuple[tuple, int, float], ...] = ()
    since_2: bool = False  # an element SSP 2.0 added
    open: bool = False  # content left to other schemas: not looked into


def q(ns: str, *tags: str) -> tuple:
    return tuple((ns, t) for t in tags)


INF = float("inf")
ANY = ("*",)
BASE = {"id": Attr(), "description": Attr()}
TOP = {**BASE, "author": Attr(), "fileversion": Attr(), "copyright": Attr(), "license": Attr(),
       "generationTool": Attr(), "generationDateAndTime": Attr("dateTime")}
VERSION = {"version": Attr("version", required=True)}
SOURCE = {"type": Attr(), "source": Attr(), "sourceBase": Attr(("SSD", "component"))}
META = (q(SSC, "MetaData"), 0, INF)
SIGNATURE = (q(SSC, "Signature"), 0, INF)
TYPES_1 = ("Real", "Integer", "Boolean", "String", "Enumeration", "Binary")
TYPES_2 = ("Float64", "Float32", "Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32", "Int64", "UInt64", "Clock")
KINDS_2 = ("constant", "local", "structuralParameter", "unspecified")
VARIABILITY = ("constant", "fixed", "tunable", "changing", "countdown", "triggered")
TRANSFORMATIONS = q(SSC, "LinearTransformation", "BooleanMappingTransformation", "IntegerMappingTransformation",
                    "EnumerationMappingTransformation")
GEOMETRY = {"x1": Attr("double", True), "y1": Attr("double", True), "x2": Attr("double", True), "y2": Attr("double", True)}


def _annotations(ns: str) -> tuple:
    return (q(ns, "Annotations"), 0, 1)


#: TElement's sequence, which a component's and a system's continue
ELEMENT = ((q(SSD, "Connectors"), 0, 1), (q(SSD, "ElementGeometry"), 0, 1), (q(SSD, "ParameterBindings"), 0, 1), META, SIGNATURE)


_VALUE_TYPES = {  # ssv value elements: their value's type
    "Real": "double", "Float64": "double", "Float32": "float", "Integer": "int", "Int8": "byte", "UInt8": "unsignedByte",
    "Int16": "short", "UInt16": "unsignedShort", "Int32": "int", "UInt32": "unsignedInt", "Int64": "long",
    "UInt64": "unsignedLong", "Boolean": "boolean",
}


def _rules() -> dict[tuple[str, str], Rule]:
    r: dict[tuple[str, str], Rule] = {}
    element = ELEMENT
    r[SSD, "SystemStructureDescription"] = Rule(
        {**TOP, **VERSION, "name": Attr(required=True)},
        ((q(SSD, "System"), 1, 1), (q(SSD, "Enumerations"), 0, 1), (q(SSD, "Units"), 0, 1),
         (q(SSD, "DefaultExperiment"), 0, 1), META, SIGNATURE, _annotations(SSD)))
    r[SSD, "System"] = Rule(
        {**BASE, "name": Attr(required=True)},
        element + ((q(SSD, "Elements"), 0, 1), (q(SSD, "Connections"), 0, 1), (q(SSD, "SignalDictionaries"), 0, 1),
                   (q(SSD, "SystemGeometry"), 0, 1), (q(SSD, "GraphicalElements"), 0, 1), _annotations(SSD)))
    r[SSD, "Elements"] = Rule({}, ((q(SSD, "Component", "SignalDictionaryReference", "System"), 0, INF),))
    r[SSD, "Component"] = Rule(
        {**BASE, "name": Attr(required=True), "type": Attr(), "source": Attr(),
         "implementation": Attr(("any", "ModelExchange", "CoSimulation", "ScheduledExecution"), since=("ScheduledExecution",))},
        element + (_annotations(SSD),))
    r[SSD, "SignalDictionaryReference"] = Rule({**BASE, "name": Attr(required=True), "dictionary": Attr(required=True)},
                                               element + (_annotations(SSD),))
    r[SSD, "Connectors"] = Rule({}, ((q(SSD, "Connector"), 1, INF),))
    r[SSD, "Connector"] = Rule(
        {**BASE, "name": Attr(required=True),
         "kind": Attr(("input", "output", "parameter", "calculatedParameter", "inout") + KINDS_2, True, since=KINDS_2)},
        ((q(SSC, *TYPES_1, *TYPES_2), 0, 1), (q(SSC, "Dimension"), 0, INF), (q(SSD, "Clock"), 0, INF),
         (q(SSD, "ConnectorGeometry"), 0, 1), _annotations(SSD)))
    r[SSD, "Clock"] = Rule({"name": Attr(required=True)}, since_2=True)
    r[SSD, "ConnectorGeometry"] = Rule({"x": Attr("double", True), "y": Attr("double", True),
                                        "systemInnerX": Attr("double", since=("*",)), "systemInnerY": Attr("double", since=("*",))})
    r[SSD, "ElementGeometry"] = Rule({**GEOMETRY, "rotation": Attr("double"), "iconSource": Attr(), "iconRotation": Attr("double"),
                                      "iconFlip": Attr("boolean"), "iconFixedAspectRatio": Attr("boolean")})
    r[SSD, "SystemGeometry"] = Rule(dict(GEOMETRY))
    r[SSD, "GraphicalElements"] = Rule({}, ((q(SSD, "Note"), 1, INF),))
    r[SSD, "Note"] = Rule({**GEOMETRY, "text": Attr(required=True)})
    r[SSD, "SignalDictionaries"] = Rule(open=True)
    r[SSD, "ParameterBindings"] = Rule({}, ((q(SSD, "ParameterBinding"), 1, INF),))
    r[SSD, "ParameterBinding"] = Rule(
        {**BASE, **SOURCE, "prefix": Attr()},
        ((q(SSD, "ParameterValues"), 0, 1), (q(SSD, "ParameterMapping"), 0, 1), META, SIGNATURE, _annotations(SSD)))
    r[SSD, "ParameterValues"] = Rule({}, ((ANY, 0, INF),))
    r[SSD, "ParameterMapping"] = Rule({**BASE, **SOURCE}, ((ANY, 0, INF),))
    r[SSD, "Connections"] = Rule({}, ((q(SSD, "Connection"), 1, INF),))
    r[SSD, "Connection"] = Rule(
        {**BASE, "startElement": Attr(), "startConnector": Attr(required=True), "endElement": Attr(),
         "endConnector": Attr(required=True), "suppressUnitConversion": Attr("boolean"),
         "startIndices": Attr("unsignedLong", list=True, since=("*",)), "endIndices": Attr("unsignedLong", list=True, since=("*",))},
        ((TRANSFORMATIONS, 0, 1), (q(SSD, "ConnectionGeometry"), 0, 1), _annotations(SSD)))
    r[SSD, "ConnectionGeometry"] = Rule({"pointsX": Attr("double", True, True), "pointsY": Attr("double", True, True)})
    r[SSD, "DefaultExperiment"] = Rule({"startTime": Attr("double"), "stopTime": Attr("double")}, (_annotations(SSD),))
    for ns in (SSD, SSV):
        r[ns, "Enumerations"] = Rule({}, ((q(SSC, "Enumeration"), 1, INF),))
        r[ns, "Units"] = Rule({}, ((q(SSC, "Unit"), 1, INF),))
        r[ns, "Annotations"] = Rule({}, ((q(SSC, "Annotation"), 1, INF),))
    r[SSM, "Annotations"] = Rule({}, ((q(SSC, "Annotation"), 1, INF),))
    _common(r)
    _parameter_values(r)
    r[SSM, "ParameterMapping"] = Rule({**TOP, **VERSION}, ((q(SSM, "MappingEntry"), 0, INF), META, SIGNATURE, _annotations(SSM)))
    r[SSM, "MappingEntry"] = Rule({**BASE, "source": Attr(required=True), "target": Attr(required=True),
                                   "suppressUnitConversion": Attr("boolean")}, ((TRANSFORMATIONS, 0, 1), _annotations(SSM)))
    return r


def _common(r: dict) -> None:
    """The elements of SystemStructureCommon."""
    for tag in ("Real", "Float64", "Float32"):
        r[SSC, tag] = Rule({"unit": Attr()}, since_2=tag != "Real")
    for tag in ("Integer", "Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32", "Int64", "UInt64", "Boolean", "String"):
        r[SSC, tag] = Rule({}, since_2=tag not in TYPES_1)
    r[SSC, "Enumeration"] = Rule({"name": Attr(required=True)})  # a connector's type; in <Enumerations>: DEFINITION
    r[SSC, "Item"] = Rule({"name": Attr(required=True), "value": Attr("long", True)})
    r[SSC, "Binary"] = Rule({"mime-type": Attr()})
    r[SSC, "Clock"] = Rule({"intervalVariability": Attr(VARIABILITY), "intervalDecimal": Attr("double"),
                            "shiftDecimal": Attr("double"), "supportsFraction": Attr("boolean"),
                            "resolution": Attr("unsignedLong"), "intervalCounter": Attr("unsignedLong"),
                            "shiftCounter": Attr("unsignedLong"), "priority": Attr("unsignedInt")}, since_2=True)
    r[SSC, "Dimension"] = Rule({"size": Attr("unsignedLong"), "sizeConnector": Attr()}, since_2=True)
    r[SSC, "Unit"] = Rule({**BASE, "name": Attr(required=True)}, ((q(SSC, "BaseUnit"), 1, 1), (q(SSC, "Annotations"), 0, 1)))
    r[SSC, "BaseUnit"] = Rule({**{k: Attr("int") for k in ("kg", "m", "s", "A", "K", "mol", "cd", "rad")},
                               "factor": Attr("double"), "offset": Attr("double")})
    r[SSC, "Annotations"] = Rule({}, ((q(SSC, "Annotation"), 1, INF),))
    r[SSC, "Annotation"] = Rule({"type": Attr(required=True)}, open=True)
    r[SSC, "MetaData"] = Rule(open=True, since_2=True)
    r[SSC, "Signature"] = Rule(open=True, since_2=True)
    r[SSC, "LinearTransformation"] = Rule({"factor": Attr("double"), "offset": Attr("double")})
    for tag in ("Boolean", "Integer", "Enumeration"):
        r[SSC, f"{tag}MappingTransformation"] = Rule({}, ((q(SSC, "MapEntry"), 1, INF),))
    r[SSC, "MapEntry"] = Rule({"source": Attr(required=True), "target": Attr(required=True)})  # typed by its parent


def _parameter_values(r: dict) -> None:
    r[SSV, "ParameterSet"] = Rule({**TOP, **VERSION, "name": Attr(required=True)},
                                  ((q(SSV, "Parameters"), 1, 1), (q(SSV, "Enumerations"), 0, 1), (q(SSV, "Units"), 0, 1),
                                   META, SIGNATURE, _annotations(SSV)))
    r[SSV, "Parameters"] = Rule({}, ((q(SSV, "Parameter"), 0, INF),))
    r[SSV, "Parameter"] = Rule({**BASE, "name": Attr(required=True)},
                               ((q(SSV, *_VALUE_TYPES, "String", "Enumeration", "Binary"), 1, 1), (q(SSC, "Dimension"), 0, INF),
                                _annotations(SSV)))
    for tag, kind in _VALUE_TYPES.items():
        attrs = {"value": Attr(kind, True, True)}
        if tag in ("Real", "Float64", "Float32"):
            attrs["unit"] = Attr()
        r[SSV, tag] = Rule(attrs, since_2=tag not in TYPES_1)
    r[SSV, "String"] = Rule({"value": Attr()}, ((q(SSV, "Value"), 0, INF),))
    r[SSV, "Enumeration"] = Rule({"value": Attr(), "name": Attr()}, ((q(SSV, "Value"), 0, INF),))
    r[SSV, "Binary"] = Rule({"value": Attr("hex"), "mime-type": Attr()}, ((q(SSV, "Value"), 0, INF),))
    r[SSV, "Value"] = Rule({"value": Attr(required=True)}, since_2=True)


RULES = _rules()
#: An enumeration's definition, in an SSD's or SSV's <Enumerations> (elsewhere <ssc:Enumeration> is a type)
DEFINITION = Rule({**BASE, "name": Attr(required=True)}, ((q(SSC, "Item"), 1, INF), (q(SSC, "Annotations"), 0, 1)))
#: The type of a MapEntry's source and target, by its transformation.
MAP_ENTRY_TYPES = {"BooleanMappingTransformation": "boolean", "IntegerMappingTransformation": "generic",
                   "EnumerationMappingTransformation": "string"}
ROOTS = {(SSD, "SystemStructureDescription"): "SSD", (SSV, "ParameterSet"): "SSV", (SSM, "ParameterMapping"): "SSM"}


def assumed_prefixes(prefixes: list[str], span) -> Diagnostic:
    """The warning for a file that uses SSP's prefixes without declaring their namespaces."""
    return warning(f"the file uses the prefix{'es' if len(prefixes) > 1 else ''} {', '.join(repr(p) for p in prefixes)} "
                   f"without declaring {'their namespaces' if len(prefixes) > 1 else 'its namespace'} (xmlns:...); read as "
                   "SSP's", span)


def check(root: Element, what: str) -> list[Diagnostic]:
    """Every violation of the SSP schemas in the document ``root`` (an SSD, SSV or SSM file, as
    ``what`` says)."""
    kind = ROOTS.get((root.ns, root.tag))
    if kind != what:
        expected = next(f"<{PREFIX[ns]}:{tag}>" for (ns, tag), k in ROOTS.items() if k == what)
        return [error(f"an {what} file's root element is {expected} in namespace {_ns_of(what)}, not {_name(root)}", root.span)]
    version = root.get("version", "")
    found: list[Diagnostic] = []
    _Walk(found, "1.0" if re.fullmatch(r"1\.\d+(-.*)?", version) else "2.0").element(root)
    return found


def _ns_of(what: str) -> str:
    return {"SSD": SSD, "SSV": SSV, "SSM": SSM}[what]


def _name(el: Element) -> str:
    prefix = PREFIX.get(el.ns)
    return f"<{prefix}:{el.tag}>" if prefix else (f"<{el.tag}> (namespace {el.ns})" if el.ns else f"<{el.tag}> (no namespace)")


class _Walk:
    def __init__(self, found: list[Diagnostic], version: str):
        self.found, self.version = found, version

    def error(self, message: str, span) -> None:
        self.found.append(error(message, span))

    def element(self, el: Element) -> None:
        rule = RULES.get((el.ns, el.tag))
        if (el.ns, el.tag) == (SSC, "Enumeration") and el.parent is not None and el.parent.tag == "Enumerations":
            rule = DEFINITION
        if rule is None:
            return  # reached only through an open position: another schema's element
        if rule.since_2 and self.version == "1.0":
            self.error(f"{_name(el)} is SSP 2.0; this file says version=\"{self.version}\" (SSP 1.0)", el.span)
        self.attributes(el, rule)
        if rule.open:
            return
        self.content(el, rule)
        for child in el.children:
            self.element(child)

    def attributes(self, el: Element, rule: Rule) -> None:
        for name, spec in rule.attrs.items():
            if spec.required and name not in el.attrib:
                self.error(f"{_name(el)} needs the attribute '{name}'", el.span)
        for name, value in el.attrib.items():
            if name.startswith(("{" + XSI + "}", "{" + XML + "}")):
                continue
            spec = rule.attrs.get(name)
            if el.tag == "MapEntry" and el.parent is not None and name in ("source", "target"):
                spec = Attr(MAP_ENTRY_TYPES.get(el.parent.tag, "string"))
            if spec is None:
                self.error(f"{_name(el)} has no attribute '{name}'", el.at(name))
            else:
                self.value(el, name, value, spec)

    def value(self, el: Element, name: str, value: str, spec: Attr) -> None:
        if self.version == "1.0" and ("*" in spec.since or value in spec.since):
            what = f"attribute '{name}'" if "*" in spec.since else f"{name}=\"{value}\""
            self.error(f"{_name(el)}: {what} is SSP 2.0; this file says version=\"{self.version}\" (SSP 1.0)", el.at(name))
            return
        items = value.split() if spec.list else [value]
        for item in items:
            problem = _problem(item, spec.type, self.version)
            if problem:
                self.error(f"{_name(el)}: {name}=\"{value}\" {problem}", el.at(name))
                return

    def content(self, el: Element, rule: Rule) -> None:
        counts = [0] * len(rule.content)
        position = 0
        for child in el.children:
            at = next((i for i in range(position, len(rule.content)) if _allows(rule.content[i][0], child)), None)
            if at is None:
                earlier = any(_allows(names, child) for names, _lo, _hi in rule.content)
                where = "is out of order" if earlier else "is not allowed"
                self.error(f"{_name(child)} {where} in {_name(el)}{_expected(rule, position)}", child.span)
                continue
            if counts[at] >= rule.content[at][2]:
                self.error(f"{_name(el)} has more than {int(rule.content[at][2])} {_name(child)}", child.span)
            counts[at] += 1
            position = at
        for (names, low, _high), n in zip(rule.content, counts):
            if n < low and names != ANY:
                self.error(f"{_name(el)} needs {' or '.join(f'<{PREFIX[ns]}:{t}>' for ns, t in names)}", el.span)
        if el.text.strip() and el.tag != "Annotation":
            self.error(f"{_name(el)} holds text, which the SSP schemas do not allow there", el.span)


def _allows(names: tuple, child: Element) -> bool:
    return names == ANY or (child.ns, child.tag) in names


def _expected(rule: Rule, position: int) -> str:
    names = [f"<{PREFIX[ns]}:{t}>" for names, _lo, _hi in rule.content[position:] if names != ANY for ns, t in names]
    return f" (expected here: {', '.join(names[:6])}{', ...' if len(names) > 6 else ''})" if names else " (it allows no elements)"


def _problem(value: str, kind, version: str) -> str | None:
    """Why ``value`` is not of the attribute type ``kind`` (None: it is)."""
    if isinstance(kind, tuple):
        return None if value in kind else f"is not one of {', '.join(repr(k) for k in kind)}"
    if kind == "version":
        ok = value in VERSIONS or re.fullmatch(r"1\.\d+(-.*)?", value)
        return None if ok else "is not an SSP version (\"1.0\" or \"2.0\")"
    if kind in _RANGES:
        if not re.fullmatch(_INTEGER, value.strip()):
            return "is not an integer"
        low, high = _RANGES[kind]
        return None if low <= int(value) <= high else f"is out of range ({low} to {high})"
    pattern = _PATTERNS.get(kind)
    if pattern is not None and not re.fullmatch(pattern, value.strip()):
        return {"double": "is not a number", "float": "is not a number", "boolean": "is not true or false",
                "hex": "is not hexadecimal bytes", "dateTime": "is not a date and time (xs:dateTime)"}[kind]
    return None
