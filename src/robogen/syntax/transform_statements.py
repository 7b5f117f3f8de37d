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

    def bare_stmt(self, c):
        """A statement that is only a target: a call `op(args)`, a plain event `e`, or `e.v`."""
        target = c[0]
        span = self._span(c)
        if isinstance(target, ast.Call):
            return ast.CallStmt(target, span=span)
        if isinstance(target, ast.Name) and not target.qualified:
            comm = ast.Communication(target.last, span=span, event_span=target.span)
            return ast.Communicate(comm, False, span=span)
        if isinstance(target, ast.Field) and isinstance(target.obj, ast.Name) and not target.obj.qualified:
            value = ast.Name((target.field,), span=target.field_span)
            comm = ast.Communication(target.obj.last, ".", value=value, span=span, event_span=target.obj.span)
            return ast.Communicate(comm, False, span=span)
        self.problems.append(error("this expression is not a statement (expected an assignment, a call or a communication)", span))
        return ast.Skip(span=span)

    def assign(self, c):
        return ast.Assign(c[0], c[1], span=self._span(c))

    def _stmt_comm(self, c, kind):
        target, payload = c
        span = self._span(c)
        if not (isinstance(target, ast.Name) and not target.qualified):
            self.problems.append(error("a communication must name an event", target.span or span))
            return ast.Skip(span=span)
        if kind == "?":
            comm = ast.Communication(target.last, "?", self._name(payload), span=span, event_span=target.span, var_span=self._tspan(payload))
        else:
            comm = ast.Communication(target.last, "!", value=payload, span=span, event_span=target.span)
        return ast.Communicate(comm, False, span=span)

    def comm_input_stmt(self, c):
        return self._stmt_comm(c, "?")

    def comm_output_stmt(self, c):
        return self._stmt_comm(c, "!")
