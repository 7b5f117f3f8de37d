"""Reading ``modelDescription.xml`` of an FMI 3.0 FMU into plain dataclasses.

The parser never expands entities, never loads a DTD and never touches the network (a
third-party FMU is untrusted input). Every element keeps its source line so that the master
and the validator can point at it. Only what robogen uses is read: the Co-Simulation interface,
the default experiment, the variables (clocks with their timing attributes) and the model
structure.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from lxml import etree

from robogen.diagnostics import RobogenError, Span

TYPE_TAGS = (
    "Float32", "Float64", "Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32", "Int64", "UInt64",
    "Boolean", "String", "Binary", "Enumeration", "Clock",
)
MAX_XML_BYTES = 64 * 1024 * 1024


@dataclass(frozen=True)
class Variable:
    name: str
    value_reference: int
    type: str  # one of TYPE_TAGS
    causality: str = "local"
    variability: str = "continuous"
    initial: str | None = None
    start: str | None = None  # the raw attribute text
    clocks: tuple[int, ...] = ()
    declared_type: str | None = None
    previous: int | None = None
    # Clock attributes (type == "Clock")
    interval_variability: str | None = None
    interval: float | None = None
    shift: float | None = None
    can_be_deactivated: bool = False
    attributes: dict = field(default_factory=dict, compare=False, hash=False)
    line: int = 0

    @property
    def is_clock(self) -> bool:
        return self.type == "Clock"

    @property
    def is_clocked(self) -> bool:
        return bool(self.clocks)


@dataclass(frozen=True)
class CoSimulation:
    model_identifier: str
    has_event_mode: bool = False
    can_handle_variable_step: bool = False
    might_return_early: bool = False
    can_get_and_set_state: bool = False
    fixed_internal_step: float | None = None
    attributes: dict = field(default_factory=dict, compare=False, hash=False)
    line: int = 0


@dataclass(frozen=True)
class Unknown:
    kind: str  # Output, ContinuousStateDerivative, ClockedState, InitialUnknown, EventIndicator
    value_reference: int
    dependencies: tuple[int, ...] | None
    line: int = 0


@dataclass(frozen=True)
class ModelDescription:
    fmi_version: str
    model_name: str
    instantiation_token: str
    co_simulation: CoSimulation | None
    variables: tuple[Variable, ...]
    unknowns: tuple[Unknown, ...] = ()
    start_time: float | None = None
    stop_time: float | None = None
    step_size: float | None = None
    has_model_exchange: bool = False
    has_scheduled_execution: bool = False
    path: str = "modelDescription.xml"

    def by_name(self) -> dict[str, Variable]:
        return {v.name: v for v in self.variables}

    def by_vr(self) -> dict[int, Variable]:
        return {v.value_reference: v for v in self.variables}

    def span(self, line: int) -> Span:
        return Span.point(self.path, max(line, 1))


def safe_parser() -> etree.XMLParser:
    """An lxml parser that resolves no entities, loads no DTD and uses no network."""
    return etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False, dtd_validation=False, huge_tree=False, remove_comments=False)


def parse_xml(data: bytes, display_path: str) -> etree._ElementTree:
    if len(data) > MAX_XML_BYTES:
        raise RobogenError.at(f"modelDescription.xml is larger than {MAX_XML_BYTES} bytes", Span.whole_file(display_path))
    if b"<!DOCTYPE" in data[:4096] or b"<!ENTITY" in data:
        raise RobogenError.at("modelDescription.xml declares a DOCTYPE or entities, which FMI does not allow", Span.whole_file(display_path))
    try:
        return etree.ElementTree(etree.fromstring(data, safe_parser()))
    except etree.XMLSyntaxError as exc:
        line, col = exc.position if exc.position else (1, 1)
        raise RobogenError.at(f"malformed XML: {exc.msg}", Span.point(display_path, line or 1, (col or 0) + 1)) from None


def _bool(value: str | None) -> bool:
    return value in ("true", "1")


def _float(value: str | None, what: str, where: Span) -> float | None:
    if value is None:
        return None
    try:
        return float(value)
    except ValueError:
        raise RobogenError.at(f"{what}: '{value}' is not a number", where) from None


def _int(value: str | None, what: str, where: Span) -> int:
    try:
        return int(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise RobogenError.at(f"{what}: '{value}' is not an integer", where) from None


def _vr_list(value: str | None, what: str, where: Span) -> tuple[int, ...]:
    if value is None:
        return ()
    try:
        return tuple(int(x) for x in value.split())
    except ValueError:
        raise RobogenError.at(f"{what}: '{value}' is not a list of value references", where) from None


def read_model_description(data: bytes, display_path: str = "modelDescription.xml") -> ModelDescription:
    """Parse the bytes of a modelDescription.xml. Raises RobogenError with a location."""
    root = parse_xml(data, display_path).getroot()

    def at(el) -> Span:
        return Span.point(display_path, el.sourceline or 1)

    if root.tag != "fmiModelDescription":
        raise RobogenError.at(f"root element is <{root.tag}>, expected <fmiModelDescription>", at(root))
    version = root.get("fmiVersion", "")
    if not version.startswith("3."):
        raise RobogenError.at(f"fmiVersion is '{version}': robogen imports FMI 3.0 only", at(root))

    cs = None
    el = root.find("CoSimulation")
    if el is not None:
        cs = CoSimulation(
            model_identifier=el.get("modelIdentifier", ""),
            has_event_mode=_bool(el.get("hasEventMode")),
            can_handle_variable_step=_bool(el.get("canHandleVariableCommunicationStepSize")),
            might_return_early=_bool(el.get("mightReturnEarlyFromDoStep")),
            can_get_and_set_state=_bool(el.get("canGetAndSetFMUState")),
            fixed_internal_step=_float(el.get("fixedInternalStepSize"), "fixedInternalStepSize", at(el)),
            attributes=dict(el.attrib),
            line=el.sourceline or 0,
        )

    start = stop = step = None
    de = root.find("DefaultExperiment")
    if de is not None:
        start = _float(de.get("startTime"), "startTime", at(de))
        stop = _float(de.get("stopTime"), "stopTime", at(de))
        step = _float(de.get("stepSize"), "stepSize", at(de))

    variables: list[Variable] = []
    mv = root.find("ModelVariables")
    for v in (mv if mv is not None else []):
        if not isinstance(v.tag, str) or v.tag not in TYPE_TAGS:
            continue
        where = at(v)
        a = v.attrib
        prev = a.get("previous")
        variables.append(Variable(
            name=a.get("name", ""),
            value_reference=_int(a.get("valueReference"), "valueReference", where),
            type=v.tag,
            causality=a.get("causality", "local"),
            variability=a.get("variability", "continuous" if v.tag in ("Float32", "Float64") else "discrete"),
            initial=a.get("initial"),
            start=a.get("start"),
            clocks=_vr_list(a.get("clocks"), "clocks", where),
            declared_type=a.get("declaredType"),
            previous=_int(prev, "previous", where) if prev is not None else None,
            interval_variability=a.get("intervalVariability"),
            interval=_float(a.get("intervalDecimal"), "intervalDecimal", where),
            shift=_float(a.get("shiftDecimal"), "shiftDecimal", where),
            can_be_deactivated=_bool(a.get("canBeDeactivated")),
            attributes=dict(a),
            line=v.sourceline or 0,
        ))

    unknowns: list[Unknown] = []
    ms = root.find("ModelStructure")
    for u in (ms if ms is not None else []):
        if not isinstance(u.tag, str):
            continue
        where = at(u)
        deps = u.get("dependencies")
        unknowns.append(Unknown(
            kind=u.tag,
            value_reference=_int(u.get("valueReference"), "valueReference", where),
            dependencies=_vr_list(deps, "dependencies", where) if deps is not None else None,
            line=u.sourceline or 0,
        ))

    return ModelDescription(
        fmi_version=version,
        model_name=root.get("modelName", ""),
        instantiation_token=root.get("instantiationToken", ""),
        co_simulation=cs,
        variables=tuple(variables),
        unknowns=tuple(unknowns),
        start_time=start,
        stop_time=stop,
        step_size=step,
        has_model_exchange=root.find("ModelExchange") is not None,
        has_scheduled_execution=root.find("ScheduledExecution") is not None,
        path=display_path,
    )


def load_model_description(folder: str | Path, display_path: str | None = None) -> ModelDescription:
    """Read ``folder/modelDescription.xml`` of an extracted FMU."""
    path = Path(folder) / "modelDescription.xml"
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise RobogenError.at(f"cannot read modelDescription.xml: {exc.strerror}", Span.whole_file(display_path or str(path))) from None
    return read_model_description(data, display_path or str(path))
