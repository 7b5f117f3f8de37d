"""Type checking of RoboSim's ``$`` expressions (a part of
:class:`~robogen.semantics.exprs.ExprChecker`), as RoboSim's type provider types them: ``$e``
of an input event is a boolean (it occurred), ``$x`` of a variable its value, ``$r.f`` a field
of a record variable; ``$e?x`` and ``$e.v`` test an input in a transition condition. They may
stand anywhere an expression can, the value of an output included (``$out!$x``, ``$out.$in``).
An output event cannot be tested.

A name after ``$`` (or after ``?``) may be qualified by the interface or machine that declares
it (``$I::x``): :meth:`DollarForms.qualifier_fits` checks that it does.
"""

from __future__ import annotations

from robogen.diagnostics import Note, Span, did_you_mean
from robogen.semantics import types as T
from robogen.semantics.model import KIND_WORDS, EventSym, VarSym
from robogen.syntax import ast


class DollarForms:
    """The ``$`` rules of :class:`~robogen.semantics.exprs.ExprChecker` (a mixin)."""

    def qualifier_fits(self, qualifier: tuple[str, ...], name: str, decl: ast.Node | None, span: Span | None) -> bool:
        """Does ``qualifier::name`` name ``decl`` (a member of this machine, or of an interface
        it names)? Reports it when not."""
        if not qualifier:
            return True
        owners = [tuple(self.scope.qname.split("::"))] if _declares(self.scope.node, decl) else []
        for _, ref, iface in self.scope.interfaces:
            if iface is not None and _declares(iface, decl):
                owners += [ref.name.parts, (iface.name,)]
        if any(owner[len(owner) - len(qualifier):] == qualifier for owner in owners):
            return True
        self.sink.error(f"'{'::'.join(qualifier + (name,))}' does not name '{name}' of {self.scope.kind} '{self.scope.name}'", span,
                        Note("a qualified name names the interface, or the machine, that declares it"))
        return False

    def _dollar_event(self, name: str, node, span) -> EventSym | None:
        ev = self.scope.events.get(name)
        if ev is None:
            self.sink.error(
                f"unknown event '{name}'" + did_you_mean(name, self.scope.events),
                span,
                Note("RoboSim machines declare the events they read in their 'input context'"),
            )
            return None
        self.tables.refs[id(node)] = ev
        if not ev.input:
            self.sink.error(
                f"'{name}' is an output event; output events cannot be tested in a condition",
                span,
                Note(f"declared in {ev.origin}", ev.span),
            )
        return ev

    def _require_guard(self, e: ast.Expr, what: str) -> None:
        if not self.where.guard:
            self._err(f"'{what}' tests an input and may only appear in a transition condition", e)

    def _dollar_variable(self, name: str) -> VarSym | None:
        """The variable ``$name`` reads, if it names one (and not an event)."""
        v = self.scope.vars.get(name)
        return v if v is not None and name not in self.scope.events else None

    def _e_Dollar(self, e: ast.Dollar) -> T.Type:
        if not self.robosim:
            return self._err("'$' is RoboSim syntax", e)
        span = e.name_span or e.span
        v = self._dollar_variable(e.name)
        if v is not None:
            self.qualifier_fits(e.qualifier, e.name, v.decl, span)
            self.tables.refs[id(e)] = v
            return v.type
        ev = self._dollar_event(e.name, e, span)
        if ev is not None:
            self.qualifier_fits(e.qualifier, e.name, ev.decl, span)
        return T.BOOLEAN

    def _e_DollarInput(self, e: ast.DollarInput) -> T.Type:
        self._require_guard(e, f"${e.event}?{e.var}")
        ev = self._dollar_event(e.event, e, e.event_span or e.span)
        if ev is not None:
            self.qualifier_fits(e.qualifier, e.event, ev.decl, e.event_span or e.span)
        var = self.lookup_var(e.var)
        if var is None:
            self.sink.error(f"unknown variable '{e.var}'" + did_you_mean(e.var, self._visible_value_names()), e.var_span or e.span)
        elif not self.qualifier_fits(e.var_qualifier, e.var, var.decl, e.var_span or e.span):
            pass  # reported
        elif not var.assignable:
            self.sink.error(f"cannot bind the value of '{e.event}' to {KIND_WORDS[var.kind]} '{e.var}'", e.var_span or e.span, Note("declared here", var.span))
        elif ev is not None:
            if ev.type is None:
                self.sink.error(f"event '{e.event}' carries no value to bind to '{e.var}'", e.event_span or e.span, Note("declared here", ev.span))
            elif not T.receivable(ev.type, var.type):
                self.sink.error(
                    f"cannot bind a value of event '{e.event}' ({ev.type.show()}) to '{e.var}' ({var.type.show()})",
                    e.var_span or e.span,
                )
        if var is not None:
            self.tables.refs[("bind", id(e))] = var
        if e.predicate is not None:
            pt = self.expr(e.predicate)
            if not T.is_boolean(pt):
                self._err(f"the predicate after ':' must be boolean, not {pt.show()}", e.predicate)
        return T.BOOLEAN

    def _e_DollarValue(self, e: ast.DollarValue) -> T.Type:
        v = self._dollar_variable(e.event)
        if v is not None:
            return self._dollar_field(e, v)
        self._require_guard(e, f"${e.event}.v")
        ev = self._dollar_event(e.event, e, e.event_span or e.span)
        vt = self.expr(e.value)
        if ev is not None:
            self.qualifier_fits(e.qualifier, e.event, ev.decl, e.event_span or e.span)
            if ev.type is None:
                self.sink.error(f"event '{e.event}' carries no value", e.event_span or e.span)
            elif not T.comparable(vt, ev.type):
                self._err(f"event '{e.event}' carries {ev.type.show()}, not {vt.show()}", e.value)
        return T.BOOLEAN

    def _dollar_field(self, e: ast.DollarValue, v: VarSym) -> T.Type:
        """``$r.f`` for a variable ``r``: its field ``f``."""
        self.qualifier_fits(e.qualifier, e.event, v.decl, e.event_span or e.span)
        self.tables.refs[id(e)] = v
        record = self._record(v.type)
        if isinstance(record, T.UnknownT):
            return record
        if not isinstance(record, T.RecordT) or not (isinstance(e.value, ast.Name) and not e.value.qualified):
            return self._err(f"after ${e.event}, a variable of type {v.type.show()}, '.' selects a field of a record", e)
        field = record.field(e.value.last)
        if field is None:
            return self._err(f"datatype '{record.qname}' has no field '{e.value.last}'" + did_you_mean(e.value.last, [n for n, _ in record.fields]),
                             e.value)
        return field


def _declares(container: ast.Node, decl: ast.Node | None) -> bool:
    """Is ``decl`` declared by the interface or machine (a variable of one of its lists, an event,
    operation, clock or parameter; for a RoboSim machine, a member of one of its contexts)?"""
    members = getattr(container, "members", ()) + getattr(container, "params", ())
    for m in members:
        if m is decl or (isinstance(m, ast.VarList) and any(v is decl for v in m.vars)):
            return True
        if isinstance(m, ast.Context) and _declares(m, decl):
            return True
    return False


__all__ = ["DollarForms"]
