"""What the operations on sets and sequences (:class:`robogen.ir.model.Coll`) compute: the
reference semantics, which the reference interpreter runs and the generated C
(``robogen_collections.h`` and the per-type functions of :mod:`robogen.codegen.collections`)
follows step for step.

A set is a list of distinct elements in ascending order (its canonical form, so that equality,
printing and the FMI array of a set never depend on how it was built); a sequence is a list.
Elements are ordered by :func:`compare`: numbers and enumeration literals by value (``false``
before ``true``), records and tuples field by field. Membership and insertion use the same
comparison. Every operation builds its result in order, element by element: a result with more
than ``capacity`` elements is a run-time error (:class:`CollectionFault`) naming the expression,
as is ``head``, ``last``, ``tail``, ``front``, ``min`` or ``max`` of an empty collection.

The operations, by the name lowering gives them (``s``, ``t`` sets, ``q``, ``r`` sequences):

- ``set(x...)``, ``seq(x...)``: enumerations ``{x, ...}`` and ``<x, ...>``;
- ``in(x, s)``, ``notin(x, s)`` (also of a sequence's elements), ``size(s)`` (also of a sequence);
- ``union``, ``inter``, ``diff``, ``symdiff`` of two sets; ``subseteq``, ``subset`` (tests);
- ``cat(q, r)`` (``^``, ``concat``), ``head``, ``last``, ``tail``, ``front``, ``reverse``;
- ``elems(q)`` (``ran`` of a sequence: the set of its elements), ``indices(q)`` (its ``dom``);
- ``filter(q, s)``: the elements of q in s, in order; ``extract(q, a)``: the elements of q at
  the positions (from 1) in the set of integers a, in order (the toolkit's ``extract(a, q)``);
  ``range(x, y)``: the integers x..y;
- ``min(s)``, ``max(s)`` of a set of integers; ``nonempty(s)`` (``isNonEmpty``, ``hasMin``,
  ``hasMax``); ``prefix(q, r)``, ``suffix(q, r)``, ``infix(q, r)``.
"""

from __future__ import annotations

from robogen.semantics import types as T

# the operations whose result is a set / a sequence / something else (and which element type
# their result has is the code generator's business)
SET_RESULTS = ("set", "union", "inter", "diff", "symdiff", "elems", "indices")
SEQ_RESULTS = ("seq", "cat", "tail", "front", "reverse", "filter", "extract", "range")
EMPTY_FAULTS = ("head", "last", "tail", "front", "min", "max")
CAN_OVERFLOW = ("set", "seq", "union", "symdiff", "cat", "elems", "range", "dom", "ran", "rinv", "rimage", "roverride",
                "relcomp")


class CollectionFault(Exception):
    """A collection operation cannot give its result: the message says why."""


def compare(a, b, t: T.Type) -> int:
    """-1, 0 or 1: the order of elements of type ``t``."""
    if isinstance(t, T.RecordT):
        for n, ft in t.fields:
            c = compare(a[n], b[n], ft)
            if c:
                return c
        return 0
    return (a > b) - (a < b)


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
        self.empty = empty  # the message of finding no element to give

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
    if op in ("union", "symdiff"):
        t = args[1]
        for x in s:
            if op == "union" or not member(x, t, elem):
                out.insert(x, elem)
        for x in t:
            if op == "union" or not member(x, s, elem):
                out.insert(x, elem)
        return out.items
    if op in ("inter", "diff"):
        for x in s:
            if member(x, args[1], elem) == (op == "inter"):
                out.append(x)
        return out.items
    if op in ("subseteq", "subset"):
        inside = all(member(x, args[1], elem) for x in s)
        return inside and (op == "subseteq" or len(s) < len(args[1]))
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
    if op in ("prefix", "suffix", "infix"):
        q, r = s, args[1]
        n = len(q)
        starts = [0] if op == "prefix" else [len(r) - n] if op == "suffix" else range(len(r) - n + 1)
        return n <= len(r) and any(all(compare(q[k], r[i + k], elem) == 0 for k in range(n)) for i in starts)
    raise CollectionFault(f"unknown collection operation {op}")  # pragma: no cover


# relations are sets of pairs (tuples with fields _1, _2): their operations, by name
RELATION_OPS = ("dom", "ran", "rinv", "dres", "dsub", "rres", "rsub", "rimage", "roverride", "relcomp", "squash",
                "haskey", "at")
# the operations that may find no element to give: a message of the same site (robogen.codegen)
NO_ELEMENT = EMPTY_FAULTS + ("at",)


def _relation(op: str, args: list, arg_types: list[T.Type], result: T.Type, out: Builder):
    """``dom``, ``ran``, ``rinv``, ``dres(a, r)``, ``dsub(a, r)``, ``rres(r, b)``, ``rsub(r, b)``,
    ``rimage(r, a)``, ``override(r, s)`` (``roverride``), ``relcomp(r, s)``, ``squash(f)``
    (the second components in the order of the first: a set of pairs is ordered by them), and
    for function values (robogen.ir.functions) ``haskey(r, x)``, whether a pair has first
    component x, and ``at(r, x)``, the second component of the first such pair (a fault if none)."""
    relation = 1 if op in ("dres", "dsub") else 0
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
        for p in r:
            for q in args[1]:
                if compare(p["_2"], q["_1"], y) == 0:
                    out.insert({"_1": p["_1"], "_2": q["_2"]}, res_elem)
        return out.items
    for p in r:  # squash
        out.append(p["_2"])
    return out.items


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


def overflow_message(text: str, where: str, capacity: int) -> str:
    return f"more than {capacity} elements (the capacity) in {text} at {where}"


def empty_message(op: str, text: str, where: str) -> str:
    if op == "at":
        return f"{text} outside the function's domain at {where}"
    return f"'{op}' of an empty collection in {text} at {where}"


def index(q: list, i: int, what: str) -> int:
    """The 0-based position of the 1-based index ``i`` of a sequence (an error out of range)."""
    if not 1 <= i <= len(q):
        raise CollectionFault(f"index {i} out of range 1..{len(q)} of {what}")
    return i - 1


__all__ = ["CollectionFault", "apply", "compare", "member", "index", "received", "overflow_message", "empty_message", "SET_RESULTS", "SEQ_RESULTS", "EMPTY_FAULTS", "CAN_OVERFLOW",
           "NO_ELEMENT"]
