"""Parameter bindings applied: the start values of the instances an SSP's hierarchy becomes.

A binding on a component names the FMU's variables; a binding on a system names, hierarchically,
its connectors (``P``) and its elements' variables and connectors (``C.P``, ``S.C.P``), where a
name may reach several (the standard's punning) and a name that reaches nothing is not applied
(with a warning). Bindings higher in the hierarchy win over lower ones, a later binding over an
earlier one at the same level. A value bound to a system connector goes to every FMU input that
connector feeds (its connections traced as :mod:`robogen.cosim.ssp_flatten` traces them), converted
along the way like a connected value. Each value is converted to its variable: from its unit to
the variable's, then by its mapping's linear transformation; an enumeration item by name to its
value in the FMU's enumeration type.
"""

from __future__ import annotations

from robogen.cosim.ssp_flatten import Edge, Flattener, Leaf, Node, Path_
from robogen.cosim.ssp_model import Binding, SystemNode
from robogen.cosim.ssp_package import Package
from robogen.cosim.ssp_params import INTEGERS, REALS, Value, bound_values
from robogen.cosim.units import Scale, UnitMismatch, apply, compose, conversion
from robogen.diagnostics import DiagnosticSink, Note, Span
from robogen.fmu.modeldesc import ModelDescription, Variable

#: The FMI types a value of each SSV type may start.
FITS = {**{t: ("Float32", "Float64") for t in REALS},
        **{t: ("Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32", "Int64", "UInt64", "Enumeration", "Float32", "Float64")
           for t in INTEGERS},
        "Boolean": ("Boolean",), "String": ("String",), "Enumeration": ("Enumeration",)}

Target = tuple[str, tuple, str | None]  # ("var", (system path, component), variable) or ("conn", node, None)


class StartValues:
    """Collects the bindings of a hierarchy and turns them into the instances' start values."""

    def __init__(self, flattener: Flattener, package: Package, sink: DiagnosticSink, unit_of):
        self.flattener, self.package, self.sink, self.unit_of = flattener, package, sink, unit_of
        self.leaves = flattener.flat.leaves
        self.assigned: list[tuple[int, int, Target, Value]] = []

    def collect(self, system: SystemNode, path: Path_ = ()) -> None:
        """Every binding of ``system`` and below, with its level (deeper first when applied)."""
        for name, element in system.elements.items():
            if isinstance(element, SystemNode):
                self.collect(element, path + (name,))
            elif (path, name) in self.leaves:
                leaf = self.leaves[path, name]
                for binding in element.bindings:
                    for value in self._values(binding, leaf):
                        self._component_target(leaf, (path, name), value)
        for binding in system.bindings:
            for value in self._values(binding, None):
                targets = self._targets(system, path, value.name)
                if not targets:
                    self._not_applied(value, f"system '{system.name}' has no parameter, connector or element variable of that name")
                for target in targets:
                    self.assigned.append((-len(path), len(self.assigned), target, value))

    def _values(self, binding: Binding, leaf: Leaf | None) -> list[Value]:
        fmu = self.flattener.fmus.get(leaf.instance) if leaf is not None else None
        return bound_values(binding, self.package, self.sink, fmu)

    def _component_target(self, leaf: Leaf, key: tuple, value: Value) -> None:
        if leaf.md is None:
            return
        if value.name not in leaf.md.by_name():
            self._not_applied(value, f"the FMU of component '{leaf.component.name}' has no such variable")
            return
        self.assigned.append((-leaf.depth, len(self.assigned), ("var", key, value.name), value))

    def _not_applied(self, value: Value, why: str) -> None:
        self.sink.warning(f"parameter '{value.name}' is not applied: {why}", value.span)

    def _targets(self, system: SystemNode, path: Path_, name: str) -> list[Target]:
        """What ``name`` reaches in ``system`` (hierarchical names, every reading of them)."""
        found: list[Target] = []
        if name in system.connectors:
            found.append(("conn", (path, None, name), None))
        for element_name, element in system.elements.items():
            if not name.startswith(element_name + "."):
                continue
            rest = name[len(element_name) + 1:]
            if isinstance(element, SystemNode):
                found += self._targets(element, path + (element_name,), rest)
            elif (path, element_name) in self.leaves and self.leaves[path, element_name].md is not None \
                    and rest in self.leaves[path, element_name].md.by_name():
                found.append(("var", (path, element_name), rest))
        return found

    # -- applying -------------------------------------------------------------------------------
    def start_values(self) -> dict[str, dict[str, tuple[object, Span]]]:
        """Per instance, its variables' start values (the bindings applied in precedence order)."""
        final: dict[tuple[tuple, str], tuple[Value, Node | None, list[Edge]]] = {}
        for _level, _seq, (what, key, var), value in sorted(self.assigned, key=lambda a: (a[0], a[1])):
            if what == "var":
                final[key, var] = (value, None, [])
                continue
            for node, (origin, edges) in self.flattener.flat.fed.items():
                if origin == key:
                    final[(node[0], node[1]), node[2]] = (value, origin, edges)
        starts: dict[str, dict[str, tuple[object, Span]]] = {}
        for (key, var), (value, origin, edges) in final.items():
            leaf = self.leaves[key]
            if leaf.md is None or var not in leaf.md.by_name():
                continue  # its FMU, or its variable, is missing: reported already
            converted = self._converted(value, leaf, var, origin, edges)
            if converted is not None:
                starts.setdefault(leaf.instance, {})[var] = (converted, value.span)
        return starts

    def _converted(self, value: Value, leaf: Leaf, name: str, origin: Node | None, edges: list[Edge]):
        """The value as a start value of the FMU variable ``name`` (None: a problem, reported)."""
        md = leaf.md
        var = md.by_name()[name]
        if value.type == "Binary":
            self.sink.error("Binary parameter values are not supported (no more than in a system file)", value.span)
            return None
        if var.type not in FITS.get(value.type, ()):
            self.sink.error(f"parameter '{value.name}' is {value.type}, but '{leaf.instance}.{name}' is {var.type}", value.span)
            return None
        if value.type == "Enumeration":
            return self._items(value, md, var, leaf.instance)
        if var.type not in ("Float32", "Float64"):
            return value.python()
        scale = self._scale(value, origin, edges, (leaf.path, leaf.component.name, name))
        if scale is False:
            return None
        converted = [apply(scale, float(v)) for v in value.values]
        return converted if value.array else converted[0]

    def _scale(self, value: Value, origin: Node | None, edges: list[Edge], node: Node) -> Scale | None | bool:
        """The conversion of a real value: to the unit of what it is bound to, its mapping's
        linear transformation, then along the connections from a system connector."""
        first = self.unit_of(origin if origin is not None else node)
        scale: Scale | None = None
        if first is not None and value.unit is not None and not value.suppress_units:
            try:
                scale = conversion(value.unit, first)
            except UnitMismatch as exc:
                self.sink.error(f"parameter '{value.name}': {exc}", value.span,
                                Note("suppressUnitConversion=\"true\" on its mapping entry applies it without converting"))
                return False
        scale = compose(scale, value.linear)
        if origin is None:
            return scale
        along = self.flattener.scale(edges, first or value.unit, self.unit_of)
        return False if along is False else compose(scale, along)

    def _items(self, value: Value, md: ModelDescription, var: Variable, instance: str):
        """Enumeration items by name, as the values of the variable's enumeration type."""
        kind = next((t for t in md.type_definitions if t.name == var.declared_type), None)
        items = {i.name: i.value for i in kind.items} if kind is not None else {}
        missing = [v for v in value.values if v not in items]
        if missing:
            self.sink.error(f"'{missing[0]}' is not an item of the enumeration type {var.declared_type} of "
                            f"'{instance}.{var.name}'", value.span, Note(f"its items: {', '.join(items) or 'none'}"))
            return None
        numbers = [items[v] for v in value.values]
        return numbers if value.array else numbers[0]
