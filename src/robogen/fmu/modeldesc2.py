"""FMI 2.0 model descriptions, read into the classes of :mod:`robogen.fmu.modeldesc`.

The master sees one kind of description: an FMI 2.0 ``<ScalarVariable>`` becomes a
:class:`~robogen.fmu.modeldesc.Variable` of the FMI 3.0 type its values travel as (Real as
Float64, Integer as Int32, Boolean, String, Enumeration as Enumeration: Int64 in connections), the
GUID the instantiation token, ``<CoSimulation>`` and ``<ModelExchange>`` the interfaces (FMI 2.0
Co-Simulation has no Event Mode and never returns early; ``canGetAndSetFMUstate`` as FMI 3.0's
flag; ``completedIntegratorStepNotNeeded`` as the negation of FMI 3.0's
``needsCompletedIntegratorStep``), and ``<ModelStructure>``'s indices (1-based positions in
``<ModelVariables>``) value references: ``<Outputs>`` as ``Output``, ``<Derivatives>`` as
``ContinuousStateDerivative``, ``<InitialUnknowns>`` as ``InitialUnknown``.
"""

from __future__ import annotations

from lxml import etree

from robogen.diagnostics import RobogenError
from robogen.fmu.modeldesc import (
    CoSimulation, DefaultExperiment, EnumerationType, Item, LogCategory, ModelDescription, ModelExchange, Unit, Unknown,
    Variable,
)

#: FMI 2.0's variable types, as the FMI 3.0 types their values travel as.
TYPES = {"Real": "Float64", "Integer": "Int32", "Boolean": "Boolean", "String": "String", "Enumeration": "Enumeration"}
#: <ModelStructure>'s lists, as FMI 3.0's elements.
STRUCTURE = {"Outputs": "Output", "Derivatives": "ContinuousStateDerivative", "InitialUnknowns": "InitialUnknown"}


def _children(parent, tags=None) -> list:
    if parent is None:
        return []
    return [el for el in parent if isinstance(el.tag, str) and (tags is None or el.tag in tags)]


def _bool(value: str | None) -> bool:
    return value in ("true", "1")


def read_fmi2(root: etree._Element, source) -> ModelDescription:
    """The description of an FMI 2.0 FMU (``source``: modeldesc's located reader of the file)."""
    elements = _children(root.find("ModelVariables"), ("ScalarVariable",))
    variables = tuple(_variable(el, source) for el in elements)
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
        unknowns=tuple(_structure(root.find("ModelStructure"), variables, source)),
        fmi_version=root.get("fmiVersion", ""),
        description=root.get("description", ""),
        generation_tool=root.get("generationTool", ""),
        variable_naming_convention=root.get("variableNamingConvention"),
        unit_definitions=tuple(Unit(el.get("name", "")) for el in _children(root.find("UnitDefinitions"), ("Unit",))),
        type_definitions=tuple(_enumeration_type(el, source) for el in _children(root.find("TypeDefinitions"), ("SimpleType",))
                               if el.find("Enumeration") is not None),
        log_categories=tuple(LogCategory(el.get("name", ""), el.get("description", ""))
                             for el in _children(root.find("LogCategories"), ("Category",))),
        default_experiment=_default_experiment(root.find("DefaultExperiment"), source),
        event_indicators=source.optional_integer(root, "numberOfEventIndicators") or 0,
        path=source.path,
    )


def _variable(el: etree._Element, source) -> Variable:
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


def _structure(el, variables: tuple[Variable, ...], source) -> list[Unknown]:
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


def _enumeration_type(el: etree._Element, source) -> EnumerationType:
    items = _children(el.find("Enumeration"), ("Item",))
    return EnumerationType(el.get("name", ""), tuple(Item(i.get("name", ""), source.integer(i, "value"), i.get("description", ""))
                                                     for i in items))


def _default_experiment(el, source) -> DefaultExperiment | None:
    if el is None:
        return None
    return DefaultExperiment(source.decimal(el, "startTime"), source.decimal(el, "stopTime"),
                             source.decimal(el, "tolerance"), source.decimal(el, "stepSize"))


__all__ = ["TYPES", "read_fmi2"]
