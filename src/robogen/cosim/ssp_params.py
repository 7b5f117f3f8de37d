"""Parameter bindings: the values of an SSV parameter set (inline or a ``.ssv`` file), renamed and
transformed by an optional parameter mapping (inline or a ``.ssm`` file), as named values.

:func:`bound_values` gives, for one ``<ssd:ParameterBinding>``, the values it applies, each under
the name it is applied to (the binding's prefix prepended; with a mapping, only the mapped
parameters, under their target names), typed by its SSV element, with its unit and the linear
transformation that follows the unit conversion (both applied where the target is known,
:mod:`robogen.cosim.ssp_flatten`). Boolean, integer and enumeration mapping transformations are
applied here: they map values to values.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

from robogen.cosim import ssp_schema
from robogen.cosim.ssp_model import Binding, Transformation, read_units, transformation
from robogen.cosim.ssp_package import Package, read_member
from robogen.cosim.ssp_schema import SSC, SSM, SSV
from robogen.cosim.units import UnitDef
from robogen.cosim.xmltree import Element, parse
from robogen.diagnostics import DiagnosticSink, Note, RobogenError, Span

REALS = ("Real", "Float64", "Float32")
INTEGERS = ("Integer", "Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32", "Int64", "UInt64")
_TRUE = ("true", "1")


@dataclass(frozen=True)
class Value:
    """A value a binding applies: to ``name`` (relative to the element the binding is on)."""

    name: str
    type: str  # its SSV element: Real, Float64, ..., Integer, Int8, ..., Boolean, String, Enumeration, Binary
    values: tuple  # floats, ints, bools, strings (Enumeration: item names), bytes
    array: bool  # given with <ssc:Dimension> or as several values
    span: Span
    unit: UnitDef | None = None
    linear: tuple[float, float] | None = None  # a mapping's LinearTransformation, after unit conversion
    suppress_units: bool = False

    def python(self):
        """The value as a start value: one value, or a list for an array."""
        return list(self.values) if self.array else self.values[0]


def bound_values(binding: Binding, package: Package, sink: DiagnosticSink, component_fmu: Path | None) -> list[Value]:
    """The values ``binding`` applies (see the module's docstring); problems into ``sink``."""
    parameter_set = _document(binding.values, binding.source, binding.el, binding.source_base, "SSV", package, sink, component_fmu)
    if parameter_set is None:
        return []
    units = read_units(parameter_set.find(SSV, "Units"), sink)
    values = [v for p in parameter_set.path(SSV, "Parameters", "Parameter") if (v := _value(p, units, sink)) is not None]
    values = [replace(v, name=binding.prefix + v.name) for v in values]
    if binding.mapping is None:
        return values
    inline = binding.mapping.children[0] if binding.mapping.children else None
    mapping = _document(inline, binding.mapping.get("source"), binding.mapping, binding.mapping.get("sourceBase", "SSD"),
                        "SSM", package, sink, component_fmu)
    return _mapped(values, mapping, sink) if mapping is not None else []


def _document(inline: Element | None, source: str | None, el: Element, base: str, what: str, package: Package,
              sink: DiagnosticSink, component_fmu: Path | None) -> Element | None:
    """The SSV or SSM root element a binding gives inline or names by ``source``."""
    root_tag = {"SSV": (SSV, "ParameterSet"), "SSM": (SSM, "ParameterMapping")}[what]
    if source is None:
        if inline is None or (inline.ns, inline.tag) != root_tag or len(inline.parent.children) != 1:
            sink.error(f"<{el.tag}> must hold one <{what.lower()}:{root_tag[1]}>", el.span)
            return None
        return inline
    if base == "component":
        if component_fmu is None:
            sink.error("sourceBase=\"component\" names a file inside a component's FMU; this binding is on a system",
                       el.at("sourceBase"))
            return None
        read = read_member(component_fmu, source, el.at("source"), sink, package)
        if read is None:
            return None
        data, display = read
    else:
        file = package.resolve(source, el.at("source"), sink, what=f"{what} file")
        if file is None:
            return None
        data, display = file.read_bytes(), package.display(file)
    try:
        root, assumed = parse(data, display, ssp_schema.PREFIXES)
    except RobogenError as exc:
        sink.extend(exc.diagnostics)
        return None
    if assumed:
        sink.add(ssp_schema.assumed_prefixes(assumed, root.span))
    problems = ssp_schema.check(root, what)
    sink.extend(problems)
    return None if problems else root


def _value(p: Element, units: dict[str, UnitDef], sink: DiagnosticSink) -> Value | None:
    typed = next(c for c in p.children if c.ns == SSV)  # the schema requires it first
    kind, name = typed.tag, p.get("name", "")
    children = [v.get("value", "") for v in typed.findall(SSV, "Value")]
    if children and typed.get("value") is not None:
        sink.error(f"parameter '{name}' gives its value both as an attribute and as <ssv:Value> elements", typed.span)
        return None
    texts = children or (typed.get("value", "").split() if kind in REALS + INTEGERS + ("Boolean",) else [typed.get("value", "")])
    if kind in REALS:
        values: tuple = tuple(float(t) for t in texts)
    elif kind in INTEGERS:
        values = tuple(int(t) for t in texts)
    elif kind == "Boolean":
        values = tuple(t.strip() in _TRUE for t in texts)
    elif kind == "Binary":
        values = tuple(bytes.fromhex(t) for t in texts)
    else:
        values = tuple(texts)
    dims = [int(d.get("size", "0")) for d in p.findall(SSC, "Dimension")]
    if dims and _product(dims) != len(values):
        sink.error(f"parameter '{name}' has {len(values)} values for dimensions {' x '.join(map(str, dims))}", typed.span)
        return None
    if not values:
        sink.error(f"parameter '{name}' has no value", typed.span)
        return None
    unit = None
    if typed.get("unit") is not None:
        unit = units.get(typed.get("unit", ""))
        if unit is None:
            sink.error(f"unit '{typed.get('unit')}' is not defined in the parameter set's <ssv:Units>", typed.at("unit"))
            return None
    return Value(name, kind, values, bool(dims) or len(values) > 1, p.span, unit)


def _product(dims: list[int]) -> int:
    n = 1
    for d in dims:
        n *= d
    return n


def _mapped(values: list[Value], mapping: Element, sink: DiagnosticSink) -> list[Value]:
    """The values a parameter mapping applies: each entry's source value under its target name,
    transformed by the entry's transformation."""
    by_name = {v.name: v for v in values}
    targets: dict[str, Span] = {}
    out = []
    for entry in mapping.findall(SSM, "MappingEntry"):
        source, target = entry.get("source", ""), entry.get("target", "")
        if target in targets:
            sink.error(f"two mapping entries map to '{target}'", entry.at("target"), Note("the first is here", targets[target]))
            continue
        targets[target] = entry.at("target")
        value = by_name.get(source)
        if value is None:
            continue  # the parameter set does not give it: nothing to apply
        mapped = _transformed(value, transformation(entry), sink)
        if mapped is not None:
            out.append(replace(mapped, name=target, span=entry.span, suppress_units=entry.get("suppressUnitConversion") in _TRUE))
    return out


def _transformed(value: Value, t: Transformation | None, sink: DiagnosticSink) -> Value | None:
    if t is None:
        return value
    fits = {"linear": REALS, "boolean": ("Boolean",), "integer": INTEGERS, "enumeration": ("Enumeration",)}[t.kind]
    if value.type not in fits:
        sink.error(f"a {t.el.tag} applies to {' or '.join(fits)} parameters; '{value.name}' is {value.type}", t.el.span)
        return None
    if t.kind == "linear":
        return replace(value, linear=(t.factor, t.offset))
    if t.kind == "boolean":
        table = {k.strip() in _TRUE: v.strip() in _TRUE for k, v in t.entries.items()}
    elif t.kind == "integer":
        table = {int(k): int(v) for k, v in t.entries.items()}
    else:
        table = dict(t.entries)
    return replace(value, values=tuple(table.get(v, v) for v in value.values))
