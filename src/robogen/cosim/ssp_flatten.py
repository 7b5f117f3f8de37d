"""A hierarchy of SSP systems flattened to robogen's instances and connections.

Each FMU component becomes an instance, named by its path from the root system (nested systems'
names and its own joined by ``__``, each made an identifier). System connectors are junctions:
a connection's direction follows from the kinds of its ends (an element's output, or a system's
own input, is where data comes from), and every FMU input is traced back through the junctions
to the FMU output that drives it, which gives one robogen connection. Along that path the value
is converted wherever it crosses units (the connectors' ``unit``, else the FMU variable's; a
system connector without one passes the unit through) and by each connection's
``LinearTransformation``; the composed conversion is the connection's ``scale``. An FMU input
traced back to a system connector that nothing drives takes the value bound to that connector,
as a start value.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from robogen.cosim.ssp_model import Component, Connection, Connector, Document, SystemNode
from robogen.cosim.system import Connection as Link, Endpoint
from robogen.cosim.units import SI_BASE_UNITS, Scale, UnitDef, UnitMismatch, compose, conversion
from robogen.diagnostics import DiagnosticSink, Note, Span, did_you_mean
from robogen.fmu.modeldesc import ModelDescription, Variable

#: Connector kinds data flows out of, seen from outside an element (and into, seen from inside a system).
OUT_KINDS = ("output", "calculatedParameter", "constant", "local")
IN_KINDS = ("input", "parameter", "structuralParameter")
SEPARATOR = "__"

Path_ = tuple[str, ...]  # element names from the root system
Node = tuple[Path_, str | None, str]  # (system, component or None for the system's own connector, connector)


@dataclass
class Leaf:
    """An FMU component of the hierarchy and the instance it becomes."""

    instance: str
    path: Path_  # its system's path
    component: Component
    md: ModelDescription | None = None
    depth: int = 0


@dataclass
class Edge:
    source: Node
    target: Node
    connection: Connection


@dataclass
class Flat:
    """The hierarchy's FMU components (by their component node key) and connections."""

    leaves: dict[tuple[Path_, str], Leaf]
    links: list[Link] = field(default_factory=list)
    #: per FMU input fed by a system connector that nothing drives: (that connector, the path's edges)
    fed: dict[Node, tuple[Node, list[Edge]]] = field(default_factory=dict)


def instance_names(doc: Document, sink: DiagnosticSink) -> dict[tuple[Path_, str], Leaf]:
    """Every FMU component of ``doc`` with its instance name; a clash between names is an error."""
    leaves: dict[tuple[Path_, str], Leaf] = {}
    taken: dict[str, Span] = {}

    def walk(system: SystemNode, path: Path_) -> None:
        for name, element in system.elements.items():
            if isinstance(element, SystemNode):
                walk(element, path + (name,))
                continue
            instance = SEPARATOR.join(_identifier(n) for n in path + (name,))
            if instance in taken:
                sink.error(f"component '{'.'.join(path + (name,))}' and another become the same instance '{instance}'",
                           element.el.at("name"), Note("the other is here", taken[instance]),
                           Note(f"robogen names a nested component by its systems' names and its own joined by '{SEPARATOR}'"))
                continue
            taken[instance] = element.el.at("name")
            leaves[path, name] = Leaf(instance, path, element, depth=len(path) + 1)

    walk(doc.root, ())
    return leaves


def _identifier(name: str) -> str:
    """An SSP element name as an instance name: characters other than letters, digits and '_' become '_'."""
    text = re.sub(r"[^A-Za-z0-9_]", "_", name)
    return "_" + text if not text or text[0].isdigit() else text


class Flattener:
    """Traces the connections of ``doc`` through its systems' connectors (see the module's docstring)."""

    def __init__(self, doc: Document, leaves: dict[tuple[Path_, str], Leaf], sink: DiagnosticSink):
        self.doc, self.sink = doc, sink
        self.flat = Flat(leaves)
        self.fmus: dict[str, Path] = {}  # per instance, its FMU file
        self.systems: dict[Path_, SystemNode] = {}
        self.incoming: dict[Node, Edge] = {}
        self._collect(doc.root, ())

    def _collect(self, system: SystemNode, path: Path_) -> None:
        self.systems[path] = system
        for name, element in system.elements.items():
            if isinstance(element, SystemNode):
                self._collect(element, path + (name,))
        for connection in system.connections:
            edge = self._edge(system, path, connection)
            if edge is None:
                continue
            first = self.incoming.get(edge.target)
            if first is not None:
                self.sink.error(f"'{self.label(edge.target)}' is connected twice", connection.el.span,
                                Note("first connected here", first.connection.el.span))
                continue
            self.incoming[edge.target] = edge

    # -- endpoints ------------------------------------------------------------------------------
    def connector(self, node: Node) -> Connector | None:
        path, component, name = node
        if component is not None:
            return self.flat.leaves[path, component].component.connectors.get(name)
        return self.systems[path].connectors.get(name)

    def label(self, node: Node) -> str:
        path, component, name = node
        return ".".join(path + ((component,) if component else ()) + (name,))

    def _end(self, system: SystemNode, path: Path_, end: tuple[str | None, str], el, attrs: tuple[str, str]) -> tuple[Node, bool] | None:
        """The node of one end of a connection, and whether it is seen from inside (a system's own)."""
        element_name, name = end
        if element_name is None:
            node, owner, inside = (path, None, name), system, True
        else:
            element = system.elements.get(element_name)
            if element is None:
                self.sink.error(f"system '{system.name}' has no element '{element_name}'{did_you_mean(element_name, system.elements)}",
                                el.at(attrs[0]))
                return None
            inside = False
            if isinstance(element, SystemNode):
                node, owner = (path + (element_name,), None, name), element
            elif (path, element_name) in self.flat.leaves:
                node, owner = (path, element_name, name), element
            else:
                return None  # a component refused already
        if name not in owner.connectors:
            what = "system" if isinstance(owner, SystemNode) else "component"
            notes = [Note(f"declare it in the <ssd:Connectors> of {what} '{owner.name}'", owner.el.span)]
            self.sink.error(f"{what} '{owner.name}' has no connector '{name}'{did_you_mean(name, owner.connectors)}",
                            el.at(attrs[1]), *notes)
            return None
        return node, inside

    def _edge(self, system: SystemNode, path: Path_, c: Connection) -> Edge | None:
        start = self._end(system, path, c.start, c.el, ("startElement", "startConnector"))
        end = self._end(system, path, c.end, c.el, ("endElement", "endConnector"))
        if start is None or end is None:
            return None
        flows = [_flows_out(self.connector(node).kind, inside) for node, inside in (start, end)]
        if flows[0] is None and flows[1] is None:
            self.sink.error(f"cannot tell which way '{self.label(start[0])}' and '{self.label(end[0])}' are connected: "
                            "both connectors are of kind unspecified or inout", c.el.span)
            return None
        out_first = flows[0] if flows[0] is not None else not flows[1]
        if flows[1] is not None and flows[1] == out_first:
            both = "produce" if out_first else "consume"
            kinds = [f"'{self.label(n)}' ({self.connector(n).kind}{', seen from inside its system' if i else ''})" for n, i in (start, end)]
            self.sink.error(f"a connection needs one end that produces a value and one that consumes it; both {both} "
                            f"one: {kinds[0]} and {kinds[1]}", c.el.span)
            return None
        source, target = (start[0], end[0]) if out_first else (end[0], start[0])
        return Edge(source, target, c)

    # -- tracing --------------------------------------------------------------------------------
    def trace(self, node: Node) -> tuple[Node, list[Edge]] | None:
        """The node that drives ``node`` through junctions, and the edges from it (None: nothing does)."""
        edges: list[Edge] = []
        seen = {node}
        while node in self.incoming:
            edge = self.incoming[node]
            edges.insert(0, edge)
            node = edge.source
            if node[1] is not None:
                return node, edges
            if node in seen:
                self.sink.error(f"the connections through '{self.label(node)}' form a loop of system connectors", edge.connection.el.span)
                return None
            seen.add(node)
        return (node, edges) if edges else None

    def links(self, unit_of) -> list[Link]:
        """Every FMU input traced to its FMU output: robogen's connections, in the order of the
        connections into the inputs in the file (``unit_of(node)``: the unit of a connector, or None)."""
        for (path, name), leaf in self.flat.leaves.items():
            for connector in leaf.component.connectors:
                node = (path, name, connector)
                traced = self.trace(node) if node in self.incoming else None
                if traced is None:
                    continue
                origin, edges = traced
                if origin[1] is None:
                    self.flat.fed[node] = traced
                    continue
                scale = self.scale(edges, unit_of(origin), unit_of)
                if scale is False:
                    continue
                span = edges[-1].connection.el.span
                src_leaf = self.flat.leaves[origin[0], origin[1]]
                self.flat.links.append(Link(Endpoint(src_leaf.instance, origin[2], span), Endpoint(leaf.instance, connector, span),
                                            span, scale or None))
        self.flat.links.sort(key=lambda link: (link.span.line, link.span.column))  # in the file's order
        return self.flat.links

    def scale(self, edges: list[Edge], unit: UnitDef | None, unit_of) -> Scale | None | bool:
        """The conversion along ``edges`` of a value in ``unit``: unit conversions where a
        connection's ends have units, each connection's linear transformation after; False with
        the problem reported."""
        scale: Scale | None = None
        for edge in edges:
            c, target = edge.connection, unit_of(edge.target)
            if target is not None and unit is not None and not c.suppress_units:
                try:
                    scale = compose(scale, conversion(unit, target))
                except UnitMismatch as exc:
                    self.sink.error(f"{exc} (connection '{self.label(edge.source)} -> {self.label(edge.target)}')", c.el.span,
                                    Note("suppressUnitConversion=\"true\" connects them without converting"))
                    return False
            unit = target if target is not None else unit
            t = c.transformation
            if t is not None and t.kind != "linear":
                self.sink.error(f"a {t.el.tag} on a connection is not supported: robogen converts connected values "
                                "linearly only (units, LinearTransformation)", t.el.span)
                return False
            if t is not None:
                scale = compose(scale, (t.factor, t.offset))
        return scale


def _flows_out(kind: str, inside: bool) -> bool | None:
    """Whether data leaves a connector of ``kind`` through a connection (None: either way)."""
    if kind in OUT_KINDS:
        return not inside
    if kind in IN_KINDS:
        return inside
    return None


def fmu_unit(md: ModelDescription, var: Variable) -> UnitDef | None:
    """The unit of an FMU variable, as its model description defines it (None: none)."""
    if var.unit is None:
        return None
    for unit in md.unit_definitions:
        if unit.name == var.unit and unit.base_unit is not None:
            exponents = dict(unit.base_unit)
            return UnitDef(unit.name, tuple(exponents.get(k, 0) for k in SI_BASE_UNITS),
                           float(unit.factor or 1), float(unit.offset or 0))
    return UnitDef(var.unit)
