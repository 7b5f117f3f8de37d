"""What code generation supports: the concrete types of IR values, and the located error for a
construct that has no code-generation meaning yet (reported, never silently dropped)."""

from __future__ import annotations

from dataclasses import dataclass

from robogen.diagnostics import RobogenError, Span
from robogen.semantics import types as T


def not_supported(what: str, span: Span | None) -> RobogenError:
    return RobogenError.at(f"{what} is not supported for code generation", span)


@dataclass(frozen=True, slots=True)
class TupleT(T.RecordT):
    """A product ``A * B`` as code generation represents it: a record whose fields ``_1``,
    ``_2``, ... are its components (``p[k]`` selects field ``_k``), so that tuples share the
    records' C structs, equality, FMI variables and interpreter values."""

    def show(self) -> str:
        return " * ".join(f"({t.show()})" if isinstance(t, TupleT) else t.show() for _, t in self.fields)


def tuple_type(items: tuple[T.Type, ...]) -> TupleT:
    """The code-generation type of a product of ``items`` (already normalised)."""
    return TupleT("tuple(" + ",".join(t.show() for t in items) + ")", tuple((f"_{i + 1}", t) for i, t in enumerate(items)))


@dataclass(frozen=True, slots=True)
class TaggedT(T.RecordT):
    """An enumeration some of whose literals carry arguments (``EM2(real)``), as code generation
    represents it: a record whose field ``tag`` is the literal (a plain enumeration of the same
    literals, so an FMI Enumeration variable) and, per argument ``k`` of literal ``L``, a field
    ``L_k``. A value sets the fields of its own literal's arguments and leaves the others at their
    type's default, so the records' equality is the literals': same literal and equal arguments;
    records give the C struct, FMI variables and interpreter values. ``level``: as
    :class:`InnerRecordT`'s, for one whose arguments hold collections."""

    level: int = 0

    def show(self) -> str:
        return self.qname

    @property
    def tag(self) -> T.EnumT:
        t = self.fields[0][1]
        assert isinstance(t, T.EnumT)
        return t

    def arg_fields(self, literal: str) -> tuple[tuple[str, T.Type], ...]:
        """The fields of the arguments of ``literal``, in order."""
        return tuple((n, t) for n, t in self.fields[1:] if n.rsplit("_", 1)[0] == literal)


@dataclass(frozen=True, slots=True)
class InnerSetT(T.SetT):
    """A set inside another set or sequence (directly, or in a field of its elements), whose
    nesting level holds at most ``capacity`` elements, not the FMU's first capacity
    (``--capacity 32,8``: see :func:`normalise`). A type of its own, so that the C type and
    the interpreter's overflow checks follow it; a value of it used where the outermost level's
    type is expected is converted (``conv``), and the other way a run-time error if it would
    not fit."""

    capacity: int


@dataclass(frozen=True, slots=True)
class InnerSeqT(T.SeqT):
    """A sequence at a nesting level of another capacity (see :class:`InnerSetT`)."""

    capacity: int


@dataclass(frozen=True, slots=True)
class InnerRecordT(T.RecordT):
    """A record inside a collection whose fields hold collections of that nesting level's
    capacity: another C struct than the record's outside collections. ``level`` is the first
    nesting level whose capacities give these fields (its C name ``rg_rec<level>_<name>``)."""

    level: int

    def show(self) -> str:
        return self.qname


@dataclass(frozen=True, slots=True)
class ArrayT(T.Type):
    """An FMI array variable of several dimensions (``<Dimension>`` each, row-major), of scalars
    or strings: a part of the values of a collection nested in collections, at an FMU port or as
    a local variable (robogen.ir.ports). Only FMI variables have this type, never model values."""

    element: T.Type
    dims: tuple[int, ...]

    @property
    def size(self) -> int:
        n = 1
        for d in self.dims:
            n *= d
        return n

    def show(self) -> str:
        return f"array({self.element.show()}, {', '.join(map(str, self.dims))})"


def capacity_at(capacities: tuple[int, ...], level: int) -> int:
    """The capacity of a collection at nesting ``level`` (0: outermost): one per level, the last
    for every deeper level."""
    return capacities[min(level, len(capacities) - 1)]


def _collection(kind: type, element: T.Type, capacities: tuple[int, ...], level: int) -> T.Type:
    capacity = capacity_at(capacities, level) if capacities else 0
    if not capacities or capacity == capacities[0]:
        return kind(element)
    return (InnerSetT if kind is T.SetT else InnerSeqT)(element, capacity)


def literal_conditions(t: T.Type, path: tuple[str, ...]) -> tuple[tuple[tuple[str, ...], int], ...]:
    """When the part at ``path`` of a value of type ``t`` holds an argument of an enumeration
    literal: (path of the tag, literal index) for each tagged record on the way. An input
    assembled from FMI variables takes an argument only when its tag selects that literal, and
    the argument's default otherwise, so that equal literals are equal records (only for a
    scalar part)."""
    found = []
    for i, name in enumerate(path):
        if isinstance(t, TaggedT) and name != "tag":
            found.append((path[:i] + ("tag",), t.tag.literals.index(name.rsplit("_", 1)[0])))
        t = t.field(name) if isinstance(t, T.RecordT) else T.UNKNOWN  # type: ignore[assignment]
    return tuple(found) if is_scalar(t) else ()  # (an array argument is taken as it is)


def tagged_type(t: T.EnumT, given: str, capacities: tuple[int, ...] = (), level: int = 0) -> TaggedT:
    tag = T.EnumT(t.qname, t.literals)
    fields = tuple((f"{lit}_{k + 1}", normalise(at, given, capacities, level))
                   for lit, args in zip(t.literals, t.literal_args) for k, at in enumerate(args))
    return TaggedT(t.qname, (("tag", tag),) + fields)


def normalise(t: T.Type, given: str = "int", capacities: tuple[int, ...] = (), level: int = 0) -> T.Type:
    """Replace given types by their concrete scalar type, and products by :class:`TupleT`,
    recursively. ``capacities``: the capacity of each nesting level of collections (outermost
    first, the last for every deeper one; empty: one capacity for all): a collection ``level``
    collections deep whose capacity is not the outermost one's is an :class:`InnerSetT` or
    :class:`InnerSeqT`, and a record there whose fields hold such collections an
    :class:`InnerRecordT` (a tagged record its own ``level``)."""
    t = T.single(t)
    if isinstance(t, (TupleT, TaggedT, InnerRecordT, InnerSetT, InnerSeqT, ArrayT)):
        return t  # already concrete
    if isinstance(t, T.Given):
        return T.PRIMITIVES[given]
    if isinstance(t, T.ProductT):
        return tuple_type(tuple(normalise(x, given, capacities, level) for x in t.items))
    if isinstance(t, (T.SetT, T.SeqT)):
        kind = T.SetT if isinstance(t, T.SetT) else T.SeqT
        return _collection(kind, normalise(t.element, given, capacities, level + 1), capacities, level)
    if isinstance(t, T.FunctionT) and t.relation:  # a relation is the set of its pairs
        pair = tuple_type((normalise(t.domain, given, capacities, level + 1), normalise(t.range, given, capacities, level + 1)))
        return _collection(T.SetT, pair, capacities, level)
    if isinstance(t, T.FunctionT):  # its parameters and result are values of their own (level 0)
        return T.FunctionT(normalise(t.domain, given, capacities), normalise(t.range, given, capacities), t.relation)
    if isinstance(t, T.RecordT) or (isinstance(t, T.EnumT) and any(t.literal_args)):
        return _record(t, given, capacities, level)
    if isinstance(t, T.VectorT):
        return T.VectorT(normalise(t.element, given), t.size)
    if isinstance(t, T.MatrixT):
        return T.MatrixT(normalise(t.element, given), t.rows, t.columns)
    if isinstance(t, T.EnumT) and t.literal_args:
        return T.EnumT(t.qname, t.literals)
    return t


def _record(t: T.RecordT | T.EnumT, given: str, capacities: tuple[int, ...], level: int) -> T.RecordT:
    """A record (or tagged enumeration) at nesting ``level``: its fields' collections have that
    level's capacities. Where they differ from the outermost level's, the type is the record of
    the first level that gives these fields (see :class:`InnerRecordT`)."""
    def at(k: int) -> T.RecordT:
        if isinstance(t, T.EnumT):
            return tagged_type(t, given, capacities, k)
        return T.RecordT(t.qname, tuple((n, normalise(ft, given, capacities, k)) for n, ft in t.fields))

    mine = at(level)
    if level == 0 or mine.fields == at(0).fields:
        return mine
    first = next(k for k in range(1, level + 1) if k == level or at(k).fields == mine.fields)
    if isinstance(mine, TaggedT):
        return TaggedT(mine.qname, mine.fields, first)
    return InnerRecordT(mine.qname, mine.fields, first)


def _holds_enum(t: T.Type, qname: str, skip_tag: bool = False) -> bool:
    """Whether a value of ``t`` contains one of enumeration ``qname`` (not counting the tag)."""
    if isinstance(t, T.EnumT):
        return t.qname == qname
    if isinstance(t, T.RecordT):
        return any(_holds_enum(ft, qname) for _, ft in (t.fields[1:] if skip_tag else t.fields))
    inner = getattr(t, "element", None)
    return inner is not None and _holds_enum(inner, qname)


SCALARS = (T.NAT, T.INT, T.REAL, T.BOOLEAN)


def is_scalar(t: T.Type) -> bool:
    return t in SCALARS or isinstance(t, T.EnumT)


def check_codegen_type(t: T.Type, span: Span | None, what: str) -> None:
    """Raise the not-supported error unless values of ``t`` (already normalised) have a
    representation in generated code: scalars, records of them, sized vectors and matrices."""
    if is_scalar(t) or t == T.STRING:  # a string: one of the model's string literals
        return
    if isinstance(t, TaggedT) and _holds_enum(t, t.qname, skip_tag=True):
        raise not_supported(f"{what}: enumeration {t.qname} whose literal's argument holds a {t.qname} "
                            "(a recursive enumeration)", span)
    if isinstance(t, T.RecordT):
        for n, ft in t.fields:
            check_codegen_type(ft, span, f"field '{n}' of {what}")
        return
    if isinstance(t, T.VectorT) and is_scalar(t.element):
        if t.size is None:
            raise not_supported(f"{what}: a vector whose size is not an integer literal", span)
        return
    if isinstance(t, T.MatrixT) and is_scalar(t.element):
        if t.rows is None or t.columns is None:
            raise not_supported(f"{what}: a matrix whose size is not given by integer literals", span)
        return
    if isinstance(t, T.FunctionT) and not t.relation:  # stored as the number of a function value
        check_codegen_type(t.domain, span, f"the domain of {what}")
        check_codegen_type(t.range, span, f"the range of {what}")
        return
    if isinstance(t, (T.SetT, T.SeqT)):
        if holds_function(t.element):
            raise not_supported(f"{what}: a {T.form(t)[2:]} of {t.element.show()} (two function values cannot be "
                                "compared, so a collection of them has no order or membership)", span)
        check_codegen_type(t.element, span, f"the elements of {what}")
        return
    raise not_supported(f"{what} of type {t.show()}", span)


def holds_function(t: T.Type) -> bool:
    """Whether a value of ``t`` contains a function value (which has no equality in C)."""
    if isinstance(t, T.FunctionT):
        return True
    if isinstance(t, T.RecordT):
        return any(holds_function(ft) for _, ft in t.fields)
    inner = getattr(t, "element", None)
    return inner is not None and holds_function(inner)


def holds_string(t: T.Type) -> bool:
    """Whether a value of ``t`` contains a string (ordered by its text, which C finds through the
    model's data)."""
    if t == T.STRING:
        return True
    if isinstance(t, T.RecordT):
        return any(holds_string(ft) for _, ft in t.fields)
    inner = getattr(t, "element", None)
    return inner is not None and holds_string(inner)


def convertible(source: T.Type, target: T.Type) -> bool:
    """Whether a value of ``source`` becomes one of ``target`` part by part: the same form, with
    numbers of other numeric types or collections of other capacities inside."""
    if source == target or (source in T.NUMERIC and target in T.NUMERIC):
        return True
    if is_collection(source) and is_collection(target):
        return isinstance(source, T.SetT) == isinstance(target, T.SetT) and \
            convertible(source.element, target.element)  # type: ignore[attr-defined]
    if isinstance(source, T.RecordT) and isinstance(target, T.RecordT):
        same = isinstance(source, TupleT) == isinstance(target, TupleT) and (isinstance(source, TupleT) or source.qname == target.qname)
        return same and [n for n, _ in source.fields] == [n for n, _ in target.fields] and \
            all(convertible(a, b) for (_, a), (_, b) in zip(source.fields, target.fields))
    if isinstance(source, T.VectorT) and isinstance(target, T.VectorT):
        return source.size == target.size and convertible(source.element, target.element)
    if isinstance(source, T.MatrixT) and isinstance(target, T.MatrixT):
        return (source.rows, source.columns) == (target.rows, target.columns) and convertible(source.element, target.element)
    return False


def fits(source: T.Type, target: T.Type, capacity_of) -> bool:
    """Whether every collection inside a value of ``source`` holds at most as many elements in
    ``target`` (``capacity_of``: the capacity of a collection type): converting it cannot
    overflow."""
    if is_collection(source) and is_collection(target):
        return capacity_of(source) <= capacity_of(target) and fits(source.element, target.element, capacity_of)  # type: ignore[attr-defined]
    if isinstance(source, T.RecordT) and isinstance(target, T.RecordT):
        return all(fits(a, b, capacity_of) for (_, a), (_, b) in zip(source.fields, target.fields))
    return True


def is_collection(t: T.Type) -> bool:
    return isinstance(t, (T.SetT, T.SeqT))


__all__ = ["not_supported", "normalise", "is_scalar", "is_collection", "check_codegen_type", "SCALARS", "TupleT",
           "tuple_type", "InnerSetT", "InnerSeqT", "InnerRecordT", "ArrayT", "capacity_at", "holds_function", "holds_string", "convertible", "fits"]
