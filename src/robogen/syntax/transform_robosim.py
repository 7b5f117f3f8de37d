"""Rules of the RoboSim extensions: cycle definitions, input and output contexts, ``$``
statements (outputs, platform calls, shared variables) and ``$`` expressions (inputs and
variables). A name after ``$`` may be qualified: the node keeps its simple name and, apart,
the parts written before it."""

from __future__ import annotations

from robogen.syntax import ast
from robogen.syntax.transform_base import first_child


def _split(name: ast.Name) -> tuple[str, tuple[str, ...]]:
    """(simple name, qualifier) of a possibly qualified name."""
    return name.last, name.parts[:-1]


class RoboSim:
    """Callbacks of the robosim rules (a part of :class:`~robogen.syntax.transform.ToAst`)."""

    def cycle_def(self, c):
        return ast.CycleDef(c[0], span=self._span(c, left=("cycleDef",)))

    @first_child
    def context_kind(self, c):
        return c[0]

    def context(self, c):
        return ast.Context(str(c[0]), tuple(c[1:]), span=self._span(c, right=("}",)) if len(c) > 1 else self._span(c, right=("context", "{", "}")))

    def _output(self, c, kind: str):
        name, qualifier = _split(c[0])
        value = c[1] if len(c) > 1 else None
        return ast.DollarOutput(name, kind, value, qualifier, span=self._span(c, left=("$",)), event_span=c[0].span)

    def dollar_stmt(self, c):
        return self._output(c, "")

    def dollar_output(self, c):
        return self._output(c, "!")

    def dollar_sync(self, c):
        return self._output(c, ".")

    def dollar_call(self, c):
        args = c[1] if len(c) > 1 else ()
        right = (")",) if args else ("(", ")")
        name, qualifier = _split(c[0])
        return ast.DollarCall(name, args, qualifier, span=self._span(c, left=("$",), right=right), op_span=c[0].span)

    def dollar_assign(self, c):
        name, qualifier = _split(c[0])
        return ast.DollarAssign(name, c[1], qualifier, span=self._span(c, left=("$",)), var_span=c[0].span)

    def cycle_atom(self, c):
        return ast.Keyword("cycle", span=self._span(c))

    def dollar(self, c):
        name, qualifier = _split(c[0])
        return ast.Dollar(name, qualifier, span=self._span(c, left=("$",)), name_span=c[0].span)

    def dollar_index(self, c):
        """`$x[i]`: an element of a variable read with `$`."""
        return ast.Index(self.dollar(c[:1]), c[1], span=self._span(c, left=("$",), right=("]",)))

    def dollar_apply(self, c):
        """`$f(a)` in an expression: a call of what `$f` denotes."""
        args = c[1] if len(c) > 1 else ()
        return ast.Call(self.dollar(c[:1]), args, span=self._span(c, left=("$",), right=(")",) if args else ("(", ")")))

    def dollar_input(self, c):
        event, qualifier = _split(c[0])
        var, var_qualifier = _split(c[1])
        return ast.DollarInput(
            event, var, c[2] if len(c) > 2 else None, qualifier, var_qualifier,
            span=self._span(c, left=("$",)), event_span=c[0].span, var_span=c[1].span,
        )

    def dollar_value(self, c):
        event, qualifier = _split(c[0])
        return ast.DollarValue(event, c[1], qualifier, span=self._span(c, left=("$",)), event_span=c[0].span)
