"""Forms of RoboTool's older grammars, which models written before a change of the language
still use (found in the history of RoboChart.xtext and RoboSim.xtext):

- RoboChart before 2020-11 wrote the empty trigger as a bare ``trigger``, alone or before clock
  resets (``trigger #C``): read as no trigger;
- RoboChart from 2020-02-10 to 2020-02-24 wrote ``vector(T, n)`` as ``T^n``: read as the vector;
- RoboSim before 2021-08 wrote ``send $e!v``: read as ``$e!v``;
- RoboSim before 2019-07 declared ``const cycle: T`` in a machine, controller or module: ``cycle``
  is implicit now, the declaration is dropped.

Each is read as its current form with a warning that names that form (kept in the file's
``notices``, as the checker reports the obsolete forms of ``cycleDef``). Two forms have no
current form: the time binding ``@ t`` of a trigger (RoboChart before 2020-11) and the start
deadline ``{d}>`` of a trigger or statement (before 2020-10) stay syntax errors, whose message
says so (robogen.syntax.parser).
"""

from __future__ import annotations

from robogen.diagnostics import Note, warning
from robogen.syntax import ast
from robogen.syntax.transform_base import Clause, Positioned, pos, span_pos


class Dropped(Positioned):
    """A member an obsolete form declares that the current language has no place for (the
    containers leave it out)."""

    __slots__ = ()

    def __init__(self, at):
        self.pos = at


class Obsolete:
    """Callbacks of the obsolete forms (a part of :class:`~robogen.syntax.transform.ToAst`)."""

    def _obsolete(self, what: str, span, current: str) -> None:
        self.notices.append(warning(f"obsolete syntax: {what}", span, Note(current)))

    def empty_trigger(self, c):
        self._obsolete("a bare 'trigger' (RoboTool's empty trigger, before its grammar of 2020-11) is read as no trigger",
                       self._tspan(c[0]), "write the transition without the word 'trigger' (clock resets follow 'to')")
        return Clause("trigger", None, pos(c[0]))

    def power_type(self, c):
        element, size = c[0], c[1]
        span = self._span(c)
        n = ast.IntLit(int(size), span=self._tspan(size))
        self._obsolete(f"the vector type '{self.text[span.offset:span.end_offset]}' (RoboTool's grammar of 2020-02) is "
                       "read as a vector", span, f"write 'vector({self.text[element.span.offset:element.span.end_offset]}, {size})'")
        return ast.VectorType(element, n, span=span)

    def const_cycle(self, c):
        span = self._span(c, left=("const",))
        self._obsolete("'const cycle' (RoboSim before 2019-07) is dropped: 'cycle' is implicit", span,
                       "remove the declaration; 'cycleDef cycle == p' defines the period")
        return Dropped(span_pos(span))

    def _send_dollar(self, c, kind: str):  # `send $e`, `send $e!v`, `send $e.v`
        node = self._output(c[1:], kind)  # type: ignore[attr-defined]
        written = self.text[node.span.offset:node.span.end_offset]
        self._obsolete("'send' before a RoboSim output (before RoboTool's grammar of 2021-08) is ignored", self._tspan(c[0]),
                       f"write '{written}' without 'send'")
        return node

    def send_dollar_output(self, c):
        return self._send_dollar(c, "!" if len(c) > 2 else "")

    def send_dollar_sync(self, c):
        return self._send_dollar(c, ".")


__all__ = ["Obsolete", "Dropped"]
