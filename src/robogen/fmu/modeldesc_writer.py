"""Writing ``modelDescription.xml`` from a :class:`robogen.fmu.modeldesc.ModelDescription`.

The text is deterministic (the same description gives the same bytes) and laid out for reading:
two spaces per level; the root and ``<CoSimulation>``, the head a reader scans, put one
attribute per line; every other element is one line, its children indented below it.
Attributes come in a fixed order and only when present (false flags and empty texts are left
out, as the standard's defaults say the same). ``<ModelStructure>`` is written in the order the
standard requires whatever order the description lists it in.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace

from robogen.fmu.modeldesc import (
    START_ELEMENT_TYPES, STRUCTURE_ORDER, CoSimulation, DefaultExperiment, EnumerationType, ModelDescription,
    ModelExchange, ScheduledExecution, Unit, Unknown, Variable, instantiation_token,
)

XML_DECLARATION = '<?xml version="1.0" encoding="UTF-8"?>'
_ESCAPES = str.maketrans({"&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "\n": "&#10;", "\r": "&#13;",
                          "\t": "&#9;"})


def write_model_description(md: ModelDescription) -> str:
    """The text of ``modelDescription.xml`` for ``md``."""
    root = _Element("fmiModelDescription", [
        ("fmiVersion", md.fmi_version),
        ("modelName", md.model_name),
        ("instantiationToken", md.instantiation_token),
        ("description", md.description or None),
        ("generationTool", md.generation_tool or None),
        ("variableNamingConvention", md.variable_naming_convention),
    ], wrap=True)
    root.children = [element for element in (
        _interface("ModelExchange", md.model_exchange),
        _co_simulation(md.co_simulation),
        _interface("ScheduledExecution", md.scheduled_execution),
        _list("UnitDefinitions", [_unit(u) for u in md.unit_definitions]),
        _list("TypeDefinitions", [_enumeration_type(t) for t in md.type_definitions]),
        _list("LogCategories", [_Element("Category", [("name", c.name), ("description", c.description or None)])
                                for c in md.log_categories]),
        _default_experiment(md.default_experiment),
        _Element("ModelVariables", [], [_variable(v) for v in md.variables]),
        _Element("ModelStructure", [], [_unknown(u) for u in sorted(md.unknowns, key=_structure_rank)]),
    ) if element is not None]
    return "\n".join([XML_DECLARATION, *root.lines(0)]) + "\n"


def with_content_token(md: ModelDescription) -> ModelDescription:
    """``md`` with the instantiation token hashed from its own text (written with an empty
    token), for FMUs that the description defines (Python FMUs, the C test FMUs)."""
    return replace(md, instantiation_token=instantiation_token(write_model_description(
        replace(md, instantiation_token=""))))


@dataclass
class _Element:
    """An element to write: its attributes in order (a None value is left out) and children."""

    tag: str
    attributes: list[tuple[str, str | None]]
    children: list["_Element"] = field(default_factory=list)
    wrap: bool = False  # one attribute per line

    def lines(self, depth: int) -> list[str]:
        pad = "  " * depth
        attributes = [f'{name}="{value.translate(_ESCAPES)}"' for name, value in self.attributes if value is not None]
        end = ">" if self.children else "/>"
        if self.wrap:
            head = [f"{pad}<{self.tag}", *(f"{pad}  {a}" for a in attributes)]
            head[-1] += end
        else:
            head = [f"{pad}<{' '.join([self.tag, *attributes])}{end}"]
        if not self.children:
            return head
        return [*head, *(line for child in self.children for line in child.lines(depth + 1)), f"{pad}</{self.tag}>"]


def _list(tag: str, children: list[_Element]) -> _Element | None:
    """A container element, left out when it would be empty (the schema wants at least one child)."""
    return _Element(tag, [], children) if children else None


def _number(value: int | None) -> str | None:
    return None if value is None else str(value)


def _value_references(vrs: tuple[int, ...] | None) -> str | None:
    return None if vrs is None else " ".join(map(str, vrs))


def _co_simulation(cs: CoSimulation | None) -> _Element | None:
    if cs is None:
        return None
    flags = [(f.metadata["xml"], "true") for f in fields(cs) if "xml" in f.metadata and getattr(cs, f.name)]
    return _Element("CoSimulation", [("modelIdentifier", cs.model_identifier), *flags,
                                     ("fixedInternalStepSize", cs.fixed_internal_step)], wrap=True)


def _interface(tag: str, interface: ModelExchange | ScheduledExecution | None) -> _Element | None:
    """``<ModelExchange>`` or ``<ScheduledExecution>``: its identifier and its true flags."""
    if interface is None:
        return None
    flags = [("needsCompletedIntegratorStep", getattr(interface, "needs_completed_integrator_step", False)),
             ("canGetAndSetFMUState", interface.can_get_and_set_state)]
    return _Element(tag, [("modelIdentifier", interface.model_identifier), *((n, "true") for n, on in flags if on)],
                    wrap=True)


def _unit(unit: Unit) -> _Element:
    scale = [(k, v) for k, v in (("factor", unit.factor), ("offset", unit.offset)) if v is not None]
    base = [] if unit.base_unit is None else [_Element("BaseUnit", [(k, str(e)) for k, e in unit.base_unit] + scale)]
    return _Element("Unit", [("name", unit.name)], base)


def _enumeration_type(t: EnumerationType) -> _Element:
    items = [_Element("Item", [("name", i.name), ("value", str(i.value)), ("description", i.description or None)])
             for i in t.items]
    return _Element("EnumerationType", [("name", t.name)], items)


def _default_experiment(de: DefaultExperiment | None) -> _Element | None:
    if de is None:
        return None
    return _Element("DefaultExperiment", [("startTime", de.start_time), ("stopTime", de.stop_time),
                                          ("tolerance", de.tolerance), ("stepSize", de.step_size)])


def _variable(v: Variable) -> _Element:
    start_attribute = v.type not in START_ELEMENT_TYPES
    attributes = [
        ("name", v.name),
        ("valueReference", str(v.value_reference)),
        ("causality", v.causality),
        ("variability", v.variability),
        ("intervalVariability", v.interval_variability),
        ("intervalDecimal", v.interval_decimal),
        ("shiftDecimal", v.shift_decimal),
        ("canBeDeactivated", "true" if v.can_be_deactivated else None),
        ("priority", _number(v.priority)),
        ("declaredType", v.declared_type),
        ("clocks", _value_references(v.clocks or None)),
        ("previous", _number(v.previous)),
        ("initial", v.initial),
        ("start", " ".join(v.start) if start_attribute and v.start else None),
        ("unit", v.unit),
        ("description", v.description or None),
    ]
    children = [_Element("Dimension", [("start", _number(d.start)), ("valueReference", _number(d.value_reference))])
                for d in v.dimensions]
    if not start_attribute:
        children += [_Element("Start", [("value", value)]) for value in v.start]
    return _Element(v.type, attributes, children)


def _structure_rank(u: Unknown) -> int:
    return STRUCTURE_ORDER.index(u.kind) if u.kind in STRUCTURE_ORDER else len(STRUCTURE_ORDER)


def _unknown(u: Unknown) -> _Element:
    return _Element(u.kind, [("valueReference", str(u.value_reference)),
                             ("dependencies", _value_references(u.dependencies))])


__all__ = ["write_model_description", "with_content_token"]
