"""The model description of an FMU: frozen dataclasses, the reader, the token.

One set of dataclasses serves both directions: :func:`read_model_description` returns a
:class:`ModelDescription` and :func:`robogen.fmu.modeldesc_writer.write_model_description` takes
one. They cover what robogen writes and what its master and validator read: the
interfaces (Co-Simulation, Model Exchange, Scheduled Execution), units, enumeration types, log categories, the default experiment,
variables of every FMI 3.0 type (arrays with their dimensions, clocks with their timing,
clocked variables) and the model structure.

Decimal attributes (``start``, ``intervalDecimal``, ``shiftDecimal``, the default experiment)
are kept as the text the producer wrote: a float cannot tell ``0`` from ``0.0``, and the text
lets a description be read and written back byte for byte. Properties give the numbers where
robogen computes with them.

FMI 2.0 descriptions are read into the same classes (:func:`read_fmi2`: Real as Float64, Integer
as Int32), so that the master sees one kind of description; a pre-release of FMI
3.0 (``3.0-beta.3``, ``3.0-rc.1``) is read as FMI 3.0 (:attr:`ModelDescription.prerelease` tells
it, for the master's warning).
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Mapping

from lxml import etree

from robogen.diagnostics import RobogenError, Span

#: The variable elements of FMI 3.0, in the order the standard lists them.
TYPE_TAGS = (
    "Float32", "Float64", "Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32", "Int64", "UInt64",
    "Boolean", "String", "Binary", "Enumeration", "Clock",
)
#: Types whose start values are ``<Start value=...>`` children instead of a ``start`` attribute.
START_ELEMENT_TYPES = ("String", "Binary")
#: Types whose variability defaults to continuous (every other type: discrete).
FLOAT_TYPES = ("Float32", "Float64")
#: The SI base units a ``<BaseUnit>`` gives exponents of, in the standard's order.
SI_BASE_UNITS = ("kg", "m", "s", "A", "K", "mol", "cd", "rad")
#: The children of ``<ModelStructure>``, in the order the standard requires.
STRUCTURE_ORDER = ("Output", "ContinuousStateDerivative", "ClockedState", "InitialUnknown", "EventIndicator")


def instantiation_token(content: str | bytes) -> str:
    """The instantiation token of an FMU defined by ``content``: its SHA-256, written like a GUID
    (``{8-4-4-4-12}`` hexadecimal digits), so identical content gives an identical token."""
    data = content.encode("utf-8") if isinstance(content, str) else content
    h = hashlib.sha256(data).hexdigest()
    return f"{{{h[0:8]}-{h[8:12]}-{h[12:16]}-{h[16:20]}-{h[20:32]}}}"


def _flag(xml: str) -> bool:
    """A boolean attribute of ``<CoSimulation>`` (default false), named ``xml`` in the file."""
    return field(default=False, metadata={"xml": xml})


@dataclass(frozen=True)
class CoSimulation:
    """The ``<CoSimulation>`` interface. The flags are written in declaration order, true ones only."""

    model_identifier: str
    needs_execution_tool: bool = _flag("needsExecutionTool")
    can_handle_variable_step: bool = _flag("canHandleVariableCommunicationStepSize")
    can_get_and_set_state: bool = _flag("canGetAndSetFMUState")
    can_serialize_state: bool = _flag("canSerializeFMUState")
    only_once_per_process: bool = _flag("canBeInstantiatedOnlyOncePerProcess")
    provides_directional_derivatives: bool = _flag("providesDirectionalDerivatives")
    provides_adjoint_derivatives: bool = _flag("providesAdjointDerivatives")
    provides_per_element_dependencies: bool = _flag("providesPerElementDependencies")
    provides_intermediate_update: bool = _flag("providesIntermediateUpdate")
    can_return_early_after_intermediate_update: bool = _flag("canReturnEarlyAfterIntermediateUpdate")
    provides_evaluate_discrete_states: bool = _flag("providesEvaluateDiscreteStates")
    has_event_mode: bool = _flag("hasEventMode")
    might_return_early: bool = _flag("mightReturnEarlyFromDoStep")
    fixed_internal_step: str | None = None  # fixedInternalStepSize, decimal text
    line: int = field(default=0, compare=False)


@dataclass(frozen=True)
class ModelExchange:
    """The ``<ModelExchange>`` interface (FMI 2.0's or 3.0's)."""

    model_identifier: str
    needs_completed_integrator_step: bool = False
    can_get_and_set_state: bool = False
    line: int = field(default=0, compare=False)


@dataclass(frozen=True)
class ScheduledExecution:
    """The ``<ScheduledExecution>`` interface (FMI 3.0)."""

    model_identifier: str
    can_get_and_set_state: bool = False
    line: int = field(default=0, compare=False)


@dataclass(frozen=True)
class Unit:
    """A ``<Unit>`` of ``<UnitDefinitions>``: its name and SI base-unit exponents (None: no
    ``<BaseUnit>``), e.g. ``Unit("m/s", (("m", 1), ("s", -1)))``, and the base unit's factor and
    offset as decimal text (None: absent, 1 and 0). Display units are not read."""

    name: str
    base_unit: tuple[tuple[str, int], ...] | None = None
    factor: str | None = None
    offset: str | None = None


@dataclass(frozen=True)
class Item:
    name: str
    value: int
    description: str = ""


@dataclass(frozen=True)
class EnumerationType:
    """An ``<EnumerationType>`` of ``<TypeDefinitions>``, named by Enumeration variables' ``declaredType``."""

    name: str
    items: tuple[Item, ...]


@dataclass(frozen=True)
class LogCategory:
    name: str
    description: str = ""


@dataclass(frozen=True)
class DefaultExperiment:
    """``<DefaultExperiment>``; each attribute is decimal text, None when absent."""

    start_time: str | None = None
    stop_time: str | None = None
    tolerance: str | None = None
    step_size: str | None = None


@dataclass(frozen=True)
class Dimension:
    """One ``<Dimension>`` of an array variable: a fixed size, or the structural parameter holding it."""

    start: int | None = None
    value_reference: int | None = None


@dataclass(frozen=True)
class Variable:
    """One model variable. ``type`` is its element name (one of :data:`TYPE_TAGS`).

    ``start`` holds one text per start value: the space-separated ``start`` attribute of an
    array, or the ``<Start>`` children of a String or Binary. ``attributes`` is the element's
    attribute table as read (the validator checks attributes that must be absent); the writer
    never looks at it.
    """

    name: str
    value_reference: int
    type: str
    causality: str = "local"
    variability: str = "continuous"
    description: str = ""
    initial: str | None = None
    start: tuple[str, ...] = ()
    declared_type: str | None = None
    clocks: tuple[int, ...] = ()
    previous: int | None = None
    unit: str | None = None
    dimensions: tuple[Dimension, ...] = ()
    # Clock attributes (type == "Clock")
    interval_variability: str | None = None
    interval_decimal: str | None = None
    shift_decimal: str | None = None
    can_be_deactivated: bool = False
    priority: int | None = None  # a clock's priority (Scheduled Execution: a lower number first)
    attributes: Mapping[str, str] = field(default_factory=dict, compare=False, hash=False, repr=False)
    line: int = field(default=0, compare=False)

    @property
    def is_clock(self) -> bool:
        return self.type == "Clock"

    @property
    def is_clocked(self) -> bool:
        return bool(self.clocks)

    @property
    def interval(self) -> float | None:
        """A periodic clock's interval in seconds (None when the description gives none)."""
        return None if self.interval_decimal is None else float(self.interval_decimal)

    @property
    def shift(self) -> float | None:
        """A periodic clock's shift in seconds (None when the description gives none)."""
        return None if self.shift_decimal is None else float(self.shift_decimal)


@dataclass(frozen=True)
class Unknown:
    """One child of ``<ModelStructure>``. ``dependencies`` None: depends on every known; (): on none."""

    kind: str  # one of STRUCTURE_ORDER
    value_reference: int
    dependencies: tuple[int, ...] | None = None
    line: int = field(default=0, compare=False)


@dataclass(frozen=True)
class ModelDescription:
    model_name: str
    instantiation_token: str
    co_simulation: CoSimulation | None
    variables: tuple[Variable, ...]
    unknowns: tuple[Unknown, ...] = ()
    fmi_version: str = "3.0"
    description: str = ""
    generation_tool: str = ""
    variable_naming_convention: str | None = None
    unit_definitions: tuple[Unit, ...] = ()
    type_definitions: tuple[EnumerationType, ...] = ()
    log_categories: tuple[LogCategory, ...] = ()
    default_experiment: DefaultExperiment | None = None
    model_exchange: ModelExchange | None = None
    scheduled_execution: ScheduledExecution | None = None
    event_indicators: int | None = None  # FMI 2.0's numberOfEventIndicators (FMI 3.0: <EventIndicator>s)
    path: str = field(default="modelDescription.xml", compare=False)

    @property
    def prerelease(self) -> bool:
        """A pre-release of FMI 3.0 (``3.0-beta.3``, ``3.0-rc.1``), read as FMI 3.0."""
        return self.fmi_version.startswith("3.0-")

    @property
    def is_fmi2(self) -> bool:
        return self.fmi_version.startswith("2.")

    def interfaces(self) -> tuple[str, ...]:
        """The interfaces the FMU offers, in the order the master prefers them."""
        offered = (("co-simulation", self.co_simulation), ("model-exchange", self.model_exchange),
                   ("scheduled-execution", self.scheduled_execution))
        return tuple(name for name, element in offered if element is not None)

    def element_count(self, var: Variable) -> int:
        """How many values the variable holds: 1 for a scalar; for an array the product of its
        dimensions, each a fixed size or the start value of the structural parameter named by its
        value reference (the master does not change structural parameters)."""
        count = 1
        by_vr = None
        for d in var.dimensions:
            if d.start is not None:
                count *= d.start
                continue
            by_vr = by_vr or self.by_vr()
            parameter = by_vr.get(d.value_reference)
            if parameter is None or len(parameter.start) != 1 or not parameter.start[0].isdigit():
                raise RobogenError.at(f"array '{var.name}': its dimension names value reference {d.value_reference}, "
                                      "which is not a structural parameter with an integer start value", self.span(var.line))
            count *= int(parameter.start[0])
        return count

    def element_names(self, var: Variable) -> list[str]:
        """The names of a variable's values: its name, or for an array name[1], name[2], ... (row-major)."""
        count = self.element_count(var)
        return [var.name] if not var.dimensions else [f"{var.name}[{k}]" for k in range(1, count + 1)]

    def number_of_states(self) -> int:
        return sum(1 for u in self.unknowns if u.kind == "ContinuousStateDerivative")

    def number_of_event_indicators(self) -> int:
        if self.event_indicators is not None:
            return self.event_indicators
        return sum(1 for u in self.unknowns if u.kind == "EventIndicator")

    def by_name(self) -> dict[str, Variable]:
        return {v.name: v for v in self.variables}

    def by_vr(self) -> dict[int, Variable]:
        return {v.value_reference: v for v in self.variables}

    def span(self, line: int) -> Span:
        return Span.point(self.path, max(line, 1))


MAX_XML_BYTES = 64 * 1024 * 1024


# --------------------------------------------------------------------------------------------
# Reading. The parser never expands entities, never loads a DTD and never touches the network
# (a third-party FMU is untrusted input). Every element keeps the line where it starts, so the
# master and the validator can point at it.


def safe_parser() -> etree.XMLParser:
    """An lxml parser that resolves no entities, loads no DTD and uses no network."""
    return etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False, dtd_validation=False,
                           huge_tree=False, remove_comments=False)


def parse_xml(data: bytes, display_path: str) -> etree._ElementTree:
    if len(data) > MAX_XML_BYTES:
        raise RobogenError.at(f"modelDescription.xml is larger than {MAX_XML_BYTES} bytes", Span.whole_file(display_path))
    if b"<!DOCTYPE" in data[:4096] or b"<!ENTITY" in data:
        raise RobogenError.at("modelDescription.xml declares a DOCTYPE or entities, which FMI does not allow",
                              Span.whole_file(display_path))
    try:
        return etree.ElementTree(etree.fromstring(data, safe_parser()))
    except etree.XMLSyntaxError as exc:
        line, col = exc.position if exc.position else (1, 1)
        raise RobogenError.at(f"malformed XML: {exc.msg}", Span.point(display_path, line or 1, (col or 0) + 1)) from None


def read_model_description(data: bytes, display_path: str = "modelDescription.xml") -> ModelDescription:
    """Parse the bytes of a modelDescription.xml. Raises RobogenError with a location."""
    root = parse_xml(data, display_path).getroot()
    source = _Source(data, display_path)
    _check_root(root, source)
    if root.get("fmiVersion", "").startswith("2."):
        return read_fmi2(root, source)
    return ModelDescription(
        model_name=root.get("modelName", ""),
        instantiation_token=root.get("instantiationToken", ""),
        co_simulation=_co_simulation(root.find("CoSimulation"), source),
        variables=tuple(_variable(el, source) for el in _children(root.find("ModelVariables"), TYPE_TAGS)),
        unknowns=tuple(_unknown(el, source) for el in _children(root.find("ModelStructure"))),
        fmi_version=root.get("fmiVersion", ""),
        description=root.get("description", ""),
        generation_tool=root.get("generationTool", ""),
        variable_naming_convention=root.get("variableNamingConvention"),
        unit_definitions=tuple(_unit(el, source) for el in _children(root.find("UnitDefinitions"), ("Unit",))),
        type_definitions=tuple(_enumeration_type(el, source)
                               for el in _children(root.find("TypeDefinitions"), ("EnumerationType",))),
        log_categories=tuple(LogCategory(el.get("name", ""), el.get("description", ""))
                             for el in _children(root.find("LogCategories"), ("Category",))),
        default_experiment=_default_experiment(root.find("DefaultExperiment"), source),
        model_exchange=_model_exchange(root.find("ModelExchange"), source),
        scheduled_execution=_scheduled_execution(root.find("ScheduledExecution"), source),
        path=display_path,
    )


def load_model_description(folder: str | Path, display_path: str | None = None) -> ModelDescription:
    """Read ``folder/modelDescription.xml`` of an extracted FMU."""
    path = Path(folder) / "modelDescription.xml"
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise RobogenError.at(f"cannot read modelDescription.xml: {exc.strerror}",
                              Span.whole_file(display_path or str(path))) from None
    return read_model_description(data, display_path or str(path))


class _Source:
    """The file being read: locates elements and converts attribute texts, with located errors."""

    def __init__(self, data: bytes, display_path: str):
        self.path = display_path
        self.lines = data.split(b"\n")

    def line(self, el: etree._Element) -> int:
        """The line where ``el``'s start tag opens (libxml2 gives the line where it closes)."""
        line = min(el.sourceline or 1, len(self.lines))
        opening = b"<" + el.tag.encode("utf-8")
        while line > 1 and opening not in self.lines[line - 1]:
            line -= 1
        return line

    def at(self, el: etree._Element) -> Span:
        return Span.point(self.path, self.line(el))

    def decimal(self, el: etree._Element, attr: str) -> str | None:
        """The text of a decimal attribute, checked to be a number."""
        value = el.get(attr)
        if value is not None:
            try:
                float(value)
            except ValueError:
                raise RobogenError.at(f"{attr}: '{value}' is not a number", self.at(el)) from None
        return value

    def integer(self, el: etree._Element, attr: str) -> int:
        value = el.get(attr)
        try:
            return int(value)  # type: ignore[arg-type]
        except (TypeError, ValueError):
            raise RobogenError.at(f"{attr}: '{value}' is not an integer", self.at(el)) from None

    def optional_integer(self, el: etree._Element, attr: str) -> int | None:
        return None if el.get(attr) is None else self.integer(el, attr)

    def vr_list(self, el: etree._Element, attr: str) -> tuple[int, ...] | None:
        value = el.get(attr)
        if value is None:
            return None
        try:
            return tuple(int(x) for x in value.split())
        except ValueError:
            raise RobogenError.at(f"{attr}: '{value}' is not a list of value references", self.at(el)) from None


def _children(parent: etree._Element | None, tags: tuple[str, ...] | None = None) -> list[etree._Element]:
    """The child elements of ``parent`` (none when absent), comments left out, only ``tags`` if given."""
    if parent is None:
        return []
    return [el for el in parent if isinstance(el.tag, str) and (tags is None or el.tag in tags)]


def _bool(value: str | None) -> bool:
    return value in ("true", "1")


def _check_root(root: etree._Element, source: _Source) -> None:
    if root.tag != "fmiModelDescription":
        raise RobogenError.at(f"root element is <{root.tag}>, expected <fmiModelDescription>", source.at(root))
    version = root.get("fmiVersion", "")
    if not version.startswith(("2.", "3.")):
        raise RobogenError.at(f"fmiVersion is '{version}': robogen imports FMI 2.0 and 3.0 only", source.at(root))


def _co_simulation(el: etree._Element | None, source: _Source) -> CoSimulation | None:
    if el is None:
        return None
    flags = {f.name: _bool(el.get(f.metadata["xml"])) for f in fields(CoSimulation) if "xml" in f.metadata}
    return CoSimulation(model_identifier=el.get("modelIdentifier", ""), **flags,
                        fixed_internal_step=source.decimal(el, "fixedInternalStepSize"), line=source.line(el))


def _model_exchange(el: etree._Element | None, source: _Source) -> ModelExchange | None:
    if el is None:
        return None
    return ModelExchange(el.get("modelIdentifier", ""), _bool(el.get("needsCompletedIntegratorStep")),
                         _bool(el.get("canGetAndSetFMUState")), source.line(el))


def _scheduled_execution(el: etree._Element | None, source: _Source) -> ScheduledExecution | None:
    if el is None:
        return None
    return ScheduledExecution(el.get("modelIdentifier", ""), _bool(el.get("canGetAndSetFMUState")), source.line(el))


def _unit(el: etree._Element, source: _Source) -> Unit:
    base = el.find("BaseUnit")
    if base is None:
        return Unit(el.get("name", ""))
    return Unit(el.get("name", ""), tuple((name, source.integer(base, name)) for name in SI_BASE_UNITS if name in base.attrib),
                source.decimal(base, "factor"), source.decimal(base, "offset"))


def _enumeration_type(el: etree._Element, source: _Source) -> EnumerationType:
    items = tuple(Item(item.get("name", ""), source.integer(item, "value"), item.get("description", ""))
                  for item in _children(el, ("Item",)))
    return EnumerationType(el.get("name", ""), items)


def _default_experiment(el: etree._Element | None, source: _Source) -> DefaultExperiment | None:
    if el is None:
        return None
    return DefaultExperiment(source.decimal(el, "startTime"), source.decimal(el, "stopTime"),
                             source.decimal(el, "tolerance"), source.decimal(el, "stepSize"))


def _variable(el: etree._Element, source: _Source) -> Variable:
    a = el.attrib
    if el.tag in START_ELEMENT_TYPES:
        start = tuple(s.get("value", "") for s in _children(el, ("Start",)))
    else:
        start = tuple(a["start"].split()) if "start" in a else ()
    return Variable(
        name=a.get("name", ""),
        value_reference=source.integer(el, "valueReference"),
        type=el.tag,
        causality=a.get("causality", "local"),
        variability=a.get("variability", "continuous" if el.tag in FLOAT_TYPES else "discrete"),
        description=a.get("description", ""),
        initial=a.get("initial"),
        start=start,
        declared_type=a.get("declaredType"),
        clocks=source.vr_list(el, "clocks") or (),
        previous=source.optional_integer(el, "previous"),
        unit=a.get("unit"),
        dimensions=tuple(Dimension(source.optional_integer(d, "start"), source.optional_integer(d, "valueReference"))
                         for d in _children(el, ("Dimension",))),
        interval_variability=a.get("intervalVariability"),
        interval_decimal=source.decimal(el, "intervalDecimal"),
        shift_decimal=source.decimal(el, "shiftDecimal"),
        can_be_deactivated=_bool(a.get("canBeDeactivated")),
        priority=source.optional_integer(el, "priority"),
        attributes=dict(a),
        line=source.line(el),
    )


def _unknown(el: etree._Element, source: _Source) -> Unknown:
    return Unknown(kind=el.tag, value_reference=source.integer(el, "valueReference"),
                   dependencies=source.vr_list(el, "dependencies"), line=source.line(el))


# --------------------------------------------------------------------------------------------
# FMI 2.0
# FMI 2.0 model descriptions, read into the classes of :mod:`robogen.fmu.modeldesc`.
#
#The master sees one kind of description: an FMI 2.0 ``<ScalarVariable>`` becomes a
#:class:`~robogen.fmu.modeldesc.Variable` of the FMI 3.0 type its values travel as (Real as
#Float64, Integer as Int32, Boolean, String, Enumeration as Enumeration: Int64 in connections), the
#GUID the instantiation token, ``<CoSimulation>`` and ``<ModelExchange>`` the interfaces (FMI 2.0
#Co-Simulation has no Event Mode and never returns early; ``canGetAndSetFMUstate`` as FMI 3.0's
#flag; ``completedIntegratorStepNotNeeded`` as the negation of FMI 3.0's
#``needsCompletedIntegratorStep``), and ``<ModelStructure>``'s indices (1-based positions in
#``<ModelVariables>``) value references: ``<Outputs>`` as ``Output``, ``<Derivatives>`` as
#``ContinuousStateDerivative``, ``<InitialUnknowns>`` as ``InitialUnknown``.

#: FMI 2.0's variable types, as the FMI 3.0 types their values travel as.
TYPES = {"Real": "Float64", "Integer": "Int32", "Boolean": "Boolean", "String": "String", "Enumeration": "Enumeration"}
#: <ModelStructure>'s lists, as FMI 3.0's elements.
STRUCTURE = {"Outputs": "Output", "Derivatives": "ContinuousStateDerivative", "InitialUnknowns": "InitialUnknown"}


def read_fmi2(root: etree._Element, source) -> ModelDescription:
    """The description of an FMI 2.0 FMU (``source``: modeldesc's located reader of the file)."""
    elements = _children(root.find("ModelVariables"), ("ScalarVariable",))
    variables = tuple(_variable2(el, source) for el in elements)
    cs, me = root.find("CoSimulation"), root.find("ModelExchange")
    return ModelDescription(
        model_name=root.get("modelName", ""),
        instantiation_token=root.get("guid", ""),
        co_simulation=None if cs is None else CoSimulation(
            cs.get("modelIdentifier", ""), can_handle_variable_step=_bool(cs.get("canHandleVariableCommunicationStepSize")),
            can_get_and_set_state=_bool(cs.get("canGetAndSetFMUstate")), line=source.line(cs)),
        model_exchange=None if me is None else ModelExchange(
            me.get("modelIdentifier", ""), not _bool(me.get("completedIntegratorStepNotNeeded")),
            _bool(me.get("canGetAndSetFMUstate")), source.line(me)),
        variables=variables,
        unknowns=tuple(_structure2(root.find("ModelStructure"), variables, source)),
        fmi_version=root.get("fmiVersion", ""),
        description=root.get("description", ""),
        generation_tool=root.get("generationTool", ""),
        variable_naming_convention=root.get("variableNamingConvention"),
        unit_definitions=tuple(Unit(el.get("name", "")) for el in _children(root.find("UnitDefinitions"), ("Unit",))),
        type_definitions=tuple(_enumeration_type2(el, source) for el in _children(root.find("TypeDefinitions"), ("SimpleType",))
                               if el.find("Enumeration") is not None),
        log_categories=tuple(LogCategory(el.get("name", ""), el.get("description", ""))
                             for el in _children(root.find("LogCategories"), ("Category",))),
        default_experiment=_default_experiment(root.find("DefaultExperiment"), source),
        event_indicators=source.optional_integer(root, "numberOfEventIndicators") or 0,
        path=source.path,
    )


def _variable2(el: etree._Element, source) -> Variable:
    a = el.attrib
    typed = _children(el, tuple(TYPES))
    if not typed:
        raise RobogenError.at(f"ScalarVariable '{a.get('name', '')}' has no type element (Real, Integer, Boolean, String "
                              "or Enumeration)", source.at(el))
    kind = typed[0]
    fmi_type = TYPES[kind.tag]
    start = kind.get("start")
    return Variable(
        name=a.get("name", ""),
        value_reference=source.integer(el, "valueReference"),
        type=fmi_type,
        causality=a.get("causality", "local"),
        variability=a.get("variability", "continuous" if fmi_type == "Float64" else "discrete"),
        description=a.get("description", ""),
        initial=a.get("initial"),
        start=() if start is None else (start,),
        declared_type=kind.get("declaredType"),
        unit=kind.get("unit"),
        attributes=dict(a),
        line=source.line(el),
    )


def _structure2(el, variables: tuple[Variable, ...], source) -> list[Unknown]:
    """<ModelStructure>'s unknowns, their indices as value references."""
    out = []
    for tag, kind in STRUCTURE.items():
        for unknown in _children(el.find(tag) if el is not None else None, ("Unknown",)):
            index = source.integer(unknown, "index")
            dependencies = source.vr_list(unknown, "dependencies")
            positions = [index, *(dependencies or ())]
            if any(not 1 <= i <= len(variables) for i in positions):
                raise RobogenError.at(f"<Unknown index=\"{index}\">: an index is not the position of a ScalarVariable "
                                      f"(1 to {len(variables)})", source.at(unknown))
            out.append(Unknown(kind, variables[index - 1].value_reference,
                               None if dependencies is None else tuple(variables[i - 1].value_reference for i in dependencies),
                               source.line(unknown)))
    return out


def _enumeration_type2(el: etree._Element, source) -> EnumerationType:
    items = _children(el.find("Enumeration"), ("Item",))
    return EnumerationType(el.get("name", ""), tuple(Item(i.get("name", ""), source.integer(i, "value"), i.get("description", ""))
                                                     for i in items))


__all__ = ["TYPE_TAGS", "START_ELEMENT_TYPES", "FLOAT_TYPES", "SI_BASE_UNITS", "STRUCTURE_ORDER", "MAX_XML_BYTES", "safe_parser",
           "parse_xml", "read_model_description", "load_model_description", "instantiation_token", "CoSimulation", "Unit",
           "Item", "EnumerationType", "LogCategory", "DefaultExperiment", "Dimension", "Variable", "Unknown",
           "ModelDescription", "ModelExchange", "ScheduledExecution", "read_fmi2"]
