"""SSP systems (``.ssp`` archives, unpacked ``.ssd`` files) read into robogen's system model.

:func:`load_ssp` is the SSP front end of :class:`~robogen.cosim.system.System`, which the TOML
file's loader also produces: the package is opened (:mod:`robogen.cosim.ssp_package`), the SSD
parsed with positions (:mod:`robogen.cosim.xmltree`) and checked against the SSP schemas'
rules (:mod:`robogen.cosim.ssp_schema`), read (:mod:`robogen.cosim.ssp_model`), its FMUs loaded
(``model_of``, the run's FMU cache), its hierarchy flattened (:mod:`robogen.cosim.ssp_flatten`),
its components checked against their FMUs (:mod:`robogen.cosim.ssp_components`), its parameter
bindings applied (:mod:`robogen.cosim.ssp_start`), and its experiment read: ``DefaultExperiment``
gives the start and stop times, a robogen annotation in it robogen's own settings::

    <ssd:DefaultExperiment startTime="0" stopTime="100">
      <ssd:Annotations>
        <ssc:Annotation type="robogen">
          <rg:Experiment xmlns:rg="urn:robogen:ssp" step="0.5" tolerance="1e-6"
                         maxEventIterations="1000" order="controller dmodel platform">
            <rg:Record every="0.1"><rg:Variable name="dmodel.*"/></rg:Record>
          </rg:Experiment>
        </ssc:Annotation>
      </ssd:Annotations>
    </ssd:DefaultExperiment>

Every problem is reported at the element or attribute of the file that causes it, all together;
the checks of connections against the FMUs are the system file's (:func:`~robogen.cosim.system.resolve`),
located at the ``<ssd:Connection>``. The format and what robogen ignores: docs/ssp.md.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Callable

from robogen.cosim import ssp_schema
from robogen.cosim.ssp_components import instance_spec
from robogen.cosim.ssp_flatten import Flattener, Leaf, Node, fmu_unit, instance_names
from robogen.cosim.ssp_model import ROBOGEN_NS, Document, read_document
from robogen.cosim.ssp_package import Package
from robogen.cosim.ssp_schema import assumed_prefixes
from robogen.cosim.ssp_start import StartValues
from robogen.cosim.system import MAX_EVENT_ITERATIONS, System
from robogen.cosim.tomlspan import PathSpans
from robogen.cosim.units import UnitDef
from robogen.cosim.xmltree import Element, parse
from robogen.diagnostics import Diagnostic, DiagnosticSink, Note, RobogenError, Span, did_you_mean
from robogen.fmu.modeldesc import ModelDescription

SUFFIXES = (".ssp", ".ssd")
EXPERIMENT_ATTRS = ("step", "tolerance", "maxEventIterations", "order")


def is_ssp(path: str | Path) -> bool:
    return Path(path).suffix.lower() in SUFFIXES


def load_ssp(path: str | Path, folder: Path, model_of: Callable[[Path, Span], ModelDescription],
             warn: Callable[[Diagnostic], None] | None = None) -> System:
    """The system of the SSP at ``path`` (an archive is unpacked into ``folder``); ``model_of``
    loads an FMU's model description (errors located at the span it is given)."""
    path = Path(path)
    package = Package(path, folder)
    data = package.ssd.read_bytes()
    sink = DiagnosticSink()
    root = _parse(data, package.display(package.ssd), sink)
    problems = ssp_schema.check(root, "SSD")
    if problems:
        raise RobogenError([*problems, *sink.items])
    doc = read_document(root, sink)
    leaves = instance_names(doc, sink)
    flattener = Flattener(doc, leaves, sink)
    flattener.fmus = _load(leaves, package, model_of, sink)
    unit_of = _units(doc, flattener)
    instances = {leaf.instance: instance_spec(leaf, flattener.fmus[leaf.instance], doc.units, sink)
                 for leaf in leaves.values() if leaf.md is not None}  # the others' problems are reported
    links = flattener.links(unit_of)
    starts = StartValues(flattener, package, sink, unit_of)
    starts.collect(doc.root)
    for name, values in starts.start_values().items():
        if name in instances:
            instances[name].start.update(values)
    spans = _spans(doc, leaves, instances)
    system = System(path, data.decode("utf-8", "replace"), 0.0, None, None, None, MAX_EVENT_ITERATIONS, [], instances, links,
                    None, spans)
    _experiment(doc, system, spans, sink)
    sink.raise_if_errors()
    for w in sink.sorted():
        (warn or (lambda d: None))(w)
    return system


def _parse(data: bytes, display: str, sink: DiagnosticSink) -> Element:
    """An SSD's root element; namespace prefixes it uses without declaring them are the SSP's (with a warning)."""
    root, assumed = parse(data, display, ssp_schema.PREFIXES)
    if assumed:
        sink.add(assumed_prefixes(assumed, root.span))
    return root


def _load(leaves: dict, package: Package, model_of, sink: DiagnosticSink) -> dict[str, Path]:
    """Each FMU component's file, its model description in its leaf."""
    fmus = {}
    for leaf in leaves.values():
        c = leaf.component
        file = package.resolve(c.source, c.el.at("source"), sink, what="component file")
        if file is None:
            continue
        try:
            leaf.md = model_of(file, c.el.at("source"))
        except RobogenError as exc:
            span = c.el.at("source")
            sink.extend(d if d.span == span else d.with_note(f"while loading the FMU of component '{c.name}'", span)
                        for d in exc.diagnostics)
            continue
        fmus[leaf.instance] = file
    return fmus


def _units(doc: Document, flattener: Flattener) -> Callable[[Node], UnitDef | None]:
    """The unit of a connector (a node of the flattener): its own, else its FMU variable's (which
    the SSD defines where the FMU names a unit without defining it)."""

    def unit_of(node: Node) -> UnitDef | None:
        path, component, name = node
        if component is None:
            connector = flattener.systems[path].connectors.get(name)
            return doc.units.get(connector.unit) if connector is not None and connector.unit else None
        leaf: Leaf = flattener.flat.leaves[path, component]
        connector = leaf.component.connectors.get(name)
        if connector is not None and connector.unit is not None:
            return doc.units[connector.unit]
        var = leaf.md.by_name().get(name) if leaf.md is not None else None
        unit = fmu_unit(leaf.md, var) if var is not None else None
        if unit is not None and unit.exponents is None and unit.name in doc.units:
            return doc.units[unit.name]  # a unit the FMU names without defining it: the SSD's of that name
        return unit

    return unit_of


def _spans(doc: Document, leaves: dict, instances: dict) -> PathSpans:
    table = PathSpans(doc.el.span)
    s = table.spans
    if doc.experiment is not None:
        s["experiment",] = doc.experiment.span
        s["experiment", "start"] = doc.experiment.at("startTime")
        s["experiment", "stop"] = doc.experiment.at("stopTime")
    connections = doc.root.el.find(ssp_schema.SSD, "Connections")
    s["connections",] = connections.span if connections is not None else doc.root.el.span
    for leaf in leaves.values():
        el = leaf.component.el
        s["instances", leaf.instance] = el.span
        s["instances", leaf.instance, "fmu"] = el.at("source")
        s["instances", leaf.instance, "interface"] = el.at("implementation")
        spec = instances.get(leaf.instance)
        for var, (_value, span) in spec.start.items() if spec is not None else ():
            s["instances", leaf.instance, "start", var] = span
        for clock, (_timing, span) in spec.clocks.items() if spec is not None else ():
            s["instances", leaf.instance, "clocks", clock] = span
    return table


def _experiment(doc: Document, system: System, spans: PathSpans, sink: DiagnosticSink) -> None:
    """The start and stop times, and robogen's settings from the robogen annotation."""
    if doc.experiment is not None:
        system.start = float(doc.experiment.get("startTime", "0"))
        if doc.experiment.get("stopTime") is not None:
            system.stop = float(doc.experiment.get("stopTime"))
        if not math.isfinite(system.start) or (system.stop is not None and not system.stop >= system.start):
            sink.error(f"stopTime {system.stop} is before startTime {system.start}", doc.experiment.at("stopTime"))
    for el in doc.settings:
        if el.ns == ROBOGEN_NS and el.tag == "Experiment":
            _settings(el, system, spans, sink)
        else:
            sink.error(f"a robogen annotation of the default experiment holds <rg:Experiment> (namespace {ROBOGEN_NS}), "
                       f"not <{el.tag}>", el.span)


def _settings(el: Element, system: System, spans: PathSpans, sink: DiagnosticSink) -> None:
    s = spans.spans
    s["experiment",] = el.span
    for name, value in el.attrib.items():
        s["experiment", {"maxEventIterations": "max_event_iterations"}.get(name, name)] = el.at(name)
        if name not in EXPERIMENT_ATTRS:
            sink.error(f"<rg:Experiment> has no attribute '{name}'{did_you_mean(name, EXPERIMENT_ATTRS)}", el.at(name))
        elif name in ("step", "tolerance"):
            number = _number(value)
            if number is None or not number > 0:
                sink.error(f"'{name}' must be a positive number, not '{value}'", el.at(name))
            else:
                setattr(system, name, number)
        elif name == "maxEventIterations":
            if not value.strip().isdigit() or int(value) < 1:
                sink.error(f"'{name}' must be a positive integer, not '{value}'", el.at(name))
            else:
                system.max_event_iterations = int(value)
        else:
            system.order = value.split()
            for o in system.order:
                if o not in system.instances:
                    sink.error(f"unknown instance '{o}' in order{did_you_mean(o, system.instances)}", el.at(name))
            if len(set(system.order)) != len(system.order):
                sink.error("an instance appears twice in 'order'", el.at(name))
    for child in el.children:
        if child.ns == ROBOGEN_NS and child.tag == "Record":
            _record(child, system, spans, sink)
        else:
            sink.error(f"<rg:Experiment> holds <rg:Record>, not <{child.tag}>", child.span)


def _record(el: Element, system: System, spans: PathSpans, sink: DiagnosticSink) -> None:
    """<rg:Record every="0.1"> with <rg:Variables><rg:Variable name="..."/></rg:Variables> (no
    <rg:Variables>: the default record list)."""
    spans.spans["record",] = el.span
    for name, value in el.attrib.items():
        number = _number(value)
        if name != "every":
            sink.error(f"<rg:Record> has no attribute '{name}'", el.at(name))
        elif number is None or not number > 0:
            sink.error(f"'every' must be a positive number, not '{value}'", el.at(name))
        else:
            system.record_every = number
    for child in el.children:
        if child.ns != ROBOGEN_NS or child.tag != "Variables":
            sink.error(f"<rg:Record> holds <rg:Variables>, not <{child.tag}>", child.span)
            continue
        system.record = []
        for i, variable in enumerate(child.children):
            if variable.ns != ROBOGEN_NS or variable.tag != "Variable" or "name" not in variable.attrib:
                sink.error("<rg:Variables> holds <rg:Variable name=\"instance.variable\"/> elements", variable.span,
                           Note("a name is a variable's or a pattern, as in a system file's [record] variables"))
                continue
            system.record.append((variable.get("name"), variable.at("name")))
            spans.spans["record", "variables", i] = variable.at("name")


def _number(text: str) -> float | None:
    try:
        value = float(text)
    except ValueError:
        return None
    return value if math.isfinite(value) else None
