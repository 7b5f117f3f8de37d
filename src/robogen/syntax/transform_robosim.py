"""Rules of the RoboSim extensions: cycle definitions, input and output contexts, ``$``
statements (outputs, platform calls, shared variables) and ``$`` atoms (inputs)."""

from __future__ import annotations

from robogen.syntax import ast


class RoboSim:
    """Callbacks of the robosim rules (a part of :class:`~robogen.syntax.transform.ToAst`)."""

    def cycle_def(self, c):
        return ast.CycleDef(c[0], span=self._span(c, left=("cycleDef",)))

    def context_kind(self, c):
        return c[0]

    def context(self, c):
        return ast.Context(str(c[0]), tuple(c[1:]), span=self._span(c, right=("}",)) if len(c) > 1 else self._span(c, right=("context", "{", "}")))

    def dollar_stmt(self, c):
        return ast.DollarOutput(self._name(c[0]), "", None, span=self._span(c, left=("$",)), event_span=self._tspan(c[0]))

    def dollar_output(self, c):
        return ast.DollarOutput(self._name(c[0]), "!", c[1], span=self._span(c, left=("$",)), event_span=self._tspan(c[0]))

    def dollar_sync(self, c):
        return ast.DollarOutput(self._name(c[0]), ".", c[1], span=self._span(c, left=("$",)), event_span=self._tspan(c[0]))

    def dollar_call(self, c):
        args = c[1] if len(c) > 1 else ()
        right = (")",) if args else ("(", ")")
        return ast.DollarCall(self._name(c[0]), args, span=self._span(c, left=("$",), right=right), op_span=self._tspan(c[0]))

    def dollar_assign(self, c):
        return ast.DollarAssign(self._name(c[0]), c[1], span=self._span(c, left=("$",)), var_span=self._tspan(c[0]))

    def cycle_atom(self, c):
        return ast.Keyword("cycle", span=self._span(c))

    def dollar(self, c):
        return ast.Dollar(self._name(c[0]), span=self._span(c, left=("$",)), name_span=self._tspan(c[0]))

    def dollar_input(self, c):
        return ast.DollarInput(
            self._name(c[0]),
            self._name(c[1]),
            c[2] if len(c) > 2 else None,
            span=self._span(c, left=("$",)),
            event_span=self._tspan(c[0]),
            var_span=self._tspan(c[1]),
        )

    def dollar_value(self, c):
        return ast.DollarValue(self._name(c[0]), c[1], span=self._span(c, left=("$",)), event_span=self._tspan(c[0]))
