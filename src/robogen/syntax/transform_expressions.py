"""Rules of expressions: logic and arithmetic, quantifiers, let, casts, literals and collections,
records, vectors and matrices, ranges, clocks' ``since`` and ``sinceEntry``."""

from __future__ import annotations

import dataclasses
import re

from robogen.syntax import ast
from robogen.syntax.transform_base import Body, SuchThat, first_child


class Expressions:
    """Callbacks of the expressions rules (a part of :class:`~robogen.syntax.transform.ToAst`)."""

    @first_child
    def binder_kind(self, c):
        return c[0]

    def binder(self, c):
        kind, decls = c[0], c[1]
        such_that = c[2].expr if len(c) == 4 else None
        return ast.Binder(str(kind), decls, such_that, c[-1], span=self._span(c))

    def decls(self, c):
        return tuple(c)

    def decl(self, c):
        return ast.Decl(self._name(c[0]), c[1], span=self._span(c), name_span=self._tspan(c[0]))

    def such_that(self, c):
        return SuchThat(c[0])

    def _binary(self, op, c):
        return ast.Binary(op, c[0], c[-1], span=self._span(c))

    def iff(self, c):
        return self._binary("iff", c)

    def implies(self, c):
        return self._binary("=>", c)

    def or_(self, c):
        return self._binary("\\/", c)

    def and_(self, c):
        return self._binary("/\\", c)

    def not_(self, c):
        return ast.Unary("not", c[0], span=self._span(c, left=("not",)))

    @first_child
    def cmp_op(self, c):
        return c[0]

    def compare(self, c):
        return ast.Binary(str(c[1]), c[0], c[2], span=self._span(c))

    def member(self, c):
        return self._binary("in", c)

    def the(self, c):
        decls = c[0]
        such_that = c[1].expr if len(c) == 3 else None
        return ast.Binder("the", decls, such_that, c[-1], span=self._span(c, left=("the",)))

    def let(self, c):
        return ast.Let(tuple(c[:-1]), c[-1], span=self._span(c, left=("let",)))

    def let_def(self, c):
        return ast.LetDef(self._name(c[0]), c[1], span=self._span(c), name_span=self._tspan(c[0]))

    def if_expr(self, c):
        return ast.IfExpr(c[0], c[1], c[2], span=self._span(c, left=("if",), right=("end",)))

    @first_child
    def cast_op(self, c):
        return c[0]

    def cast(self, c):
        return ast.Cast(str(c[1]), c[0], c[2], span=self._span(c))

    add_op = mul_op = cat_op = cast_op

    def arith(self, c):
        return ast.Binary(str(c[1]), c[0], c[2], span=self._span(c))

    def neg(self, c):
        return ast.Unary("-", c[0], span=self._span(c, left=("-",)))

    def field(self, c):
        return ast.Field(c[0], self._name(c[1]), span=self._span(c), field_span=self._tspan(c[1]))

    def index(self, c):
        return ast.Index(c[0], c[1], span=self._span(c, right=("]",)))

    def call(self, c):
        args = c[1] if len(c) > 1 else ()
        return ast.Call(c[0], args, span=self._span(c, right=(")",) if args else ("(", ")")))

    def args(self, c):
        return tuple(c)

    def int_lit(self, c):
        return ast.IntLit(int(c[0]), span=self._span(c))

    def real_lit(self, c):
        return ast.RealLit(str(c[0]), span=self._span(c))

    def string_lit(self, c):
        raw = str(c[0])[1:-1]
        return ast.StringLit(re.sub(r"\\(.)", r"\1", raw), span=self._span(c))

    def true_lit(self, c):
        return ast.BoolLit(True, span=self._span(c))

    def false_lit(self, c):
        return ast.BoolLit(False, span=self._span(c))

    @first_child
    def name(self, c):
        return c[0]  # a qname already built as ast.Name

    def result(self, c):
        return ast.Keyword("result", span=self._span(c))

    def from_atom(self, c):
        return ast.Keyword("from", span=self._span(c))

    def to_atom(self, c):
        return ast.Keyword("to", span=self._span(c))

    def _range(self, c, low_closed, high_closed):
        return ast.Range(
            c[0], c[1], low_closed, high_closed,
            span=self._span(c, left=("[" if low_closed else "(",), right=("]" if high_closed else ")",)),
        )

    def range_oo(self, c):
        return self._range(c, False, False)

    def range_oc(self, c):
        return self._range(c, False, True)

    def range_cc(self, c):
        return self._range(c, True, True)

    def range_co(self, c):
        return self._range(c, True, False)

    def since(self, c):
        return ast.Since(self._name(c[0]), span=self._span(c, left=("since", "("), right=(")",)), clock_span=self._tspan(c[0]))

    def since_entry(self, c):
        return ast.SinceEntry(c[0], span=self._span(c, left=("sinceEntry", "("), right=(")",)))

    def seq_lit(self, c):
        items = c[0] if len(c) > 1 else ()
        return ast.SeqLit(items, span=self._span(c, left=("<",)))

    def paren(self, c):
        """`( e )`, `( S )` or `( T )`: the node inside, its span widened over the parentheses (a
        level of nesting, and the end of a flat chain of operators)."""
        node = c[0]
        span = self._span(c, left=("(",), right=(")",))
        if span is None or node.span is None:
            return node
        return self._record(dataclasses.replace(node, span=span), self._depth.get(id(node), 0) + 1, c)

    def seq_items(self, c):
        return tuple(c)

    def set_empty(self, c):
        return ast.SetLit((), span=self._span(c, left=("{",)))

    def set_lit(self, c):
        return ast.SetLit(tuple(c), span=self._span(c, left=("{",), right=("}",)))

    def set_range(self, c):
        return ast.SetRange(c[0], c[1], span=self._span(c, left=("{",), right=("}",)))

    def set_comprehension(self, c):
        decls = c[0]
        such_that = next((x.expr for x in c[1:] if isinstance(x, SuchThat)), None)
        body = next((x.expr for x in c[1:] if isinstance(x, Body)), None)
        return ast.SetComprehension(decls, such_that, body, span=self._span(c, left=("{",), right=("}",)))

    def set_body(self, c):
        return Body(c[0])

    def tuple_lit(self, c):
        return ast.TupleLit(tuple(c), span=self._span(c, left=("(|",), right=("|)",)))

    def tuple_empty(self, c):
        return ast.TupleLit((), span=self._span(c, left=("(|",)))

    def record_lit(self, c):
        return ast.RecordLit(c[0], tuple(c[1:]), span=self._span(c, right=("|)",)))

    def field_value(self, c):
        return ast.FieldValue(self._name(c[0]), c[1], span=self._span(c), name_span=self._tspan(c[0]))

    def vector_lit(self, c):
        return ast.VectorLit(c[0], span=self._span(c, left=("[|",), right=("|]",)))

    def matrix_rows(self, c):
        return tuple(c)

    def matrix_row(self, c):
        return tuple(c)

    def inverse(self, c):
        return ast.MatrixOp("inverse", c[0], span=self._span(c, left=("inverse", "("), right=(")",)))

    def transpose(self, c):
        return ast.MatrixOp("transpose", c[0], span=self._span(c, left=("transpose", "("), right=(")",)))
