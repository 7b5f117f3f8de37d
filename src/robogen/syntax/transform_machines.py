"""Rules of state-machine bodies: nodes, states and their actions, transitions and their
clauses, and the communications of triggers."""

from __future__ import annotations

from robogen.syntax import ast
from robogen.syntax.transform_base import Clause, first_child, pos, span_pos


class Machines:
    """Callbacks of the machines rules (a part of :class:`~robogen.syntax.transform.ToAst`)."""

    def _node(self, cls, c, keyword: str):
        return cls(self._name(c[0]), span=self._span(c, left=(keyword,)), name_span=self._tspan(c[0]))

    def initial(self, c):
        return self._node(ast.Initial, c, "initial")

    def junction(self, c):
        return self._node(ast.Junction, c, "junction")

    def final(self, c):
        return self._node(ast.Final, c, "final")

    def probabilistic(self, c):
        return self._node(ast.Probabilistic, c, "probabilistic")

    def state(self, c):
        return self._container(ast.State, c, ("state",))

    @first_child
    def action_kind(self, c):
        return c[0]

    def state_action(self, c):
        return ast.StateAction(str(c[0]), c[1], span=self._span(c))

    def transition(self, c):
        name, source, target = c[0], c[1], c[2]
        clauses: dict = {}  # keyed by the Transition field each clause sets
        resets = []
        for x in c[3:]:
            if type(x) is Clause:
                clauses[x.key] = x.value
            elif isinstance(x, ast.ClockReset):
                resets.append(x)
        return ast.Transition(
            self._name(name),
            self._name(source),
            self._name(target),
            resets=tuple(resets),
            span=self._span(c, left=("transition",), right=("}",)),
            name_span=self._tspan(name),
            source_span=self._tspan(source),
            target_span=self._tspan(target),
            **clauses,
        )

    def trigger(self, c):
        return Clause("trigger", c[0], pos(c[0]))

    def exec_trigger(self, c):
        return Clause("exec", True, pos(c[0]))

    def probability(self, c):
        return Clause("probability", c[0], pos(c[0]))

    def reset(self, c):
        return ast.ClockReset(self._name(c[0]), span=self._span(c, left=("#",)), clock_span=self._tspan(c[0]))

    def deadline(self, c):
        return Clause("deadline", c[0], span_pos(self._span(c, left=("<{",), right=("}",))))

    def condition(self, c):
        return Clause("condition", c[0], pos(c[0]))

    def condition_else(self, c):
        return Clause("condition_else", True, pos(c[0]))

    def action(self, c):
        return Clause("action", c[0], pos(c[0]))

    def communication(self, c):
        event = c[0]
        filt = None
        suffix = None
        for x in c[1:]:
            if isinstance(x, ast.Filter):
                filt = x
            else:
                suffix = x
        kind, var, value, var_span, qualifier = "", None, None, None, ()
        if suffix is not None:
            kind, payload = suffix
            if kind == "?":
                var, qualifier, var_span = payload.last, payload.parts[:-1], payload.span
            else:
                value = payload
        if filt is not None and filt.span is None:  # [||] has no child to take a position from
            filt = self._empty_filter(event)
        parts = [event] + ([filt] if filt else []) + ([suffix[1]] if suffix else [])
        return ast.Communication(
            self._name(event), kind, var, value, filt, qualifier, span=self._span(parts), event_span=self._tspan(event), var_span=var_span
        )

    def _empty_filter(self, event) -> ast.Filter:
        """The filter ``[||]`` after ``event``, with the span of its two tokens."""
        start = self.text.index("[|", event.end_pos)
        end = self.text.index("|]", start + 2) + 2
        return ast.Filter(None, None, None, span=self._make(start, end))

    def comm_input(self, c):
        return ("?", c[0])

    def comm_output(self, c):
        return ("!", c[0])

    def comm_sync(self, c):
        return (".", c[0])

    def filter_bind(self, c):
        return ast.Filter(self._name(c[0]), c[1], c[2] if len(c) > 2 else None, span=self._span(c, left=("[|",), right=("|]",)))

    def filter_empty(self, c):
        return ast.Filter(None, None, None)

    def filter_pred(self, c):
        return ast.Filter(None, None, c[0], span=self._span(c, left=("[|",), right=("|]",)))
