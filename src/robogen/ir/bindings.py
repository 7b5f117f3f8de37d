"""Lowering of names that stand for values rather than for memory: ``let`` names, the parameters
of an applied lambda, and the variable of an input trigger inside the trigger's filter.

Each is lowered by substitution: while the expression in its scope is lowered, a use of the name
becomes the IR expression of its value (``bound``, keyed by the name's declaration). RoboChart's
expressions have no side effects, so a value computed at each use is the value computed once.

- ``let x == e1, y == e2 @ body``: the names of one ``let`` are visible in the definitions after
  them and in the body, and hide outer names of the same spelling (as the checker resolves them).
- the parameters of a lambda applied to arguments, and a ``let`` name bound to a lambda (kept
  with the names of where it was defined): their application is in :mod:`robogen.ir.functions`.
- A filter ``e[| p |]?x`` on a trigger or an input statement: the communication happens only
  with a value for which ``p`` holds, and ``p`` reads ``x`` as the value offered (the value the
  variable would receive); an event whose value fails ``p`` is neither taken nor bound, and
  waits in the buffer as any event no transition takes. ``e[| p |]`` on an untyped event is ``p``
  as an extra condition. A filter that binds the sender (``x = from``) needs ``mult`` connections'
  identities and is not supported.
"""

from __future__ import annotations

from contextlib import contextmanager
from typing import TYPE_CHECKING, Iterator

from robogen.diagnostics import Span
from robogen.ir import model as ir
from robogen.ir.region_tree import Graph
from robogen.ir.supported import not_supported
from robogen.semantics.model import VarSym
from robogen.syntax import ast

if TYPE_CHECKING:
    from robogen.semantics.model import SemanticModel


def _key(sym: VarSym) -> int:
    return id(sym.decl) if sym.decl is not None else id(sym)


def _lambda(e: ast.Expr) -> ast.Binder | None:
    return e if isinstance(e, ast.Binder) and e.kind == "lambda" else None


class BindingLowering:
    """The substitution steps of :class:`~robogen.ir.machines.MachineLowering` (a mixin)."""

    model: SemanticModel
    machine: ir.Machine
    bound: dict[int, ir.Expr | tuple[ast.Binder, dict]]  # declaration -> value (or lambda, with its scope)
    # and the expression steps: expr, conv, _norm (of ExpressionLowering and MachineLowering)

    @contextmanager
    def binding(self, pairs) -> Iterator[None]:
        """Lower inside the scope of ``pairs`` ((VarSym or declaration key, value) ...)."""
        saved = dict(self.bound)
        for key, value in pairs:
            self.bound[key if isinstance(key, int) else _key(key)] = value
        try:
            yield
        finally:
            self.bound = saved

    def bound_value(self, sym: VarSym, span: Span | None) -> ir.Expr | None:
        """The value a name stands for here (None: it names memory)."""
        value = self.bound.get(_key(sym))
        if value is None:
            if sym.kind in ("let", "binder"):
                raise not_supported(f"'{sym.name}' here", span)
            return None
        if isinstance(value, tuple):
            raise not_supported(f"the function '{sym.name}' as a value (only its application)", span)
        return self.conv(value, self._norm(sym.type), span)

    def _e_Let(self, e: ast.Let, graph: Graph) -> ir.Expr:
        pairs: list[tuple[int, object]] = []
        for d in e.defs:
            lam = _lambda(d.value)
            with self.binding(pairs):
                value = (lam, dict(self.bound)) if lam is not None else self.expr(d.value, graph)
            pairs.append((id(d), value))
        with self.binding(pairs):
            return self.expr(e.body, graph)

    def filter_guard(self, c: ast.Communication, event: ir.Event, graph: Graph) -> ir.Expr | None:
        """The condition a communication's filter adds (None: no filter, or ``[||]``); ``x`` of
        ``e?x`` stands for the value offered."""
        f = c.filter
        if f is None or (f.bind is None and f.predicate is None):
            return None
        if f.bind is not None:
            raise not_supported("a filter that binds the sender ('x = from')", f.span)
        assert f.predicate is not None
        if c.kind not in ("", "?"):
            raise not_supported("a filter on an output or synchronisation", f.span)
        pairs: list = []
        var = self.model.bound_var(c) if c.kind == "?" else None
        if var is not None and event.type is not None:
            pairs.append((var, ir.Payload(event.type, event.index)))
        with self.binding(pairs):
            return self.expr(f.predicate, graph)


__all__ = ["BindingLowering"]
