"""Type checking of statements (actions) inside one state machine or operation, and of the
communications of triggers: assignments, calls, communications, the RoboSim $ statements, and
the rules on where each may appear."""

from __future__ import annotations

from robogen.diagnostics import Note, did_you_mean
from robogen.semantics import types as T
from robogen.semantics.exprs import ExprChecker, Where
from robogen.semantics.model import KIND_WORDS, EventSym
from robogen.syntax import ast


class StmtChecker(ExprChecker):
    """Checks statements and communications; expressions through :class:`ExprChecker`."""

    def stmt(self, s: ast.Stmt) -> None:
        saved = self.where
        self.where = Where(action=True)
        try:
            self._stmt(s)
        finally:
            self.where = saved

    def _stmt(self, s: ast.Stmt) -> None:
        rule = self._stmt_rules.get(type(s)) or self.rule(self._stmt_rules, "_s_", type(s))
        if rule is None:  # pragma: no cover - every statement class has a method
            raise AttributeError(f"{type(self).__name__} has no rule _s_{type(s).__name__}")
        rule(self, s)

    def _s_Skip(self, s: ast.Skip) -> None:
        pass

    def _s_Exec(self, s: ast.Exec) -> None:
        pass

    def _s_Wait(self, s: ast.Wait) -> None:
        if self.robosim:
            self.sink.error("RoboSim has no 'wait': time passes in cycles; count cycles with a clock and 'since'", s.span)
            return
        t = self.expr(s.duration)
        if not (T.is_integral(t) or (isinstance(t, T.SetT) and T.is_integral(t.element))):
            self._err(f"'wait' takes an integer number of time units, or a set of them; this is {t.show()}", s.duration)

    def _s_ClockReset(self, s: ast.ClockReset) -> None:
        clock = self.scope.clocks.get(s.clock)
        if clock is None:
            self.sink.error(f"unknown clock '{s.clock}'" + did_you_mean(s.clock, self.scope.clocks), s.clock_span or s.span)
        else:
            self.tables.refs[id(s)] = clock

    def _s_Seq(self, s: ast.Seq) -> None:
        for x in s.stmts:
            self._stmt(x)

    def _s_IfStmt(self, s: ast.IfStmt) -> None:
        t = self.expr(s.cond)
        if not T.is_boolean(t):
            self._err(f"the condition of 'if' must be boolean, not {t.show()}", s.cond)
        self._stmt(s.then)
        if s.otherwise is not None:
            self._stmt(s.otherwise)

    def _s_Assign(self, s: ast.Assign) -> None:
        target_t = self._lvalue(s.target)
        vt = self.expr(s.value)
        if target_t is not None and not T.assignable(vt, target_t):
            self._err(f"cannot assign {vt.show()} to {_describe(s.target)} of type {target_t.show()}", s.value)

    def _lvalue(self, e: ast.Expr) -> T.Type | None:
        if isinstance(e, ast.Name) and not e.qualified:
            v = self.lookup_var(e.last)
            if v is None:
                self.expr(e)  # reports the unknown name
                return None
            self.tables.refs[id(e)] = v
            self._set(e, v.type)
            if not v.assignable:
                what = KIND_WORDS[v.kind]
                self.sink.error(f"cannot assign to {what} '{v.name}'", e.span, Note("declared here", v.span))
            return v.type
        if isinstance(e, ast.Field):
            base = self._lvalue(e.obj)
            if base is None:
                return None
            return self._e_Field_of(e, base)
        if isinstance(e, ast.Index):
            base = self._lvalue(e.obj)
            for i in e.indices:
                self.expr(i)
            if base is None:
                return None
            t = self._set(e, self._index_type(e, base))
            return t
        self._err("cannot assign to this expression", e)
        return None

    def _e_Field_of(self, e: ast.Field, base: T.Type) -> T.Type | None:
        base = self._record(base)
        if isinstance(base, T.UnknownT):
            return None
        if not isinstance(base, T.RecordT):
            self._err(f"'.{e.field}' selects a field, but this is {base.show()}, not a record", e.obj)
            return None
        ft = base.field(e.field)
        if ft is None:
            self.sink.error(f"datatype '{base.qname}' has no field '{e.field}'" + did_you_mean(e.field, [n for n, _ in base.fields]), e.field_span or e.span)
            return None
        self._set(e, ft)
        return ft

    def _index_type(self, e: ast.Index, base: T.Type) -> T.Type:
        if isinstance(base, (T.VectorT, T.SeqT)):
            return base.element
        if isinstance(base, T.MatrixT):
            return base.element
        if isinstance(base, T.ProductT) and len(e.indices) == 1 and isinstance(e.indices[0], ast.IntLit):
            k = e.indices[0].value
            if 1 <= k <= len(base.items):
                return base.items[k - 1]
        if not isinstance(base, T.UnknownT):
            self._err(f"{base.show()} cannot be indexed", e.obj)
        return T.UNKNOWN

    def _s_CallStmt(self, s: ast.CallStmt) -> None:
        call = s.call
        f = call.func
        arg_types = [self.expr(a) for a in call.args]
        if not isinstance(f, ast.Name):
            self._err("only named operations can be called", f)
            return
        op = self.scope.ops.get(f.last)
        if op is not None and f.qualified and self.lookup_global(f, self.scope.file, (ast.OperationDef,), "operation", False) is None:
            op = None  # pkg::op names an operation definition of that package, which must exist
        if op is None:
            known = [n for n in self.scope.ops]
            glob = self.lookup_global(f, self.scope.file, (ast.OperationDef,), "operation", False)
            notes = []
            if glob is not None:
                notes.append(Note(f"'{f.text}' is defined here but not required by this {self.scope.kind}: add 'requires' of an interface declaring it", glob.span))
            fn = self.lookup_global(f, self.scope.file, (ast.FunctionDef,), "function", False)
            if fn is not None:
                self._err(f"'{f.text}' is a function; a function call is an expression, not a statement", f)
                return
            self.sink.error(f"unknown operation '{f.text}'" + did_you_mean(f.last, known), f.span, *notes)
            return
        self.tables.refs[id(f)] = op
        if self.robosim and op.platform:
            self.sink.error(
                f"'{op.name}' is a platform operation; RoboSim calls it as ${op.name}(...)",
                f.span,
                Note(f"declared in {op.origin}", op.span),
            )
        self._check_args(f"operation '{op.name}'", op.params, call.args, arg_types, call)
        self.outputs_used.append((op.name, s))

    def _s_Communicate(self, s: ast.Communicate) -> None:
        if self.robosim:
            self.sink.error(
                "RoboChart communication statements are not allowed in RoboSim; write $e, $e!v or $op(...)",
                s.span,
            )
            return
        self.communication(s.comm, trigger=False)

    def communication(self, c: ast.Communication, trigger: bool) -> EventSym | None:
        ev = self.scope.events.get(c.event)
        if ev is None:
            self.sink.error(
                f"unknown event '{c.event}'" + did_you_mean(c.event, self.scope.events),
                c.event_span or c.span,
                Note(f"events come from 'event' declarations and the interfaces the {self.scope.kind} uses"),
            )
            return None
        self.tables.refs[id(c)] = ev
        if c.filter is not None:
            if c.filter.bind is not None:
                self._sender(c)
            if c.filter.predicate is not None:
                self.expr(c.filter.predicate)
        if c.kind == "":
            if ev.type is not None and not trigger:
                self.sink.error(
                    f"event '{c.event}' carries {ev.type.show()}: send a value with {c.event}!v or receive it with {c.event}?x",
                    c.span,
                )
            return ev
        if ev.type is None:
            self.sink.error(f"event '{c.event}' carries no value", c.event_span or c.span, Note("declared here", ev.span))
            return ev
        if c.kind == "?":
            var = self.lookup_var(c.var or "")
            if var is None:
                self.sink.error(f"unknown variable '{c.var}'" + did_you_mean(c.var or "", self._visible_value_names()), c.var_span or c.span)
            elif not self.qualifier_fits(c.var_qualifier, var.name, var.decl, c.var_span or c.span):
                pass  # reported
            elif not var.assignable:
                self.sink.error(f"cannot receive into {KIND_WORDS[var.kind]} '{var.name}'", c.var_span or c.span, Note("declared here", var.span))
            elif not T.receivable(ev.type, var.type):
                self.sink.error(
                    f"cannot receive a value of event '{c.event}' ({ev.type.show()}) into '{var.name}' ({var.type.show()})",
                    c.var_span or c.span,
                )
            if var is not None:
                self.tables.refs[("bind", id(c))] = var
        else:
            assert c.value is not None
            vt = self.expr(c.value)
            if not T.assignable(vt, ev.type):
                self._err(f"event '{c.event}' carries {ev.type.show()}, but this value is {vt.show()}", c.value)
            if c.kind == "!":
                self.outputs_used.append((c.event, c))
        return ev

    def _sender(self, c: ast.Communication) -> None:
        """``e[| x = from |]``: the variable x receives the sender of the event (RoboTool's grammar:
        ``_from=[Variable] '=' 'from'``; what the sender is: robogen.ir.bindings)."""
        f = c.filter
        assert f is not None and f.bind is not None
        if not (isinstance(f.bind_value, ast.Keyword) and f.bind_value.word == "from"):
            self.sink.error(f"a filter binds a variable to the sender only: write '{f.bind} = from'", f.bind_value.span if f.bind_value else f.span)
        var = self.lookup_var(f.bind)
        if var is None:
            self.sink.error(f"unknown variable '{f.bind}'" + did_you_mean(f.bind, self._visible_value_names()), f.span)
        elif not var.assignable:
            self.sink.error(f"cannot bind the sender to {KIND_WORDS[var.kind]} '{var.name}'", f.span, Note("declared here", var.span))
        else:
            self.tables.refs[("from", id(c))] = var

    def _s_StmtDeadline(self, s: ast.StmtDeadline) -> None:
        if self.robosim:
            self.sink.error("deadlines '<{ }' mean nothing in RoboSim and are rejected", s.span)
            return
        self._stmt(s.stmt)
        t = self.expr(s.bound)
        if not T.is_numeric(t):
            self._err(f"a deadline is a number of time units, not {t.show()}", s.bound)

    def _s_DollarOutput(self, s: ast.DollarOutput) -> None:
        ev = self.scope.events.get(s.event)
        if ev is None:
            self.sink.error(
                f"unknown event '{s.event}'" + did_you_mean(s.event, self.scope.events),
                s.event_span or s.span,
                Note("RoboSim machines declare the events they write in their 'output context'"),
            )
            return
        self.tables.refs[id(s)] = ev
        self.qualifier_fits(s.qualifier, s.event, ev.decl, s.event_span or s.span)
        if not ev.output:
            self.sink.error(
                f"'{s.event}' is an input event; an input event cannot be written",
                s.event_span or s.span,
                Note(f"declared in {ev.origin}", ev.span),
            )
        if s.kind == "":
            if ev.type is not None:
                self.sink.error(f"event '{s.event}' carries {ev.type.show()}: write ${s.event}!v", s.span)
        else:
            assert s.value is not None
            vt = self.expr(s.value)
            if ev.type is None:
                self.sink.error(f"event '{s.event}' carries no value", s.event_span or s.span, Note("declared here", ev.span))
            elif not T.assignable(vt, ev.type):
                self._err(f"event '{s.event}' carries {ev.type.show()}, but this value is {vt.show()}", s.value)
        self.outputs_used.append((s.event, s))

    def _s_DollarCall(self, s: ast.DollarCall) -> None:
        arg_types = [self.expr(a) for a in s.args]
        op = self.scope.ops.get(s.op)
        if op is None:
            self.sink.error(
                f"unknown platform operation '{s.op}'" + did_you_mean(s.op, self.scope.ops),
                s.op_span or s.span,
                Note("RoboSim machines name the platform operations they call in their 'output context' (requires I)"),
            )
            return
        self.tables.refs[id(s)] = op
        self.qualifier_fits(s.qualifier, s.op, op.decl, s.op_span or s.span)
        self._check_args(f"operation '{op.name}'", op.params, s.args, arg_types, s)
        self.outputs_used.append((op.name, s))

    def _s_DollarAssign(self, s: ast.DollarAssign) -> None:
        vt = self.expr(s.value)
        v = self.scope.vars.get(s.var)
        if v is None:
            self.sink.error(f"unknown shared variable '{s.var}'" + did_you_mean(s.var, self.scope.vars), s.var_span or s.span)
            return
        self.tables.refs[id(s)] = v
        if not self.qualifier_fits(s.qualifier, s.var, v.decl, s.var_span or s.span):
            return
        if not v.assignable:
            self.sink.error(f"cannot assign to {KIND_WORDS[v.kind]} '{v.name}'", s.var_span or s.span, Note("declared here", v.span))
        elif not T.assignable(vt, v.type):
            self._err(f"cannot assign {vt.show()} to '{v.name}' of type {v.type.show()}", s.value)


def _describe(e: ast.Expr) -> str:
    if isinstance(e, ast.Name):
        return f"'{e.text}'"
    if isinstance(e, ast.Field):
        return f"field '{e.field}'"
    return "this element"


__all__ = ["StmtChecker"]
