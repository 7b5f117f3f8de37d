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
- ``filter(q, s)``: the elements of q in s, in order; ``range(x, y)``: the integers x..y;
- ``min(s)``, ``max(s)`` of a set of integers; ``nonempty(s)`` (``isNonEmpty``, ``hasMin``,
  ``hasMax``); ``prefix(q, r)``, ``suffix(q, r)``, ``infix(q, r)``.
"""

from __future__ import annotations

from robogen.semantics import types as T

# the operations whose result is a set / a sequence / something else (and which element type
# their result has is the code generator's business)
SET_RESULTS = ("set", "union", "inter", "diff", "symdiff", "elems", "indices")
SEQ_RESULTS = ("seq", "cat", "tail", "front", "reverse", "filter", "range")
EMPTY_FAULTS = ("head", "last", "tail", "front", "min", "max")
CAN_OVERFLOW = ("set", "seq", "union", "symdiff", "cat", "elems", "range")


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

    def __init__(self, capacity: int, overflow: str):
        self.items: list = []
        self.capacity = capacity
        self.overflow = overflow

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


def apply(op: str, args: list, arg_types: list[T.Type], capacity: int, overflow: str, empty: str):
    """The value of operation ``op`` of :class:`~robogen.ir.model.Coll` on ``args`` (Python
    values of the types ``arg_types``). ``overflow``/``empty``: the messages of its faults."""
    first = arg_types[0] if arg_types else T.INT
    elem = first.element if isinstance(first, (T.SetT, T.SeqT)) else first  # type: ignore[union-attr]
    out = Builder(capacity, overflow)
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
    if op == "filter":
        for x in s:
            if member(x, args[1], elem):
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


def overflow_message(text: str, where: str, capacity: int) -> str:
    return f"more than {capacity} elements (the capacity) in {text} at {where}"


def empty_message(op: str, text: str, where: str) -> str:
    return f"'{op}' of an empty collection in {text} at {where}"


def index(q: list, i: int, what: str) -> int:
    """The 0-based position of the 1-based index ``i`` of a sequence (an error out of range)."""
    if not 1 <= i <= len(q):
        raise CollectionFault(f"index {i} out of range 1..{len(q)} of {what}")
    return i - 1


__all__ = ["CollectionFault", "apply", "compare", "member", "index", "overflow_message", "empty_message", "SET_RESULTS", "SEQ_RESULTS", "EMPTY_FAULTS", "CAN_OVERFLOW"]
