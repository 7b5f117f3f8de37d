"""A system written as an SSP 2.0 archive (``robogen export-ssp SYSTEM -o SYSTEM.ssp``).

The archive holds ``SystemStructure.ssd`` and the instances' FMUs under ``resources/``. Each
instance is a component whose connectors are its FMU's inputs, outputs and parameters, typed
from the model description (FMI 3.0 types, units, enumerations, array dimensions; clocks as
``<ssc:Clock>`` with their interval variability, a clock's interval and shift where the system
sets them or the FMU declares them constant; a clocked variable associated to its clocks with
``<ssd:Clock>``). Connections keep their direction (start: the output); a connection that
converts its value carries its factor and offset as a ``LinearTransformation``, and every
connection between units that differ says ``suppressUnitConversion="true"``: a system file
converts nothing the system does not ask for, and neither does the SSP. Start values become
inline parameter values of the component, the start and stop times the ``DefaultExperiment``,
and robogen's own settings (step, tolerance, event iteration bound, order, recording, isolation)
robogen annotations, so that reading the archive back gives the same system
(:mod:`robogen.cosim.ssp_read`; docs/ssp.md). The archive is deterministic: the same system gives
the same bytes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from lxml import etree

from robogen import __version__
from robogen.cosim.assemble import FmuCache, check_system, read_system
from robogen.cosim.ssp_flatten import fmu_unit
from robogen.cosim.ssp_model import ROBOGEN_NS, ROBOGEN_TYPE
from robogen.cosim.ssp_schema import SSC, SSD, SSV
from robogen.cosim.ssp_components import IMPLEMENTATIONS
from robogen.cosim.system import SOLVERS, Connection, System
from robogen.cosim.units import SI_BASE_UNITS, UnitDef, UnitMismatch, conversion
from robogen.diagnostics import DiagnosticSink, RobogenError, error
from robogen.fmu.archive import write_fmu
from robogen.fmu.modeldesc import ModelDescription, Variable
from robogen.outputs import output_file

NSMAP = {"ssd": SSD, "ssc": SSC, "ssv": SSV}
CONNECTOR_KINDS = ("input", "output", "parameter", "calculatedParameter", "structuralParameter")


def export_ssp(path: str | Path, output: str | Path, warn=None) -> Path:
    """Write the system at ``path`` (a system file or an SSP) as an SSP 2.0 archive at ``output``."""
    path = Path(path)
    cache = FmuCache()
    try:
        system = read_system(path, cache, warn or (lambda d: None))
        players = [spec for spec in system.instances.values() if spec.scenario is not None]
        if players:  # robogen's own kind of instance: no FMU to put into the archive
            raise RobogenError([error(f"instance '{spec.name}' is driven by a scenario (docs/scenarios.md), which an "
                                      "SSP cannot hold: export the system without it", spec.scenario_span)
                                for spec in players])
        target = output_file(output, inputs=[path, *(spec.fmu for spec in system.instances.values())])
        models = check_system(system, cache, warn or (lambda d: None))  # a system that would not run is not written
        writer = _Writer(system, models)
        ssd = writer.document()
        return write_fmu(target, {"SystemStructure.ssd": ssd, **writer.resources})
    finally:
        cache.close()


def _el(ns: str, tag: str, attrs: dict | None = None, *children, nsmap: dict = NSMAP) -> etree._Element:
    """An element with these attributes (None: left out) and children (None: left out)."""
    el = etree.Element(f"{{{ns}}}{tag}", nsmap=nsmap)
    for key, value in (attrs or {}).items():
        if value is not None:
            el.set(key, value)
    for child in children:
        if child is not None:
            el.append(child)
    return el


def decimal(value: float) -> str:
    """A real as XML Schema's xs:double writes it, reading back to the same double."""
    if math.isnan(value):
        return "NaN"
    if math.isinf(value):
        return "INF" if value > 0 else "-INF"
    return repr(float(value))


@dataclass
class _Writer:
    system: System
    models: dict[str, ModelDescription]
    resources: dict[str, Path] = field(default_factory=dict)
    units: dict[str, UnitDef] = field(default_factory=dict)
    enumerations: dict[str, etree._Element] = field(default_factory=dict)
    sink: DiagnosticSink = field(default_factory=DiagnosticSink)

    def document(self) -> bytes:
        s = self.system
        sources = self._sources()
        components = [self.component(name, sources[name]) for name in s.instances]
        connections = [self.connection(c) for c in s.connections]
        system = _el(SSD, "System", {"name": s.path.stem},
                     _el(SSD, "Elements", {}, *components),
                     _el(SSD, "Connections", {}, *connections) if connections else None)
        root = _el(SSD, "SystemStructureDescription", {"version": "2.0", "name": s.path.stem,
                                                       "generationTool": f"robogen {__version__}"},
                   system,
                   _el(SSD, "Enumerations", {}, *self.enumerations.values()) if self.enumerations else None,
                   _el(SSD, "Units", {}, *(self.unit(u) for u in self.units.values())) if self.units else None,
                   self.experiment())
        self.sink.raise_if_errors()
        return b'<?xml version="1.0" encoding="UTF-8"?>\n' + etree.tostring(root, encoding="UTF-8", pretty_print=True)

    def _sources(self) -> dict[str, str]:
        """Each instance's FMU under resources/: one file per FMU, named as it was where possible."""
        by_file: dict[Path, str] = {}
        sources = {}
        for name, spec in self.system.instances.items():
            key = spec.fmu.resolve()
            if key not in by_file:
                member = f"resources/{spec.fmu.name}"
                if member in self.resources:
                    member = f"resources/{spec.fmu.stem}_{name}{spec.fmu.suffix}"
                self.resources[member] = spec.fmu
                by_file[key] = member
            sources[name] = by_file[key]
        return sources

    # -- components ---------------------------------------------------------------------------
    def component(self, name: str, source: str) -> etree._Element:
        spec, md = self.system.instances[name], self.models[name]
        connectors = [self.connector(name, md, v) for v in md.variables if v.causality in CONNECTOR_KINDS]
        bindings = self.start_values(name, md)
        attrs = {"isolate": "true" if spec.isolate else None, "solver": spec.solver if spec.solver != SOLVERS[0] else None,
                 "solverStep": decimal(spec.solver_step) if spec.solver_step is not None else None}
        settings = _annotations(_rg("Instance", attrs)) if any(v is not None for v in attrs.values()) else None
        implementation = next((k for k, v in IMPLEMENTATIONS.items() if v == spec.interface), None)
        return _el(SSD, "Component", {"name": name, "type": "application/x-fmu-sharedlibrary", "source": source,
                                      "implementation": implementation if spec.interface is not None else None},
                   _el(SSD, "Connectors", {}, *connectors) if connectors else None, bindings, settings)

    def connector(self, instance: str, md: ModelDescription, var: Variable) -> etree._Element:
        by_vr = md.by_vr()
        dims = [_el(SSC, "Dimension", {"size": str(d.start)} if d.start is not None
                    else {"sizeConnector": by_vr[d.value_reference].name if d.value_reference in by_vr else None})
                for d in var.dimensions]
        clocks = [_el(SSD, "Clock", {"name": by_vr[c].name}) for c in var.clocks if c in by_vr]
        return _el(SSD, "Connector", {"name": var.name, "kind": var.causality}, self.type_of(instance, md, var), *dims, *clocks)

    def type_of(self, instance: str, md: ModelDescription, var: Variable) -> etree._Element:
        if var.is_clock:
            timing = dict(self.system.instances[instance].clocks.get(var.name, ({}, None))[0])
            attrs = {"intervalVariability": var.interval_variability}
            if var.interval_variability == "constant":
                attrs.update(intervalDecimal=var.interval_decimal, shiftDecimal=var.shift_decimal)
            if "interval" in timing:
                attrs["intervalDecimal"] = decimal(timing["interval"])
            if "shift" in timing:
                attrs["shiftDecimal"] = decimal(timing["shift"])
            return _el(SSC, "Clock", attrs)
        if var.type == "Enumeration":
            self.enumeration(md, var)
            return _el(SSC, "Enumeration", {"name": var.declared_type or ""})
        unit = fmu_unit(md, var) if var.type in ("Float32", "Float64") else None
        if unit is not None and unit.exponents is not None and self.units.setdefault(unit.name, unit) == unit:
            return _el(SSC, var.type, {"unit": unit.name})
        return _el(SSC, var.type)

    def enumeration(self, md: ModelDescription, var: Variable) -> None:
        kind = next((t for t in md.type_definitions if t.name == var.declared_type), None)
        if kind is None or kind.name in self.enumerations:
            return
        self.enumerations[kind.name] = _el(SSC, "Enumeration", {"name": kind.name},
                                           *(_el(SSC, "Item", {"name": i.name, "value": str(i.value)}) for i in kind.items))

    def unit(self, unit: UnitDef) -> etree._Element:
        attrs = {k: str(e) for k, e in zip(SI_BASE_UNITS, unit.exponents or ()) if e}
        if unit.factor != 1.0:
            attrs["factor"] = decimal(unit.factor)
        if unit.offset != 0.0:
            attrs["offset"] = decimal(unit.offset)
        return _el(SSC, "Unit", {"name": unit.name}, _el(SSC, "BaseUnit", attrs))

    def start_values(self, instance: str, md: ModelDescription) -> etree._Element | None:
        spec = self.system.instances[instance]
        if not spec.start:
            return None
        names = md.by_name()
        parameters = [self.parameter(instance, md, names[var], value, span) for var, (value, span) in spec.start.items()]
        parameter_set = _el(SSV, "ParameterSet", {"version": "2.0", "name": f"start values of {instance}"},
                            _el(SSV, "Parameters", {}, *parameters))
        return _el(SSD, "ParameterBindings", {}, _el(SSD, "ParameterBinding", {}, _el(SSD, "ParameterValues", {}, parameter_set)))

    def parameter(self, instance: str, md: ModelDescription, var: Variable, value, span) -> etree._Element | None:
        values = value if isinstance(value, list) else [value]
        kind = var.type
        if kind in ("Float32", "Float64"):
            typed = _el(SSV, kind, {"value": " ".join(decimal(v) for v in values)})
        elif kind == "Boolean":
            typed = _el(SSV, kind, {"value": " ".join("true" if v else "false" for v in values)})
        elif kind in ("String", "Enumeration"):
            attrs = {}
            if kind == "Enumeration":
                self.enumeration(md, var)
                items = {i.value: i.name for t in md.type_definitions if t.name == var.declared_type for i in t.items}
                if any(v not in items for v in values):
                    self.sink.error(f"the start value {value!r} of '{instance}.{var.name}' is no item of its enumeration "
                                    f"type {var.declared_type}: an SSP parameter names enumeration items", span)
                    return None
                values, attrs = [items[v] for v in values], {"name": var.declared_type}
            try:
                typed = (_el(SSV, kind, {"value": values[0], **attrs}) if len(values) == 1
                         else _el(SSV, kind, attrs, *(_el(SSV, "Value", {"value": v}) for v in values)))
            except ValueError:  # lxml: a character XML cannot hold
                self.sink.error(f"the start value {value!r} of '{instance}.{var.name}' holds characters XML cannot hold", span)
                return None
        else:
            typed = _el(SSV, kind, {"value": " ".join(str(int(v)) for v in values)})
        dims = [_el(SSC, "Dimension", {"size": str(len(values))})] if isinstance(value, list) else []
        return _el(SSV, "Parameter", {"name": var.name}, typed, *dims)

    # -- connections and the experiment ------------------------------------------------------------
    def connection(self, c: Connection) -> etree._Element:
        src = self.models[c.source.instance].by_name()[c.source.variable]
        dst = self.models[c.target.instance].by_name()[c.target.variable]
        suppress = c.scale is not None or self._converts(c, src, dst)
        linear = _el(SSC, "LinearTransformation", {"factor": decimal(c.scale[0]), "offset": decimal(c.scale[1])}) if c.scale else None
        return _el(SSD, "Connection", {"startElement": c.source.instance, "startConnector": c.source.variable,
                                       "endElement": c.target.instance, "endConnector": c.target.variable,
                                       "suppressUnitConversion": "true" if suppress else None}, linear)

    def _converts(self, c: Connection, src: Variable, dst: Variable) -> bool:
        """Whether an SSP reader would convert between the two variables' units."""
        a, b = fmu_unit(self.models[c.source.instance], src), fmu_unit(self.models[c.target.instance], dst)
        if a is None or b is None:
            return False
        try:
            return conversion(a, b) is not None
        except UnitMismatch:
            return True

    def experiment(self) -> etree._Element:
        s = self.system
        attrs = {"step": decimal(s.step) if s.step is not None else None,
                 "tolerance": decimal(s.tolerance) if s.tolerance is not None else None,
                 "maxEventIterations": str(s.max_event_iterations), "order": " ".join(s.order) or None}
        record = None
        if s.record is not None or s.record_every is not None:
            variables = (_rg("Variables", {}, *(_rg("Variable", {"name": n}) for n, _span in s.record))
                         if s.record is not None else None)
            record = _rg("Record", {"every": decimal(s.record_every) if s.record_every is not None else None}, variables)
        return _el(SSD, "DefaultExperiment", {"startTime": decimal(s.start), "stopTime": decimal(s.stop) if s.stop is not None else None},
                   _annotations(_rg("Experiment", attrs, record)))


def _rg(tag: str, attrs: dict, *children) -> etree._Element:
    return _el(ROBOGEN_NS, tag, attrs, *children, nsmap={"rg": ROBOGEN_NS})


def _annotations(content: etree._Element) -> etree._Element:
    return _el(SSD, "Annotations", {}, _el(SSC, "Annotation", {"type": ROBOGEN_TYPE}, content))
