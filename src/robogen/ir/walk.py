"""Every value of an FMU's IR, and every type those values have.

A back end that declares types (the C typedefs of records, tuples, tagged enumerations, vectors
and collections) must see each type wherever it first appears: a machine variable or constant,
an event or operation parameter at the boundary, a user function's signature, or only inside an
expression (a record literal whose fields are records, passed to a platform operation, has types
that no variable names). :func:`value_types` yields them all, and :func:`expressions` every
expression node of the machines, found through the dataclass fields of the IR nodes, so that an
expression form added to :mod:`robogen.ir.model` is walked without a change here.

The walk keeps its own stack: a flat chain of thousands of operands is an expression thousands
deep (see :func:`robogen.ir.model.bin_chain`), which recursion would not survive.
"""

from __future__ import annotations

from dataclasses import fields
from typing import Iterator

from robogen.ir import model as ir
from robogen.semantics import types as T


def _children(node: object) -> Iterator[object]:
    """The IR nodes (expressions, statements, terminators, cases, and the domains of a
    quantifier's bound variables, which hold expressions: ``forall x: nat | x in {first((| 3, e |))}``
    has a tuple type only its domain's set names) directly inside ``node``."""
    for f in fields(node):  # type: ignore[arg-type]
        if f.name in ("span", "type", "var", "state"):
            continue  # not sub-expressions (a Ref's Var is walked with its machine)
        value = getattr(node, f.name)
        stack = [value]
        while stack:
            v = stack.pop()
            if isinstance(v, (ir.Expr, ir.Stmt, ir.Terminator, ir.Case, ir.Domain)):
                yield v
            elif isinstance(v, (tuple, list)):
                stack.extend(reversed(v))


def children(node: object) -> Iterator[object]:
    """The IR nodes directly inside ``node`` (for the other passes that walk expressions)."""
    return _children(node)


def expressions(fmu: ir.Fmu) -> Iterator[ir.Expr]:
    """Every expression node of every machine (variable initialisers, statements, guards),
    outermost first."""
    for m in fmu.machines:
        roots: list[object] = [v.init for v in m.vars if v.init is not None]
        for b in m.blocks:
            roots += b.stmts
            if b.term is not None:
                roots.append(b.term)
        stack = list(reversed(roots))
        while stack:
            node = stack.pop()
            if isinstance(node, ir.Expr):
                yield node
            stack.extend(reversed(list(_children(node))))


def initial_order(m: ir.Machine) -> list[ir.Var]:
    """The variables of ``m`` that have an initial value, in the order Initialization Mode's end
    computes them: the constants first, then the others (variables, the generator's state) in
    declaration order, each after the ones its initialiser reads. A constant's value does not
    depend on where the model declares it (``var x: int = k + 1`` before ``const k: int = ...``
    reads k's value); a cycle (two variables reading each other) keeps declaration order."""
    own = {id(v): v for v in m.vars if v.init is not None}
    order: list[ir.Var] = []
    seen: set[int] = set()

    def visit(v: ir.Var) -> None:
        seen.add(id(v))
        stack: list[object] = [v.init]
        while stack:  # the variables of m this initialiser reads, outermost first
            node = stack.pop()
            if isinstance(node, ir.Ref) and id(node.var) in own and id(node.var) not in seen:
                visit(node.var)
            stack.extend(reversed(list(_children(node))))
        order.append(v)

    for v in sorted(own.values(), key=lambda v: v.kind != "const"):  # stable: declaration order within each
        if id(v) not in seen:
            visit(v)
    return order


def value_types(fmu: ir.Fmu) -> Iterator[T.Type]:
    """The type of every value the FMU holds or passes: its ports' payloads and operation
    parameters, its user functions' parameters and results, each machine's variables and events,
    and every expression. A type is yielded as it appears; the types inside it (fields, elements)
    are the caller's to follow."""
    for p in (*fmu.inputs, *fmu.outputs):
        if p.type is not None:
            yield p.type
        for _, t in p.params:
            yield t
    for u in fmu.user_functions:
        yield from (t for _, t in u.params)
        yield u.result
    for m in fmu.machines:
        yield from (v.type for v in m.vars)
        yield from (e.type for e in m.events if e.type is not None)
    for e in expressions(fmu):
        yield e.type


__all__ = ["children", "expressions", "value_types"]
