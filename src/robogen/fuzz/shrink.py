"""Shrinking a failing model: delta debugging over its AST.

:func:`shrink` tries smaller variants of the model, each one local change: remove a declaration,
a member, a state, a transition or a statement (from a list: first halves, then quarters, down
to one element); drop an optional part (a condition, an action, an initial value, a trigger);
replace a statement by ``skip`` or by one of its parts; replace an expression by one of its
operands or by a literal. A variant is kept when it still fails the same property in the same
way (:meth:`robogen.fuzz.properties.Failure.same`), and the search starts again from it, until no
variant does or the time is up. Most variants no longer check, which the predicate finds in
milliseconds; only those that check are compiled and run.
"""

from __future__ import annotations

import time
from dataclasses import fields, replace
from typing import Callable, Iterator

from robogen.syntax import ast, printer

Predicate = Callable[[ast.File], bool]

_LITERALS: tuple[ast.Expr, ...] = (ast.IntLit(0), ast.IntLit(1), ast.BoolLit(True), ast.BoolLit(False), ast.RealLit("0.5"))


def _node_fields(node: ast.Node):
    """The fields of ``node`` that hold nodes or tuples of nodes (not spans, names or flags)."""
    for f in fields(node):
        if not f.compare:
            continue
        value = getattr(node, f.name)
        if isinstance(value, ast.Node) or (isinstance(value, tuple) and value and isinstance(value[0], ast.Node)):
            yield f, value


def _optional(node: ast.Node, name: str) -> bool:
    return any(f.name == name and f.default is None for f in fields(node))


def _chunks(n: int) -> Iterator[tuple[int, int]]:
    """Ranges to remove from a list of ``n``: the whole of it, halves, quarters, ..., single elements."""
    size = n
    while size >= 1:
        for start in range(0, n, size):
            yield start, min(n, start + size)
        if size == 1:
            break
        size = max(1, size // 2)


def _replacements(node: ast.Node) -> Iterator[ast.Node]:
    """Simpler nodes to put in the place of ``node``."""
    if isinstance(node, ast.Expr):
        for f, value in _node_fields(node):
            for x in (value if isinstance(value, tuple) else (value,)):
                if isinstance(x, ast.Expr):
                    yield x
        if not isinstance(node, (ast.IntLit, ast.BoolLit, ast.RealLit)):
            yield from _LITERALS
    elif isinstance(node, ast.Stmt) and not isinstance(node, ast.Skip):
        if isinstance(node, ast.Seq):
            yield from node.stmts
        elif isinstance(node, ast.IfStmt):
            yield node.then
            if node.otherwise is not None:
                yield node.otherwise
        elif isinstance(node, ast.StmtDeadline):
            yield node.stmt
        yield ast.Skip()


# Fields that hold a name or a size, not a value: their node is never replaced.
_STRUCTURAL = frozenset({"package", "name", "type", "target", "state", "size", "rows", "columns", "func"})


def _replaceable(parent: ast.Node, name: str) -> bool:
    return name not in _STRUCTURAL and not isinstance(parent, (ast.File, ast.Import, ast.CycleDef, ast.TypeExpr))


def variants(node: ast.Node) -> Iterator[ast.Node]:
    """Every variant of ``node`` with one local change, the changes nearest the root first."""
    for f, value in _node_fields(node):
        if isinstance(value, tuple):
            for a, b in _chunks(len(value)):
                if f.name in ("stmts",) and b - a == len(value):
                    continue  # (an empty sequence is not a statement)
                yield replace(node, **{f.name: value[:a] + value[b:]})
        elif _optional(node, f.name):
            yield replace(node, **{f.name: None})
    for f, value in _node_fields(node):
        items = value if isinstance(value, tuple) else (value,)
        for i, child in enumerate(items):
            if not isinstance(child, ast.Node):
                continue
            if _replaceable(node, f.name):
                for simpler in _replacements(child):
                    yield _put(node, f.name, value, i, simpler)
            for v in variants(child):
                yield _put(node, f.name, value, i, v)


def _put(node: ast.Node, name: str, value, i: int, child: ast.Node) -> ast.Node:
    if isinstance(value, tuple):
        return replace(node, **{name: value[:i] + (child,) + value[i + 1:]})
    return replace(node, **{name: child})


def shrink(file: ast.File, fails: Predicate, *, seconds: float = 600.0, log: Callable[[str], None] | None = None) -> ast.File:
    """The smallest variant of ``file`` found in ``seconds`` for which ``fails`` holds (``file``
    itself must fail). After a variant is kept, the search goes on from the same place in the
    order of variants (those before it were just rejected), and starts over from the root once
    it has run through them all; it stops when a whole pass keeps nothing."""
    deadline = time.monotonic() + seconds
    tried: set[str] = set()
    current, size = file, len(printer.file(file))
    start = 0
    while time.monotonic() < deadline:
        kept = None
        for position, candidate in enumerate(variants(current)):
            if position < start:
                continue
            if time.monotonic() > deadline:
                return current
            try:
                text = printer.file(candidate)  # type: ignore[arg-type]
            except TypeError:  # a part the syntax needs was dropped (the value of `e!v`)
                continue
            if len(text) >= size or text in tried:
                continue
            tried.add(text)
            if fails(candidate):  # type: ignore[arg-type]
                kept = position
                current, size = candidate, len(text)  # type: ignore[assignment]
                if log is not None:
                    log(f"shrunk to {size} characters ({len(tried)} variants tried)")
                break
        if kept is not None:
            start = kept
        elif start > 0:  # the end of the variants: once more from the root
            start = 0
        else:
            return current
    return current


__all__ = ["shrink", "variants"]
