"""Quantifiers and set comprehensions over finite domains (:class:`robogen.ir.model.Quant`): what
they compute, step for step. The reference interpreter runs :func:`evaluate`; the generated C
(robogen.codegen.quantifiers) makes the same loops.

The bound variables take the values of their domains (:class:`robogen.ir.model.Domain`) in
nested loops, the first variable outermost; a domain after the first is computed anew for each
value of the variables before it. For each combination the predicate is evaluated, and where it
holds:

- ``forall``: the body; the first false one ends the loops (false);
- ``exists``: the body; the first true one ends the loops (true);
- ``exists1``: the body; a second true one ends the loops (false); true if exactly one;
- ``the``: the combination is kept; a second one is a run-time error; after the loops, none is
  one too, else the variables take the kept values and the body is the value;
- ``set`` (``{x: T | p @ e}``): the body is inserted into the result (a set in canonical order;
  more elements than the capacity is a run-time error).

A domain of integers (a range) of more than :data:`robogen.ir.collections.LOOP_LIMIT` values is
a run-time error before its first value: every cycle of an FMU ends.
"""

from __future__ import annotations

import copy

from robogen.ir import model as ir
from robogen.ir.collections import LOOP_LIMIT, Builder, CollectionFault, all_values, overflow_message
from robogen.semantics import types as T


def messages(e: ir.Quant, where: str, capacity: int) -> tuple[str, str, str]:
    """The run-time errors of ``e``: its result overflows, a range is too long, ``the`` has not
    exactly one value."""
    return (overflow_message(e.text, where, capacity),
            f"a range of more than {LOOP_LIMIT} integers in {e.text} at {where}",
            f"'the' without exactly one value in {e.text} at {where}")


class _Stop(Exception):
    """The loops end early (forall, exists and exists1 know their result)."""


def evaluate(e: ir.Quant, ev, store, convert, capacity: int, where: str):
    """The value of ``e``: ``ev(expr)`` evaluates an expression, ``store(var, value)`` sets a
    bound variable, ``convert(value, source, target)`` converts a number; a run-time error is a
    :class:`CollectionFault`."""
    overflow, too_long, not_one = messages(e, where, capacity)
    out = Builder(capacity, overflow)
    found: list = []  # exists1: the true bodies; the: the values of the variables where p holds

    def visit() -> None:
        if e.pred is not None and not ev(e.pred):
            return
        if e.kind == "set":
            out.insert(ev(e.body), e.type.element)  # type: ignore[arg-type, attr-defined]
        elif e.kind == "the":
            if found:
                raise CollectionFault(not_one)
            found.append([copy.deepcopy(ev(ir.Ref(d.var.type, d.var))) for d in e.domains])
        else:
            holds = bool(ev(e.body))  # type: ignore[arg-type]
            if e.kind == "forall" and not holds:
                raise _Stop
            if e.kind in ("exists", "exists1") and holds:
                found.append(True)
                if e.kind == "exists" or len(found) > 1:
                    raise _Stop

    def loop(k: int) -> None:
        if k == len(e.domains):
            visit()
            return
        d = e.domains[k]
        for v in values(d, ev, convert, too_long):
            store(d.var, v)
            loop(k + 1)

    try:
        loop(0)
    except _Stop:  # forall: a false body; exists: a true one; exists1: a second true one
        return e.kind == "exists"
    if e.kind == "set":
        return out.items
    if e.kind == "forall":
        return True
    if e.kind in ("exists", "exists1"):
        return len(found) == 1
    if not found:
        raise CollectionFault(not_one)
    for d, v in zip(e.domains, found[0]):
        store(d.var, v)
    return ev(e.body)  # type: ignore[arg-type]


def values(d: ir.Domain, ev, convert, too_long: str) -> list:
    """The values of domain ``d``, in order, as values of its variable's type."""
    t = d.var.type
    if d.kind == "values":
        return all_values(t) or []
    if d.kind == "range":
        low, high = ev(d.low), ev(d.high)
        if t == T.NAT:
            low = max(low, 0)
        if high >= low and high - low >= LOOP_LIMIT:
            raise CollectionFault(too_long)
        return [convert(x, T.INT, t) for x in range(low, high + 1)]
    elements = ev(d.set)
    source = d.set.type.element  # type: ignore[union-attr]
    return [convert(x, source, t) if source != t else x for x in elements if not (d.natural and x < 0)]


__all__ = ["evaluate", "values", "messages"]
