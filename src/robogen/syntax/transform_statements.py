"""Rules of statements (actions): sequences, exec, wait, clock resets, conditionals, deadlines,
assignments, calls and RoboChart communications."""

from __future__ import annotations

from robogen.diagnostics import error
from robogen.syntax import ast


class Statements:
    """Callbacks of the statements rules (a part of :class:`~robogen.syntax.transform.ToAst`)."""

    def seq(self, c):
        left, right = c
        items = left.stmts if isinstance(left, ast.Seq) else (left,)
        node = ast.Seq(items + (right,), span=self._span(c))
        # a sequence is flat: its depth is one more than its deepest statement
        if isinstance(left, ast.Seq):
            depth = self._depth
            d = max(depth.get(id(left), 1), depth.get(id(right), 0) + 1)
            depth[id(node)] = d
            self._alive.append(node)
            return node
        return self._nest(node, c)

    def stmt_deadline(self, c):
        return ast.StmtDeadline(c[0], c[1], span=self._span(c, right=("}",)))

    def skip(self, c):
        return ast.Skip(span=self._span(c))

    def exec_stmt(self, c):
        return ast.Exec(span=self._span(c))

    def wait(self, c):
        return ast.Wait(c[0], span=self._span(c, left=("wait", "("), right=(")",)))

    def clock_reset(self, c):
        return ast.ClockReset(self._name(c[0]), span=self._span(c, left=("#",)), clock_span=self._tspan(c[0]))

    def if_stmt(self, c):
        return ast.IfStmt(c[0], c[1], c[2] if len(c) > 2 else None, span=self._span(c, left=("if",), right=("end",)))

    def send(self, c):
        return ast.Communicate(c[0], True, span=self._span(c, left=("send",)))

    def filtered_stmt(self, c):
        """A communication with a filter, written without `send`: `e[| p |]!v`."""
        comm = self.communication(c)
        return ast.Communicate(comm, False, span=comm.span)

    def bare_stmt(self, c):
        """A statement that is only a target: a call `op(args)`, a plain event `e`, or `e.v`
        (and `e.f(args)`, whose value is a call: RoboTool's `value=CallExp`)."""
        target = c[0]
        span = self._span(c)
        if isinstance(target, ast.Call):
            func = target.func
            if isinstance(func, ast.Field) and _event_name(func.obj):
                callee = ast.Name((func.field,), span=func.field_span)
                value = ast.Call(callee, target.args, span=self._make(func.field_span.offset, target.span.end_offset))
                return self._communicate(func.obj, ".", value, span)
            return ast.CallStmt(target, span=span)
        if _event_name(target):
            comm = ast.Communication(target.last, span=span, event_span=target.span)
            return ast.Communicate(comm, False, span=span)
        if isinstance(target, ast.Field) and _event_name(target.obj):
            return self._communicate(target.obj, ".", ast.Name((target.field,), span=target.field_span), span)
        self.problems.append(error("this expression is not a statement (expected an assignment, a call or a communication)", span))
        return ast.Skip(span=span)

    def assign(self, c):
        return ast.Assign(c[0], c[1], span=self._span(c))

    def _communicate(self, event: ast.Name, kind: str, value: ast.Expr, span) -> ast.Communicate:
        comm = ast.Communication(event.last, kind, value=value, span=span, event_span=event.span)
        return ast.Communicate(comm, False, span=span)

    def _stmt_comm(self, c, kind):
        target, payload = c
        span = self._span(c)
        if not _event_name(target):
            self.problems.append(error("a communication must name an event", target.span or span))
            return ast.Skip(span=span)
        if kind == "?":
            comm = ast.Communication(target.last, "?", payload.last, var_qualifier=payload.parts[:-1], span=span,
                                     event_span=target.span, var_span=payload.span)
            return ast.Communicate(comm, False, span=span)
        return self._communicate(target, kind, payload, span)

    def comm_input_stmt(self, c):
        return self._stmt_comm(c, "?")

    def comm_output_stmt(self, c):
        return self._stmt_comm(c, "!")

    def comm_sync_stmt(self, c):
        return self._stmt_comm(c, ".")

    def sync_qname(self, c):
        """The qualified name a synchronisation carries (`e.E::lit`)."""
        return self.qname(c)


def _event_name(target) -> bool:
    """Is this target the plain name a communication starts with?"""
    return isinstance(target, ast.Name) and not target.qualified
