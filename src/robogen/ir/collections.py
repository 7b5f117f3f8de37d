"""What the operations on sets and sequences (:class:`robogen.ir.model.Coll`) compute: the
reference semantics, which the reference interpreter runs and the generated C
(``robogen_collections.h`` and the per-type functions of :mod:`robogen.codegen.collections`)
follows step for step.

A set is a list of distinct elements in ascending order (its canonical form, so that equality,
printing and the FMI array of a set never depend on how it was built); a sequence is a list.
Elements are ordered by :func:`compare`: numbers and enumeration literals by value (``false``
before ``true``), strings by their text (byte by byte in UTF-8, as C's ``strcmp``), records and
tuples field by field, vectors and matrices element by element, and sets and sequences
lexicographically: element by element, the first difference decides, and a collection that is
the beginning of another comes before it (``<1> < <1, 2> < <2>``; a set compares as the
ascending sequence of its elements, so ``{} < {1} < {1, 2} < {2}``). Membership and insertion
use the same comparison. Every operation builds its result in order, element by element: a result with more
than ``capacity`` elements is a run-time error (:class:`CollectionFault`) naming the expression,
as is ``head``, ``last``, ``tail``, ``front``, ``min`` or ``max`` of an empty collection.

The operations, by the name lowering gives them (``s``, ``t`` sets, ``q``, ``r`` sequences):

- ``set(x...)``, ``seq(x...)``: enumerations ``{x, ...}`` and ``<x, ...>``;
- ``in(x, s)``, ``notin(x, s)`` (also of a sequence's elements), ``size(s)`` (also of a sequence);
- ``union``, ``inter``, ``diff``, ``symdiff`` of two sets; ``subseteq``, ``subset`` (tests);
- ``cat(q, r)`` (``^``, ``concat``), ``head``, ``last``, ``tail``, ``front``, ``reverse``;
- ``elems(q)`` (``ran`` of a sequence: the set of its elements), ``indices(q)`` (its ``dom``),
  ``pairs(q)`` (the sequence as a set of (index, element) pairs, as RoboChart takes it where a set
  is expected: ``Union`` of a set of sequences);
- ``filter(q, s)``: the elements of q in s, in order; ``extract(q, a)``: the elements of q at
  the positions (from 1) in the set of integers a, in order (the toolkit's ``extract(a, q)``);
  ``range(x, y)``: the integers x..y;
- ``min(s)``, ``max(s)`` of a set of integers; ``nonempty(s)`` (``isNonEmpty``, ``hasMin``,
  ``hasMax``); ``prefix(q, r)``, ``suffix(q, r)``, ``infix(q, r)``; ``injective(q)``
  (``isInjectiveSequence``: no element twice);
- ``Union(a)``, ``Inter(a)`` of a set of sets (``Inter`` of the empty set is every value of the
  element type: all the literals of an enumeration, ``{false, true}``, and a run-time error for
  an infinite type); ``dconcat(q)`` of a sequence of sequences (their concatenation);
- relations (:data:`RELATION_OPS`), among them ``closure(r)`` (``tr_closure``: r with r;r,
  r;r;r... until nothing is added) and ``iter(n, r)``: ``r`` composed with itself n
  times (``relcomp``), of ``rinv(r)`` for a negative n, the identity relation for 0 (as
  ``Inter({})``, only of an enumeration or boolean); the powers stop early when one repeats the
  one before, and more than :data:`LOOP_LIMIT` of them is a run-time error.
"""

from __future__ import annotations

from robogen.semantics import types as T

# the operations whose result is a set / a sequence / something else (and which element type
# their result has is the code generator's business)
SET_RESULTS = ("set", "union", "inter", "diff", "symdiff", "elems", "indices", "Union", "Inter", "pairs")
SEQ_RESULTS = ("seq", "cat", "tail", "front", "reverse", "filter", "extract", "range", "dconcat")
EMPTY_FAULTS = ("head", "last", "tail", "front", "min", "max")
CAN_OVERFLOW = ("set", "seq", "union", "symdiff", "cat", "elems", "range", "dom", "ran", "rinv", "rimage", "roverride",
                "relcomp", "Union", "dconcat", "iter", "conv", "closure")
# operations whose second fault is not that of an empty collection: the message of each
OTHER_FAULTS = {"Inter": "'Inter' of an empty set of sets: every value of an infinite type",
                "iter": f"'iter' of 0 on an infinite type (the identity relation), or of more than {1 << 16} powers that "
                        "never repeat"}
# the operations that may fail other than by overflowing: their message is the site's second
# (robogen.codegen gives each fallible operation two sites: overflow, then this)
SECOND_FAULTS = EMPTY_FAULTS + ("at",) + tuple(OTHER_FAULTS)
# the most values one expression loops over: the integers of a quantifier's range, iter's powers
# (every cycle of an FMU ends: a loop of an expression is bounded too)
LOOP_LIMIT = 1 << 16


class CollectionFault(Exception):
    """A collection operation cannot give its result: the message says why."""


def compare(a, b, t: T.Type) -> int:
    """-1, 0 or 1: the order of elements of type ``t`` (see the module documentation)."""
    if isinstance(t, T.RecordT):
        for n, ft in t.fields:
            c = compare(a[n], b[n], ft)
            if c:
                return c
        return 0
    if isinstance(t, (T.SetT, T.SeqT, T.VectorT, T.MatrixT)):
        for x, y in zip(a, b):
            c = compare(x, y, t.element)
            if c:
                return c
        return (len(a) > len(b)) - (len(a) < len(b))
    return (a > b) - (a < b)  # a string: by code point, which is UTF-8's byte order


def all_values(t: T.Type) -> list | None:
    """Every value of a finite type, in order: the literals of an enumeration, false and true
    (None for another type)."""
    if t == T.BOOLEAN:
        return [False, True]
    if isinstance(t, T.EnumT):
        return list(range(len(t.literals)))
    return None


def _find(s: list, x, t: T.Type) -> tuple[int, bool]:
    """Where ``x`` is, or would go, in the set ``s``: (index, present)."""
    for i, y in enumerate(s):
        c = compare(y, x, t)
        if c >= 0:
            return i, c == 0
    return len(s), False


def member(x, s: list, t: T.Type, ordered: bool = True) -> bool:
    if not ordered:
        return any(compare(y, x, t) == 0 for y in s)
    return _find(s, x, t)[1]


class Builder:
    """A result under construction, that may not hold more than ``capacity`` elements."""

    def __init__(self, capacity: int, overflow: str, empty: str = ""):
        self.items: list = []
        self.capacity = capacity
        self.overflow = overflow
        self.empty = empty  # the message of the operation's other fault (robogen.ir.collections.SECOND_FAULTS)

    def append(self, x) -> None:
        if len(self.items) >= self.capacity:
            raise CollectionFault(self.overflow)
        self.items.append(x)

    def insert(self, x, t: T.Type) -> None:
        i, present = _find(self.items, x, t)
        if present:
            return
        if len(self.items) >= self.capacity:
            raise CollectionFault(self.overflow)
        self.items.insert(i, x)


def apply(op: str, args: list, arg_types: list[T.Type], capacity: int, overflow: str, empty: str,
          result: T.Type = T.BOOLEAN):
    """The value of operation ``op`` of :class:`~robogen.ir.model.Coll` on ``args`` (Python
    values of the types ``arg_types``; the result of type ``result``). ``overflow``/``empty``:
    the messages of its faults."""
    first = arg_types[0] if arg_types else T.INT
    elem = first.element if isinstance(first, (T.SetT, T.SeqT)) else first  # type: ignore[union-attr]
    out = Builder(capacity, overflow, empty)
    if op in RELATION_OPS:
        return _relation(op, args, arg_types, result, out)
    if op in ("set", "seq"):
        for x, xt in zip(args, arg_types):
            out.insert(x, xt) if op == "set" else out.append(x)
        return out.items
    if op in ("in", "notin"):
        s_t = arg_types[1]
        found = member(args[0], args[1], first, ordered=isinstance(s_t, T.SetT))
        return found if op == "in" else not found
    s = args[0]
    if op == "size":
        return len(s)
    if op == "nonempty":
        return bool(s)
    if op in EMPTY_FAULTS and not s:
        raise CollectionFault(empty)
    if op in ("union", "symdiff", "inter", "diff", "subseteq", "subset"):
        return _sets(op, s, args[1], elem, out)
    if op == "cat":
        for x in s + args[1]:
            out.append(x)
        return out.items
    if op == "head":
        return s[0]
    if op == "last":
        return s[-1]
    if op in ("tail", "front", "reverse"):
        return s[1:] if op == "tail" else s[:-1] if op == "front" else s[::-1]
    if op == "elems":
        for x in s:
            out.insert(x, elem)
        return out.items
    if op == "indices":
        return list(range(1, len(s) + 1))  # never longer than s
    if op == "pairs":  # a sequence as the set of its (index, element) pairs, in the order of the indices
        return [{"_1": i, "_2": x} for i, x in enumerate(s, 1)]
    if op in ("filter", "extract"):  # the elements of s in the set (filter), or at the positions in it
        for i, x in enumerate(s, 1):
            if member(x, args[1], elem) if op == "filter" else member(i, args[1], T.INT):
                out.append(x)
        return out.items
    if op == "range":
        low, high = args
        for x in range(low, high + 1) if high - low < capacity else range(low, low + capacity + 1):
            out.append(x)
        return out.items
    if op in ("min", "max"):
        return s[0] if op == "min" else s[-1]
    if op in ("Union", "Inter", "dconcat"):
        return _nested(op, s, elem, result, out)
    if op == "injective":
        return all(compare(x, y, elem) != 0 for i, x in enumerate(s) for y in s[i + 1:])
    if op in ("prefix", "suffix", "infix"):
        q, r = s, args[1]
        n = len(q)
        starts = [0] if op == "prefix" else [len(r) - n] if op == "suffix" else range(len(r) - n + 1)
        return n <= len(r) and any(all(compare(q[k], r[i + k], elem) == 0 for k in range(n)) for i in starts)
    raise CollectionFault(f"unknown collection operation {op}")  # pragma: no cover


def _sets(op: str, s: list, t: list, elem: T.Type, out: Builder):
    """The operations of two sets (union, symdiff, inter, diff; the tests subseteq, subset)."""
    if op in ("union", "symdiff"):
        for x in s:
            if op == "union" or not member(x, t, elem):
                out.insert(x, elem)
        for x in t:
            if op == "union" or not member(x, s, elem):
                out.insert(x, elem)
        return out.items
    if op in ("inter", "diff"):
        for x in s:
            if member(x, t, elem) == (op == "inter"):
                out.append(x)
        return out.items
    inside = all(member(x, t, elem) for x in s)
    return inside and (op == "subseteq" or len(s) < len(t))


def _nested(op: str, s: list, inner: T.Type, result: T.Type, out: Builder) -> list:
    """``Union``, ``Inter`` of the set of sets ``s``, ``dconcat`` of the sequence of sequences."""
    elem = inner.element  # type: ignore[attr-defined]
    if op == "Inter":
        if not s:
            every = all_values(elem)
            if every is None:
                raise CollectionFault(out.empty)
            for x in every:
                out.append(x)
            return out.items
        return [x for x in s[0] if all(member(x, t, elem) for t in s[1:])]  # never longer than s[0]
    for t in s:
        for x in t:
            out.insert(x, elem) if op == "Union" else out.append(x)
    return out.items


# relations are sets of pairs (tuples with fields _1, _2): their operations, by name
RELATION_OPS = ("dom", "ran", "rinv", "dres", "dsub", "rres", "rsub", "rimage", "roverride", "relcomp", "squash", "iter",
                "closure", "haskey", "at")


def _relation(op: str, args: list, arg_types: list[T.Type], result: T.Type, out: Builder):
    """``dom``, ``ran``, ``rinv``, ``dres(a, r)``, ``dsub(a, r)``, ``rres(r, b)``, ``rsub(r, b)``,
    ``rimage(r, a)``, ``override(r, s)`` (``roverride``), ``relcomp(r, s)``, ``squash(f)``
    (the second components in the order of the first: a set of pairs is ordered by them),
    ``iter(n, r)`` and ``closure(r)``, and for function values (robogen.ir.functions)
    ``haskey(r, x)``, whether a pair has first component x, and ``at(r, x)``, the second
    component of the first such pair (a fault if none)."""
    relation = 1 if op in ("dres", "dsub", "iter") else 0
    r, pair = args[relation], arg_types[relation].element  # type: ignore[attr-defined]
    x, y = pair.field("_1"), pair.field("_2")
    res_elem = result.element if isinstance(result, (T.SetT, T.SeqT)) else result  # type: ignore[union-attr]
    if op in ("dom", "ran", "rinv"):
        for p in r:
            out.insert(p["_1"] if op == "dom" else p["_2"] if op == "ran" else {"_1": p["_2"], "_2": p["_1"]}, res_elem)
        return out.items
    if op in ("dres", "dsub", "rres", "rsub"):
        other = args[1 - relation]
        key, kt = ("_1", x) if op in ("dres", "dsub") else ("_2", y)
        return [p for p in r if member(p[key], other, kt) == (op in ("dres", "rres"))]
    if op in ("haskey", "at"):
        for p in r:
            if compare(p["_1"], args[1], x) == 0:
                return True if op == "haskey" else p["_2"]
        if op == "at":
            raise CollectionFault(out.empty)
        return False
    if op == "rimage":
        for p in r:
            if member(p["_1"], args[1], x):
                out.insert(p["_2"], y)
        return out.items
    if op == "roverride":
        s = args[1]
        for p in s:
            out.insert(p, pair)
        for p in r:
            if not any(compare(q["_1"], p["_1"], x) == 0 for q in s):
                out.insert(p, pair)
        return out.items
    if op == "relcomp":
        return _relcomp(r, args[1], y, res_elem, out)
    if op == "iter":
        return _iter(args[0], r, pair, out)
    if op == "closure":  # tr_closure: t := t with t;r until it grows no more (it only grows: a capacity bounds it)
        closure = list(r)
        while True:
            step = _relcomp(closure, r, y, pair, Builder(out.capacity, out.overflow))
            grown = Builder(out.capacity, out.overflow)
            for q in closure + step:
                grown.insert(q, pair)
            if len(grown.items) == len(closure):
                return grown.items
            closure = grown.items
    for p in r:  # squash
        out.append(p["_2"])
    return out.items


def _relcomp(r: list, s: list, middle: T.Type, pair: T.Type, out: Builder) -> list:
    for p in r:
        for q in s:
            if compare(p["_2"], q["_1"], middle) == 0:
                out.insert({"_1": p["_1"], "_2": q["_2"]}, pair)
    return out.items


def _iter(n: int, r: list, pair: T.Type, out: Builder) -> list:
    """``iter(n, r)`` (see the module documentation)."""
    x = pair.field("_1")  # type: ignore[attr-defined]
    if n == 0:
        every = all_values(x)  # type: ignore[arg-type]
        if every is None:
            raise CollectionFault(out.empty)
        for v in every:
            out.append({"_1": v, "_2": v})
        return out.items
    if n < 0:
        for p in r:
            out.insert({"_1": p["_2"], "_2": p["_1"]}, pair)
        r, n = out.items, -n
    power = list(r)
    for k in range(1, n):
        if k >= LOOP_LIMIT:
            raise CollectionFault(out.empty)
        step = _relcomp(r, power, x, pair, Builder(out.capacity, out.overflow))  # type: ignore[arg-type]
        if len(step) == len(power) and all(compare(a, b, pair) == 0 for a, b in zip(step, power)):
            break
        power = step
    return power


def received(elements: list, size: int, t: T.Type, capacity: int) -> list:
    """A set or sequence as an FMU input gives it: ``size`` (at most the capacity: only so many
    elements exist) elements of the array, a set then put in canonical order without duplicates."""
    items = elements[:max(0, min(size, capacity))]
    if isinstance(t, T.SeqT):
        return items
    out = Builder(capacity, "")
    for x in items:
        out.insert(x, t.element)  # type: ignore[attr-defined]
    return out.items


def convert(v, source: T.Type, target: T.Type, number, capacity_of, overflow: str):
    """A value of type ``source`` as a value of ``target``, a type of the same form whose numbers
    or capacities differ: ``number(x, s, t)`` converts a number; a set or sequence is rebuilt
    element by element, each converted first, then appended (inserted into a set, in canonical
    order), and more elements than ``capacity_of(target)`` is a fault (message ``overflow``)."""
    if isinstance(target, (T.SetT, T.SeqT)):
        out = Builder(capacity_of(target), overflow)
        for x in v:
            y = convert(x, source.element, target.element, number, capacity_of, overflow)  # type: ignore[attr-defined]
            out.insert(y, target.element) if isinstance(target, T.SetT) else out.append(y)
        return out.items
    if isinstance(target, T.RecordT):
        return {n: convert(v[n], source.field(n), ft, number, capacity_of, overflow)  # type: ignore[attr-defined]
                for n, ft in target.fields}
    if isinstance(target, (T.VectorT, T.MatrixT)):
        return [convert(x, source.element, target.element, number, capacity_of, overflow) for x in v]  # type: ignore[attr-defined]
    return v if source == target else number(v, source, target)


def site_capacity(op: str, arg_types: list[T.Type], result: T.Type, capacity_of) -> str:
    """The capacity an operation's overflow message names: its result's; for a conversion, that
    of the nesting levels where the target holds fewer elements than the source (the only ones
    that can overflow; ``32/8`` when they differ)."""
    if op != "conv":
        return str(capacity_of(result))
    found: list[int] = []

    def walk(source: T.Type, target: T.Type) -> None:
        if isinstance(target, (T.SetT, T.SeqT)):
            if capacity_of(target) < capacity_of(source) and capacity_of(target) not in found:
                found.append(capacity_of(target))
            walk(source.element, target.element)  # type: ignore[attr-defined]
        elif isinstance(target, T.RecordT):
            for n, ft in target.fields:
                walk(source.field(n), ft)  # type: ignore[attr-defined, arg-type]

    walk(arg_types[0], result)
    return "/".join(map(str, found)) or str(capacity_of(result))


def overflow_message(text: str, where: str, capacity: int | str) -> str:
    return f"more than {capacity} elements (the capacity) in {text} at {where}"


def empty_message(op: str, text: str, where: str) -> str:
    """The message of an operation's second fault (:data:`SECOND_FAULTS`): an empty collection,
    an argument outside a function value's domain, or :data:`OTHER_FAULTS`."""
    if op in OTHER_FAULTS:
        return f"{OTHER_FAULTS[op]} in {text} at {where}"
    if op == "at":
        return f"{text} outside the function's domain at {where}"
    return f"'{op}' of an empty collection in {text} at {where}"


def index(q: list, i: int, what: str) -> int:
    """The 0-based position of the 1-based index ``i`` of a sequence (an error out of range)."""
    if not 1 <= i <= len(q):
        raise CollectionFault(f"index {i} out of range 1..{len(q)} of {what}")
    return i - 1


__all__ = ["CollectionFault", "apply", "compare", "member", "index", "received", "convert", "all_values", "overflow_message", "site_capacity",
           "empty_message", "SET_RESULTS", "SEQ_RESULTS", "EMPTY_FAULTS", "CAN_OVERFLOW", "OTHER_FAULTS", "SECOND_FAULTS",
           "LOOP_LIMIT"]
