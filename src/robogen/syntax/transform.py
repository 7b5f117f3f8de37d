"""The transformer that turns the LALR parse into :mod:`robogen.syntax.ast` nodes.

It runs inside the parse (Lark calls its callbacks at each reduction, so no parse tree is
built), computes every node's span from the tokens, reports reserved words used as names, and
measures how deeply constructs nest (see :data:`MAX_NESTING`). Only robogen.syntax uses it.

The callbacks are grouped by grammar area, one module each; :class:`ToAst` is their union over
the common foundation (:mod:`robogen.syntax.transform_base`).
"""

from __future__ import annotations

from robogen.syntax.transform_base import MAX_NESTING, SpanBuilder
from robogen.syntax.transform_declarations import Declarations
from robogen.syntax.transform_expressions import Expressions
from robogen.syntax.transform_machines import Machines
from robogen.syntax.transform_obsolete import Obsolete
from robogen.syntax.transform_robosim import RoboSim
from robogen.syntax.transform_statements import Statements


class ToAst(SpanBuilder, Declarations, Machines, Statements, Expressions, RoboSim, Obsolete):
    """Builds AST nodes bottom-up (see :class:`~robogen.syntax.transform_base.SpanBuilder`)."""


def _tracked(method):
    def callback(self, c):
        return self._nest(method(self, c), c)

    callback.__name__ = method.__name__
    return callback


def _chained(method):
    def callback(self, c):
        return self._nest_operand(method(self, c), c[0], c[-1])

    callback.__name__ = method.__name__
    return callback


# The callbacks of binary operators, whose left operand may continue a flat chain (see _nest_operand).
for _callback in ("iff", "implies", "or_", "and_", "compare", "member", "arith"):
    setattr(ToAst, _callback, _chained(getattr(ToAst, _callback)))

# The callbacks of other recursive constructs, whose nodes _nest measures.
for _callback in (
    # types
    "function_type", "relation_type", "product_type", "set_type", "seq_type", "vector_type", "matrix_type", "power_type",
    # states (only nested states count: transitions and actions have no depth entry)
    "state",
    # statements (seq and paren keep their own accounts)
    "stmt_deadline", "if_stmt", "assign", "bare_stmt", "comm_input_stmt", "comm_output_stmt", "comm_sync_stmt", "send", "filtered_stmt", "wait",
    "dollar_output", "dollar_sync", "dollar_call", "dollar_assign",
    # expressions
    "binder", "decl", "such_that", "not_", "the", "let", "let_def", "if_expr", "cast", "neg", "field", "index", "call", "range_oo", "range_oc", "range_cc", "range_co", "seq_lit", "set_lit",
    "set_range", "set_comprehension", "set_body", "tuple_lit", "record_lit", "field_value", "vector_lit", "inverse",
    "transpose", "dollar_input", "dollar_value", "dollar_index", "dollar_apply", "communication",
):
    setattr(ToAst, _callback, _tracked(getattr(ToAst, _callback)))
del _callback


__all__ = ["ToAst", "MAX_NESTING"]
