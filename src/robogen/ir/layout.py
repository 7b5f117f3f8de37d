"""The FMI variables of a value: how a value of any type the FMU shows (an event's payload, an
operation's argument, a machine variable as a local variable) is laid out as scalar and array
variables, and how the reference interpreter reads them out of a value and assembles a value
from them. The generated C does the same in :mod:`robogen.codegen.layout_code`.

Each *leaf* is one FMI variable: its name (after the value's own name), its path inside the
value and its FMI type. A record is its fields' leaves (``.x``, ``.at.y``). A set or sequence is
the leaves of its elements under ``.elements``, each with one more array dimension of the
collection's capacity, then ``.size``: for a collection of scalars ``.elements`` (an array of
the capacity, zeros after the last element) and ``.size``; of records, ``.elements.<field>``
per scalar field; of collections, ``.elements.elements`` (two dimensions) and
``.elements.size`` (one per element of the outer collection), and so on, one level at a time: a
``Seq(Seq(Seq(int)))`` of capacities 4, 3, 2 is ``elements.elements.elements`` [4][3][2],
``elements.elements.size`` [4][3], ``elements.size`` [4] and ``size``. A vector or matrix adds
its own dimensions last. Arrays are row-major; entries past a collection's size are zeros (the
empty string for strings).

In a path, ``#elements`` steps into every element of a collection and ``#size`` is its count.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from robogen.ir.supported import ArrayT, FunMapT, TaggedT
from robogen.semantics import types as T


@dataclass(frozen=True)
class Leaf:
    """One FMI variable of a value: ``name`` after the value's name (``("elements", "x")``),
    ``path`` inside the value, ``type`` a scalar, a string, or an array (a vector for one
    dimension, a matrix for a matrix outside collections, else :class:`ArrayT`)."""

    name: tuple[str, ...]
    path: tuple[str, ...]
    type: T.Type


def _array(element: T.Type, dims: tuple[int, ...]) -> T.Type:
    if not dims:
        return element
    if len(dims) == 1:
        return T.VectorT(element, dims[0])
    return ArrayT(element, dims)


def _shape(t: T.Type) -> tuple[T.Type, tuple[int, ...]]:
    if isinstance(t, T.VectorT):
        return t.element, (t.size or 0,)
    if isinstance(t, T.MatrixT):
        return t.element, (t.rows or 0, t.columns or 0)
    return t, ()


def leaves(t: T.Type, capacity_of: Callable[[T.Type], int], name: tuple[str, ...] = (), path: tuple[str, ...] = (),
           dims: tuple[int, ...] = ()) -> list[Leaf]:
    """The FMI variables of a value of type ``t`` (see the module documentation), in order. A
    function value has none (robogen.ir.functions: its default is robogen's numbering of the
    model's lambdas; an FMU port of one is a located error, robogen.ir.ports)."""
    if isinstance(t, FunMapT):
        return []
    if isinstance(t, T.RecordT):
        out: list[Leaf] = []
        for n, ft in t.fields:
            out += leaves(ft, capacity_of, name + (n,), path + (n,), dims)
        return out
    if isinstance(t, (T.SetT, T.SeqT)):
        inner = dims + (capacity_of(t),)
        out = leaves(t.element, capacity_of, name + ("elements",), path + ("#elements",), inner)
        return out + [Leaf(name + ("size",), path + ("#size",), _array(T.NAT, dims))]
    if dims and isinstance(t, (T.VectorT, T.MatrixT)):
        element, own = _shape(t)
        return [Leaf(name, path, _array(element, dims + own))]
    return [Leaf(name, path, _array(t, dims) if dims else t)]


def nested(t: T.Type) -> bool:
    """Whether a value of ``t`` has a part that is not a record field, a vector, or a collection
    of scalars or of records of scalars (the forms the C runtime reads and writes without a loop
    per nesting level; robogen.codegen.layout_code writes the others)."""
    if isinstance(t, T.RecordT):
        return any(nested(ft) for _, ft in t.fields)
    if isinstance(t, (T.SetT, T.SeqT)):
        return _deep(t.element)
    return False


def _deep(t: T.Type) -> bool:
    """An element type of a collection that needs more than one array per field."""
    if isinstance(t, TaggedT):
        return True
    if isinstance(t, FunMapT):
        return False  # no FMI variables
    if isinstance(t, T.RecordT):
        return any(_deep(ft) for _, ft in t.fields)
    return isinstance(t, (T.SetT, T.SeqT, T.VectorT, T.MatrixT))


def width(t: T.Type, path: tuple[str, ...], capacity_of) -> int:
    """How many entries of the leaf at ``path`` one value of ``t`` fills."""
    if not path:
        n = 1
        for d in _shape(t)[1]:
            n *= d
        return n
    p = path[0]
    if p == "#size":
        return 1
    if p == "#elements":
        return capacity_of(t) * width(t.element, path[1:], capacity_of)  # type: ignore[attr-defined]
    return width(t.field(p), path[1:], capacity_of)  # type: ignore[attr-defined, arg-type]


def gather(v, t: T.Type, path: tuple[str, ...], capacity_of, zero) -> list:
    """The entries of the leaf at ``path`` of value ``v`` of type ``t``, row-major (``zero``:
    the padding past a collection's size, of the leaf's scalar type)."""
    if not path:
        return list(v) if isinstance(t, (T.VectorT, T.MatrixT)) else [v]
    p = path[0]
    if p == "#size":
        return [len(v)]
    if p == "#elements":
        each = width(t.element, path[1:], capacity_of)  # type: ignore[attr-defined]
        out: list = []
        for i in range(capacity_of(t)):
            out += gather(v[i], t.element, path[1:], capacity_of, zero) if i < len(v) else [zero] * each  # type: ignore[attr-defined]
        return out
    return gather(v[p], t.field(p), path[1:], capacity_of, zero)  # type: ignore[attr-defined, arg-type]


def build(t: T.Type, path: tuple[str, ...], pos: int, read, capacity_of, received, default):
    """The value of type ``t`` at ``path`` that an FMU input assembles from its leaves: ``read(path,
    pos, n)`` gives the ``n`` entries of the leaf at ``path`` from entry ``pos * n`` (n = 1: one
    entry); a collection takes its first ``size`` elements, at most its capacity, through
    ``received(items, type)`` (a set in canonical order); an argument of an enumeration literal
    only when the tag selects the literal (``default(type)`` otherwise)."""
    if isinstance(t, (T.SetT, T.SeqT)):
        cap = capacity_of(t)
        size = int(read(path + ("#size",), pos, 1)[0])
        items = [build(t.element, path + ("#elements",), pos * cap + i, read, capacity_of, received, default)
                 for i in range(max(0, min(size, cap)))]
        return received(items, t)
    if isinstance(t, TaggedT):
        tag = build(t.tag, path + ("tag",), pos, read, capacity_of, received, default)
        literal = t.tag.literals[tag] if 0 <= tag < len(t.tag.literals) else None
        value = {"tag": tag}
        for n, ft in t.fields[1:]:
            mine = n.rsplit("_", 1)[0] == literal
            value[n] = build(ft, path + (n,), pos, read, capacity_of, received, default) if mine else default(ft)
        return value
    if isinstance(t, FunMapT):  # no FMI variables
        return default(t)
    if isinstance(t, T.RecordT):
        return {n: build(ft, path + (n,), pos, read, capacity_of, received, default) for n, ft in t.fields}
    n = width(t, (), capacity_of)
    entries = read(path, pos, n)
    return list(entries) if isinstance(t, (T.VectorT, T.MatrixT)) else entries[0]


__all__ = ["Leaf", "leaves", "nested", "gather", "build", "width"]
