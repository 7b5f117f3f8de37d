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


@dataclass(frozen=True, slots=True)
class FunMapT(T.RecordT):
    """A function value ``D -> R`` at run time (robogen.ir.functions): a record of ``pairs``, a
    set of (argument, result) pairs of at most one pair per argument (its finite part, in
    canonical order), and ``base``, the number of the function value (a lambda or named function,
    in the machine's table of function values of this type) that gives the result for every
    argument outside ``pairs``; 0 for none (the function is the finite map ``pairs``). Inside
    a collection, ``pairs`` has that nesting level's capacity (an :class:`InnerSetT`), as a
    relation's pairs there have."""

    def show(self) -> str:
        pair = self.pair
        return f"{_paren(pair.field('_1'))} -> {pair.field('_2').show()}"  # type: ignore[arg-type]

    @property
    def pair(self) -> TupleT:
        t = self.fields[0][1]
        assert isinstance(t, T.SetT) and isinstance(t.element, TupleT)
        return t.element

    @property
    def pairs(self) -> T.SetT:
        t = self.fields[0][1]
        assert isinstance(t, T.SetT)
        return t


def _paren(t: T.Type) -> str:
    return f"({t.show()})" if isinstance(t, (TupleT, FunMapT)) else t.show()


def fun_map_type(domain: T.Type, range_: T.Type, capacities: tuple[int, ...] = (), level: int = 0) -> FunMapT:
    """The run-time type of function values ``domain -> range_`` (both normalised, at nesting
    ``level + 1``) at nesting ``level``: its pairs are a set of that level's capacity."""
    pair = tuple_type((domain, range_))
    return FunMapT(f"fun({pair.qname})", (("pairs", _collection(T.SetT, pair, capacities, level)), ("base", T.INT)))


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


ENUM_DEPTH = 4  # the default depth bound of recursive enumerations (robogen compile --enum-depth)


@dataclass(frozen=True, slots=True)
class Unshaped(T.Type):
    """A type that holds itself with no enumeration literal between (a record on a cycle of
    records and collections): no finite shape. :func:`check_codegen_type` reports it."""

    qname: str

    def show(self) -> str:
        return self.qname


class Shapes:
    """What :func:`normalise` needs to give a type a finite shape: the enumerations and records
    the model declares, in full (inside a recursive one the checker refers to it by a stand-in
    without arguments or fields), the depth bound of recursive ones, and the capacity of each
    nesting level of collections.

    A type on a cycle of references (an enumeration whose literal's argument holds it, directly
    or through collections, products, records or other enumerations of the cycle) is unrolled to
    ``depth`` levels: at level k an enumeration literal's arguments hold the types of its cycle
    at level k - 1 (records pass their level on to their fields); at level 0 those arguments
    are absent, so a value that needs one is deeper than the bound (a run-time error where it
    is made: robogen.ir.expressions). Level ``depth`` keeps the type's own name, so a model's
    variables and ports are named as without recursion; level k < depth is ``<name>@k``.

    ``capacities``: the capacity of each nesting level of collections (outermost first, the
    last for every deeper one; empty or all equal: one capacity for all, ``--capacity 32,8,4``):
    a collection ``level`` collections deep whose capacity is not the outermost one's is an
    :class:`InnerSetT` or :class:`InnerSeqT`, and a record there whose fields hold such
    collections an :class:`InnerRecordT` (a tagged record its own ``level``)."""

    def __init__(self, declared: dict[str, T.Type] | None = None, depth: int = ENUM_DEPTH,
                 capacities: tuple[int, ...] = ()):
        self.declared = dict(declared or {})
        self.depth = depth
        self.capacities = capacities if len(set(capacities)) > 1 else ()
        self._reach: dict[str, frozenset[str]] = {}
        self._records: dict[tuple, T.RecordT] = {}  # a record's fields at a nesting level, computed once

    def full(self, t: T.EnumT | T.RecordT) -> T.Type:
        """The declaration of ``t`` (``t`` itself where the model declares none)."""
        return self.declared.get(t.qname, t)

    def reach(self, qname: str) -> frozenset[str]:
        """The enumerations and records a value of type ``qname`` may hold, at any depth."""
        if qname not in self._reach:
            seen: set[str] = set()
            todo = [qname]
            while todo:
                for n in _named_in(_parts_of(self.declared.get(todo.pop()))):
                    if n not in seen:
                        seen.add(n)
                        todo.append(n)
            self._reach[qname] = frozenset(seen)
        return self._reach[qname]

    def cycle(self, qname: str) -> frozenset[str]:
        """The types on a cycle of references with ``qname`` (empty: it is not recursive)."""
        r = self.reach(qname)
        return frozenset(n for n in r if qname in self.reach(n)) if qname in r else frozenset()

    def named(self, qname: str, level: int, cycle: frozenset[str]) -> str:
        return qname if not cycle or level == self.depth else f"{qname}@{level}"

    def remember(self, key: tuple, make):
        """``make()``, computed once per ``key`` where nesting levels differ in capacity (a
        record's fields at each level are compared with the outermost's: :func:`normalise`)."""
        if not self.capacities:
            return make()
        if key not in self._records:
            self._records[key] = make()
        return self._records[key]


_PLAIN = Shapes()


def base_name(qname: str) -> str:
    """The declared name of a type unrolled by :class:`Shapes` (``pkg::E@2`` -> ``pkg::E``)."""
    return qname.split("@", 1)[0]


def _parts_of(t: T.Type | None) -> list[T.Type]:
    """The types a declared enumeration's arguments or record's fields have."""
    if isinstance(t, T.EnumT):
        return [a for args in t.literal_args for a in args]
    if isinstance(t, T.RecordT):
        return [ft for _, ft in t.fields]
    return []


def _named_in(types) -> set[str]:
    """The enumerations and records named in ``types`` (through collections, products,
    functions, vectors; not into their own declarations)."""
    found: set[str] = set()
    todo = list(types)
    while todo:
        t = T.single(todo.pop())
        if isinstance(t, (T.EnumT, T.RecordT)) and not isinstance(t, TupleT):
            found.add(t.qname)
        elif isinstance(t, TupleT):
            todo += [ft for _, ft in t.fields]
        elif isinstance(t, T.ProductT):
            todo += list(t.items)
        elif isinstance(t, T.FunctionT):
            todo += [t.domain, t.range]
        elif isinstance(getattr(t, "element", None), T.Type):
            todo.append(t.element)  # type: ignore[attr-defined]
    return found


def tagged_type(t: T.EnumT, given: str, shapes: Shapes = _PLAIN, unroll: int | None = None,
                path: tuple = (), level: int = 0) -> TaggedT:
    """The code-generation type of enumeration ``t`` (declared in full), at level ``unroll`` of
    its cycle (None: the top, the depth bound; see :class:`Shapes`), at nesting ``level`` of
    collections (its arguments' collections have that level's capacities)."""
    cycle = shapes.cycle(t.qname)
    unroll = shapes.depth if unroll is None else unroll
    tag = T.EnumT(t.qname, t.literals)
    fields = []
    for lit, args in zip(t.literals, t.literal_args):
        if unroll == 0 and cycle & _named_in(args):
            continue  # no room for another level: a value of this literal is deeper than the bound
        for k, at in enumerate(args):
            inner = (cycle, unroll - 1) if cycle & _named_in([at]) else None
            fields.append((f"{lit}_{k + 1}", normalise(at, given, shapes, inner, path, level)))
    return TaggedT(shapes.named(t.qname, unroll, cycle), (("tag", tag),) + tuple(fields))


def normalise(t: T.Type, given: str = "int", shapes: Shapes = _PLAIN, within: tuple | None = None,
              path: tuple = (), level: int = 0) -> T.Type:
    """Replace given types by their concrete scalar type, products by :class:`TupleT`, function
    types by :class:`FunMapT`, enumerations with arguments by :class:`TaggedT`, recursively;
    recursive types unrolled by ``shapes`` (``within``: the cycle and level of the recursive
    type whose parts these are; ``path``: the named types being normalised, outermost first);
    ``level``: how many collections hold the value (their capacities: see :class:`Shapes`)."""
    t = T.single(t)
    if isinstance(t, (TaggedT, InnerRecordT, InnerSetT, InnerSeqT, ArrayT, Unshaped)):
        return t  # already concrete
    if isinstance(t, T.Given):
        return T.PRIMITIVES[given]
    if isinstance(t, (T.UnknownT, T.TypeVarT)):  # the elements of a set or sequence nothing gives a type (a
        return T.INT  # toolkit result's ?Y that an empty argument leaves open): it is empty

    def norm(x: T.Type, inner: int = 0) -> T.Type:  # a part, ``inner`` collections further in
        return normalise(x, given, shapes, within, path, level + inner)

    caps = shapes.capacities
    if isinstance(t, TupleT):  # concrete, perhaps at another nesting level (a generic function's ?X): its parts at this one
        return tuple_type(tuple(norm(ft) for _, ft in t.fields))
    if isinstance(t, FunMapT):
        return fun_map_type(norm(t.pair.fields[0][1], 1), norm(t.pair.fields[1][1], 1), caps, level)
    if isinstance(t, (T.EnumT, T.RecordT)):
        return _named_type(t, given, shapes, within, path, level)
    if isinstance(t, T.ProductT):
        return tuple_type(tuple(norm(x) for x in t.items))
    if isinstance(t, (T.SetT, T.SeqT)):
        return _collection(T.SetT if isinstance(t, T.SetT) else T.SeqT, norm(t.element, 1), caps, level)
    if isinstance(t, T.FunctionT) and t.relation:  # a relation is the set of its pairs
        return _collection(T.SetT, tuple_type((norm(t.domain, 1), norm(t.range, 1))), caps, level)
    if isinstance(t, T.FunctionT):  # a function value: its finite part (pairs, as a relation's) and its default
        return fun_map_type(norm(t.domain, 1), norm(t.range, 1), caps, level)
    if isinstance(t, T.VectorT):
        return T.VectorT(norm(t.element), t.size)
    if isinstance(t, T.MatrixT):
        return T.MatrixT(norm(t.element), t.rows, t.columns)
    return t


def _named_type(t: T.EnumT | T.RecordT, given: str, shapes: Shapes, within: tuple | None, path: tuple,
                level: int) -> T.Type:
    """An enumeration or record (see :func:`normalise`)."""
    full = shapes.full(t)
    assert isinstance(full, (T.EnumT, T.RecordT))
    unroll = within[1] if within is not None and full.qname in within[0] else shapes.depth
    if (full.qname, unroll) in path:  # back to itself with no enumeration literal between
        return Unshaped(full.qname)
    path = path + ((full.qname, unroll),)
    if isinstance(full, T.EnumT) and not any(full.literal_args):
        return T.EnumT(full.qname, full.literals)
    return _record(full, given, shapes, unroll, path, level)


def _record(full: T.RecordT | T.EnumT, given: str, shapes: Shapes, unroll: int, path: tuple, level: int) -> T.RecordT:
    """A record (or tagged enumeration) at level ``unroll`` of its cycle and nesting ``level``:
    its fields' collections have that nesting level's capacities. Where they differ from the
    outermost level's, the type is the record of the first level that gives these fields (see
    :class:`InnerRecordT`)."""
    def make(k: int) -> T.RecordT:
        if isinstance(full, T.EnumT):
            return tagged_type(full, given, shapes, unroll, path, k)
        cycle = shapes.cycle(full.qname)
        return T.RecordT(shapes.named(full.qname, unroll, cycle), tuple(
            (n, normalise(ft, given, shapes, (cycle, unroll) if cycle & _named_in([ft]) else None, path, k))
            for n, ft in full.fields))

    def at(k: int) -> T.RecordT:
        return shapes.remember((full, given, unroll, path, k), lambda: make(k))

    mine = at(level)
    if level == 0 or not shapes.capacities or mine.fields == at(0).fields:
        return mine
    first = next(k for k in range(1, level + 1) if k == level or at(k).fields == mine.fields)
    if isinstance(mine, TaggedT):
        return TaggedT(mine.qname, mine.fields, first)
    return InnerRecordT(mine.qname, mine.fields, first)


SCALARS = (T.NAT, T.INT, T.REAL, T.BOOLEAN)


def is_scalar(t: T.Type) -> bool:
    return t in SCALARS or isinstance(t, T.EnumT)


def check_codegen_type(t: T.Type, span: Span | None, what: str) -> None:
    """Raise the not-supported error unless values of ``t`` (already normalised) have a
    representation in generated code: scalars, strings, records and collections of them, sized
    vectors and matrices."""
    if is_scalar(t) or t == T.STRING:  # a string: one of the model's string literals
        return
    if isinstance(t, Unshaped):
        raise not_supported(f"{what}: {t.qname} holds itself with no enumeration literal between (a value of it "
                            "would be infinite, or a tree of collections: give the recursion an enumeration literal "
                            "to end it)", span)
    if isinstance(t, FunMapT):
        check_codegen_type(t.pairs, span, f"the pairs of {what}")
        return
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
    if isinstance(t, (T.SetT, T.SeqT)):
        check_codegen_type(t.element, span, f"the elements of {what}")
        return
    raise not_supported(f"{what} of type {t.show()}", span)


def holds_function(t: T.Type) -> bool:
    """Whether a value of ``t`` contains a function value (:class:`FunMapT`)."""
    if isinstance(t, FunMapT):
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


__all__ = ["ENUM_DEPTH", "Shapes", "base_name", "FunMapT", "fun_map_type", "not_supported", "normalise", "is_scalar",
           "is_collection", "check_codegen_type", "SCALARS", "TupleT", "tuple_type", "InnerSetT", "InnerSeqT", "InnerRecordT",
           "ArrayT", "capacity_at", "holds_function", "holds_string", "convertible", "fits"]
