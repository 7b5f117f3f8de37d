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
  as an extra condition.
- A filter that binds the sender, ``e[| x = from |]`` (with a predicate ``e[| x = from | p |]``,
  which reads ``x`` as the sender): when the communication happens, ``x`` receives the sender of
  the occurrence taken (a variable that is also the input's ``?x`` receives the value, which is
  bound last). The sender is where the occurrence comes from: the FMU's boundary - the robotic
  platform of a module (its name as the module references it), or the environment of a single
  machine - or the state machine that sent it, through whatever connections of controllers and
  modules it travelled. Its number is 0 for the boundary and k for the k-th state machine of the
  FMU (the order of their ``<machine>.state`` outputs); a ``nat`` or ``int`` variable receives the
  number, a ``string`` variable the name (the platform's, ``environment``, or the machine's FMI
  name). An event that such a filter reads keeps its sender in its register (ir.model.Event).
"""

from __future__ import annotations

from contextlib import contextmanager
from typing import TYPE_CHECKING, Iterator

from robogen.diagnostics import Span
from robogen.ir import model as ir
from robogen.ir.region_tree import Graph
from robogen.ir.supported import not_supported
from robogen.semantics import types as T
from robogen.semantics.model import MachineScope, VarSym
from robogen.syntax import ast

if TYPE_CHECKING:
    from robogen.ir.boundary import Boundary
    from robogen.semantics.model import SemanticModel

SENDER = "from"  # the field of an event register that holds the sender's number
ENVIRONMENT = "environment"  # the sender's name of what reaches a single machine's FMU from outside


def sender_type(value: T.Type | None) -> T.RecordT:
    """The register of an event that keeps its sender: its value (if it carries one) and the
    sender's number."""
    fields = ((("value", value),) if value is not None else ()) + ((SENDER, T.NAT),)
    return T.RecordT(f"sent({value.show() if value is not None else ''})", fields)


def sender_events(model: SemanticModel, scope: MachineScope) -> set[str]:
    """The events of machine ``scope`` whose sender some filter ``[| x = from |]`` reads: in the
    machine, or in an operation definition (any of the workspace: one it may call)."""
    names = set()
    for body in [scope] + [s for s in model.scopes if s.is_operation]:
        for use in body.communications():
            comm = use.node.comm if isinstance(use.node, ast.Communicate) else use.node
            if comm.filter is not None and comm.filter.bind is not None:
                names.add(use.event)
    return names


def _key(sym: VarSym) -> int:
    return id(sym.decl) if sym.decl is not None else id(sym)


def _lambda(e: ast.Expr) -> ast.Binder | None:
    return e if isinstance(e, ast.Binder) and e.kind == "lambda" else None


class BindingLowering:
    """The substitution steps of :class:`~robogen.ir.machines.MachineLowering` (a mixin)."""

    model: SemanticModel
    machine: ir.Machine
    boundary: Boundary
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
        """The condition a communication's filter adds (None: no filter, ``[||]`` or only
        ``[| x = from |]``); ``x`` of ``e?x`` stands for the value offered, the variable of
        ``x = from`` for the sender."""
        f = c.filter
        if f is None or (f.bind is None and f.predicate is None):
            return None
        if c.kind not in ("", "?"):
            raise not_supported("a filter on an output or synchronisation", f.span)
        if f.predicate is None:
            return None
        sender = self.sender_binding(c, event)
        pairs: list = [sender] if sender is not None else []
        var = self.model.bound_var(c) if c.kind == "?" else None
        if var is not None and event.value_type is not None:  # after the sender: the value wins
            pairs.append((var, self.conv(self.event_value(event), self._norm(var.type), c.span)))  # type: ignore[attr-defined]
        with self.binding(pairs):
            return self.expr(f.predicate, graph)

    def event_value(self, event: ir.Event) -> ir.Expr:
        """The value the occurrence of ``event`` in the machine's buffer carries."""
        payload = ir.Payload(event.type, event.index)  # type: ignore[arg-type]
        return ir.FieldOf(event.value_type, payload, "value") if event.sender else payload  # type: ignore[arg-type]

    def sender_binding(self, c: ast.Communication, event: ir.Event) -> tuple[VarSym, ir.Expr] | None:
        """(variable, value) of ``e[| x = from |]``: the sender of the occurrence of ``event`` in
        the buffer, as the type of ``x`` holds it (None: the communication binds no sender)."""
        var = self.model.sender_var(c) if c.filter is not None and c.filter.bind is not None else None
        if var is None:
            return None
        assert event.sender, f"event {event.name} keeps no sender"
        number: ir.Expr = ir.FieldOf(T.NAT, ir.Payload(event.type, event.index), SENDER)  # type: ignore[arg-type]
        t = self._norm(var.type)  # type: ignore[attr-defined]
        if t == T.NAT:
            return var, number
        if t == T.INT:
            return var, ir.Conv(T.INT, number)
        if t != T.STRING:
            raise not_supported(f"the sender in '{var.name}' of type {t.show()} (robogen gives the sender as a number, "
                                "nat or int, or as a name, string)", c.filter.span)  # type: ignore[union-attr]
        names = self.sender_names()
        value: ir.Expr = ir.Lit(T.STRING, names[0])
        for k in range(len(names) - 1, 0, -1):
            value = ir.Cond(T.STRING, ir.Bin(T.BOOLEAN, "eq", number, ir.Lit(T.NAT, k)), ir.Lit(T.STRING, names[k]), value)
        return var, value

    def sender_names(self) -> list[str]:
        """The name of each sender, by number: the boundary's, then each machine's."""
        module = self.boundary.module
        boundary = module.platform.name if module is not None and module.platform is not None else ENVIRONMENT
        return [boundary] + [m.name for m in self.ctx.fmu.machines]  # type: ignore[attr-defined]


__all__ = ["BindingLowering", "SENDER", "ENVIRONMENT", "sender_type", "sender_events"]
