"""Lowering of expressions: checked AST expressions become typed IR expressions.

Numeric operands get explicit conversions (``Conv``) to the type of the operation, so the C
emitter and the interpreter never infer types. One step per expression form (``_e_<Form>``);
a form without a step has no code-generation meaning yet and is reported as not supported.
"""

from __future__ import annotations

from dataclasses import replace
from fractions import Fraction
from typing import TYPE_CHECKING

from robogen.diagnostics import RobogenError, Span, working_on
from robogen.ir import linear
from robogen.ir import model as ir
from robogen.ir.collections import RELATION_OPS
from robogen.ir.constants import default_expr
from robogen.ir.derived import FUNCTIONAL, RELATIONAL, identity
from robogen.ir.region_tree import Graph
from robogen.ir.supported import (FunMapT, TaggedT, TupleT, base_name, check_codegen_type, convertible, fits, is_collection,
                                  is_scalar, not_supported, tuple_type)
from robogen.semantics import types as T
from robogen.semantics.model import EnumLitSym, EventSym, FuncSym, VarSym
from robogen.syntax import ast
from robogen.syntax.printer import expr as expr_text

if TYPE_CHECKING:  # the attributes MachineLowering provides
    from robogen.semantics.model import SemanticModel


def _unknown_inside(t: T.Type) -> bool:
    """Does ``t`` hold the type of elements nothing gave a type (``{}``, ``<>``, a toolkit result's
    ``?Y`` that such an argument leaves open)?"""
    if isinstance(t, (T.UnknownT, T.TypeVarT)):
        return True
    if isinstance(t, (T.SetT, T.SeqT)):
        return _unknown_inside(t.element)
    if isinstance(t, T.ProductT):
        return any(_unknown_inside(x) for x in t.items)
    return False


# collection operations whose result holds elements of their collection arguments (of one type;
# extract's second argument holds positions)
_ELEMENTWISE = ("union", "inter", "diff", "symdiff", "cat", "reverse", "tail", "front", "filter", "elems", "extract")

# relation operations whose result is empty when their relation is ({} nothing types), or, for
# override({}, s), the other relation (not iter(0, {}), the identity)
_EMPTY_IN_EMPTY_OUT = ("dom", "ran", "rinv", "dres", "dsub", "rres", "rsub", "rimage", "relcomp", "squash", "closure", "roverride")

# relation operations whose result holds pairs of its relation argument (rinv: swapped); the
# others' results are sets of the pairs' fields (dom, ran, rimage) or pairs of two relations (relcomp)
_SAME_PAIRS = ("dres", "dsub", "rres", "rsub", "roverride", "closure", "rinv")

_BINARY = {
    "iff": "iff", "=>": "implies", "\\/": "or", "/\\": "and",
    "==": "eq", "!=": "ne", "<": "lt", "<=": "le", ">": "gt", ">=": "ge",
    "+": "add", "-": "sub", "*": "mul", "/": "div", "%": "mod",
}


_KINDS = ("value", "pair", "set", "seq")  # the forms of arguments (a set or sequence may hold anything)

# toolkit functions code generation implements: (name, the forms of the arguments) -> operation
# of robogen.ir.collections (first, second and maplet are tuple operations)
TOOLKIT: dict[str, dict[tuple[str, tuple[str, ...]], str]] = {
    "set_toolkit": {
        **{("notin", (a, "set")): "notin" for a in _KINDS},
        ("subseteq", ("set", "set")): "subseteq", ("subset", ("set", "set")): "subset",
        ("union", ("set", "set")): "union", ("inter", ("set", "set")): "inter", ("diff", ("set", "set")): "diff",
        ("symetric_diff", ("set", "set")): "symdiff", ("Union", ("set",)): "Union", ("Inter", ("set",)): "Inter",
    },
    "relation_toolkit": {
        ("first", ("pair",)): "first", ("second", ("pair",)): "second",
        **{("maplet", (a, b)): "maplet" for a in _KINDS for b in _KINDS},
        ("dom", ("seq",)): "indices", ("ran", ("seq",)): "elems",
        # relations: sets of pairs
        ("dom", ("set",)): "dom", ("ran", ("set",)): "ran", ("rinv", ("set",)): "rinv",
        ("dres", ("set", "set")): "dres", ("dsub", ("set", "set")): "dsub", ("rres", ("set", "set")): "rres",
        ("rsub", ("set", "set")): "rsub", ("rimage", ("set", "set")): "rimage", ("override", ("set", "set")): "roverride",
        ("relcomp", ("set", "set")): "relcomp",
    },
    "sequence_toolkit": {
        ("range", ("value", "value")): "range", ("size", ("set",)): "size", ("size", ("seq",)): "size",
        ("hasMin", ("set",)): "nonempty", ("hasMax", ("set",)): "nonempty", ("min", ("set",)): "min",
        ("max", ("set",)): "max", ("isNonEmpty", ("seq",)): "nonempty", ("concat", ("seq", "seq")): "cat",
        ("reverse", ("seq",)): "reverse", ("head", ("seq",)): "head", ("last", ("seq",)): "last",
        ("tail", ("seq",)): "tail", ("front", ("seq",)): "front", ("filter", ("seq", "set")): "filter",
        ("extract", ("set", "seq")): "extract",
        ("dconcat", ("seq",)): "dconcat", ("iter", ("value", "set")): "iter", ("isInjectiveSequence", ("seq",)): "injective",
        ("squash", ("set",)): "squash", ("prefix", ("seq", "seq")): "prefix", ("suffix", ("seq", "seq")): "suffix", ("infix", ("seq", "seq")): "infix",
    },
}


class ExpressionLowering:
    """The expression steps of :class:`~robogen.ir.machines.MachineLowering` (a mixin). It uses
    the machine lowering's ``_norm`` (concrete types), ``_declare_var`` (a shared variable met
    first in a called operation) and ``declared_call`` (a call of a function the model declares)."""

    model: SemanticModel
    machine: ir.Machine
    vars: dict[str, ir.Var]
    period: Fraction  # the FMU's cycle period (RoboChart: 1)

    # -- entry points

    def expr(self, e: ast.Expr, graph: Graph) -> ir.Expr:
        with working_on(e.span):
            step = getattr(self, "_e_" + type(e).__name__, None)
            if step is None:
                raise not_supported(type(e).__name__, e.span)
            return step(e, graph)

    def lvalue(self, e: ast.Expr, graph: Graph) -> ir.Expr:
        if isinstance(e, ast.Name):
            return self.var_ref(graph, self.model.symbol(e), e.span)
        if isinstance(e, ast.Field):
            base = self.lvalue(e.obj, graph)
            assert isinstance(base.type, T.RecordT)
            return ir.FieldOf(base.type.field(e.field), base, e.field)  # type: ignore[arg-type]
        if isinstance(e, ast.Index):
            return self._index(self.lvalue(e.obj, graph), e, graph)
        raise not_supported("this assignment target", e.span)

    def var_ref(self, graph: Graph, sym, span: Span | None) -> ir.Expr:
        if isinstance(sym, VarSym) and sym.kind == "binder" and id(sym.decl) in self.bound:  # type: ignore[attr-defined]
            return self.bound[id(sym.decl)]  # type: ignore[attr-defined]  # a lambda's parameter, applied
        if not isinstance(sym, VarSym):
            raise not_supported("this variable reference", span)
        var = graph.env.get(sym.name) or self.vars.get(sym.name)
        if var is None and ((sym.shared and sym.kind == "var") or sym.kind == "const"):
            # a variable the controller provides, or a constant an operation requires, used by
            # an operation the machine calls: the machine's (a constant: an FMU parameter)
            var = self._declare_var(sym, sym.name)
        if var is None:
            raise not_supported(f"variable '{sym.name}' here", span)
        return ir.Ref(var.type, var)

    def conv(self, e: ir.Expr, t: T.Type | None, span: Span | None) -> ir.Expr:
        """``e`` as a value of type ``t``: numbers converted, literals retyped."""
        if t is None or e.type == t:
            return e
        if e.type in T.NUMERIC and t in T.NUMERIC:
            if isinstance(e, ir.Lit) and not isinstance(e.value, bool):
                value = e.value
                if t == T.REAL:
                    return ir.Lit(T.REAL, Fraction(value))  # type: ignore[arg-type]
                if isinstance(value, int) or (isinstance(value, Fraction) and value.denominator == 1):
                    return ir.Lit(t, int(value))  # type: ignore[arg-type]
            return ir.Conv(t, e)
        if isinstance(t, (T.VectorT, T.MatrixT)) and isinstance(e, ir.VectorLit):
            return ir.VectorLit(t, tuple(self.conv(x, t.element, span) for x in e.items))
        if isinstance(t, (T.VectorT, T.MatrixT)) and type(e.type) is type(t) and e.type.element != t.element:  # type: ignore[attr-defined]
            return self._conv_linear(e, t, span)
        if isinstance(t, T.RecordT) and isinstance(e.type, T.RecordT) and t.qname != e.type.qname \
                and base_name(t.qname) == base_name(e.type.qname):
            return self._reshape(e, t, span)  # a recursive type at another level (robogen.ir.supported.Shapes)
        if isinstance(t, T.RecordT) and isinstance(e, ir.RecordLit):
            return ir.RecordLit(t, tuple((n, self.conv(v, t.field(n), span)) for n, v in e.values))
        if isinstance(e.type, FunMapT) and isinstance(t, T.SetT) and convertible(e.type.pairs, t):  # a function as its pairs
            return self.conv(self.pairs_of(e, "this function", span), t, span)  # type: ignore[attr-defined]
        if isinstance(t, FunMapT) and isinstance(e.type, T.SetT):  # a set of pairs as a function
            return self.map_of_pairs(self.conv(e, t.pairs, span), t)  # type: ignore[attr-defined]
        if is_collection(t) and is_collection(e.type) and isinstance(t, T.SetT) == isinstance(e.type, T.SetT):
            return self._conv_collection(e, t, span)  # type: ignore[arg-type]
        if isinstance(t, (T.RecordT, T.VectorT, T.MatrixT)) and not isinstance(e, ir.VectorLit) and convertible(e.type, t):
            return ir.Coll(t, "conv", (e,), self._conv_text(e.type, t), span)  # collections of other capacities inside
        if isinstance(t, T.RecordT) and isinstance(e.type, T.RecordT) and e.type != t and isinstance(e, ir.Cond):
            return ir.Cond(t, e.cond, self.conv(e.then, t, span), self.conv(e.otherwise, t, span))
        if isinstance(t, T.RecordT) and isinstance(e.type, T.RecordT) and e.type != t and \
                [n for n, _ in t.fields] == [n for n, _ in e.type.fields]:  # a tuple of nats as one of ints: field by field
            return ir.RecordLit(t, tuple((n, self.conv(ir.FieldOf(e.type.field(n), e, n), ft, span)) for n, ft in t.fields))  # type: ignore[arg-type]
        return e

    def _conv_linear(self, e: ir.Expr, t: T.VectorT | T.MatrixT, span: Span | None) -> ir.Expr:
        """A vector or matrix as one of another number type (`vector(nat, 2)` used as a
        `vector(int, 2)`): the branches of a conditional converted, else each element."""
        if isinstance(e, ir.Cond):
            return ir.Cond(t, e.cond, self.conv(e.then, t, span), self.conv(e.otherwise, t, span))
        if isinstance(t, T.VectorT):
            places = [(ir.Lit(T.INT, i + 1),) for i in range(t.size or 0)]
        else:
            places = [(ir.Lit(T.INT, r + 1), ir.Lit(T.INT, c + 1)) for r in range(t.rows or 0) for c in range(t.columns or 0)]
        source = e.type.element  # type: ignore[attr-defined]
        return ir.VectorLit(t, tuple(self.conv(ir.IndexOf(source, e, at), t.element, span) for at in places))

    def converted(self, e: ir.Expr, t: T.Type, span: Span | None) -> ir.Expr | None:
        """``e`` as a value of ``t``, or None when it cannot be one."""
        try:
            value = self.conv(e, t, span)
        except RobogenError:
            return None
        return value if value.type == t else None

    def _reshape(self, e: ir.Expr, t: T.RecordT, span: Span | None) -> ir.Expr:
        """A value of a recursive type as one of another level: field by field; a field ``t``
        lacks is a literal's argument with no room at its last level, so a value of that literal
        is deeper than the bound: a run-time error."""
        source = e.type
        assert isinstance(source, T.RecordT)
        given = dict(e.values) if isinstance(e, ir.RecordLit) else {}

        def part(n: str) -> ir.Expr:
            return given[n] if n in given else ir.FieldOf(source.field(n), e, n)  # type: ignore[arg-type]

        value: ir.Expr = ir.RecordLit(t, tuple((n, self.conv(part(n), ft, span) if source.field(n) is not None
                                                else default_expr(ft, span)) for n, ft in t.fields))
        if not isinstance(t, TaggedT):
            return value
        lost = sorted({t.tag.literals.index(n.rsplit("_", 1)[0]) for n, _ in source.fields if t.field(n) is None})
        tag = part("tag")
        if isinstance(tag, ir.Lit):  # a literal: known here
            lost = [k for k in lost if k == tag.value]
        if not lost:
            return value
        deep = ir.Bin(T.BOOLEAN, "eq", tag, ir.Lit(t.tag, lost[0]))
        for k in lost[1:]:
            deep = ir.Bin(T.BOOLEAN, "or", deep, ir.Bin(T.BOOLEAN, "eq", tag, ir.Lit(t.tag, k)))
        fault = ir.Coll(t, "undefined", (), f"a value of {base_name(t.qname)} nested deeper than the depth bound "
                        f"{self.ctx.shapes.depth} (--enum-depth)", span)  # type: ignore[attr-defined]
        return ir.Cond(t, deep, fault, value)

    def _conv_collection(self, e: ir.Expr, t: T.SetT | T.SeqT, span: Span | None) -> ir.Expr:
        """A set or sequence as one of another element type or capacity: an enumeration's
        elements are converted (``{}`` takes the type it is used as); another value element by
        element (a set re-ordered), a run-time error if it holds more than ``t``'s capacity."""
        if isinstance(e, ir.Coll) and e.op in ("set", "seq"):
            return ir.Coll(t, e.op, tuple(self.conv(x, t.element, span) for x in e.args), e.text, e.span)
        if isinstance(e, ir.Coll) and e.op == "identity":  # id(): the identity relation of the type it is used as
            return identity(t, "id", e.text, e.span)
        source = e.type.element  # type: ignore[attr-defined]
        if isinstance(source, T.UnknownT):
            return e
        if convertible(e.type, t):
            return ir.Coll(t, "conv", (e,), self._conv_text(e.type, t), span)
        # a value built from enumerations (`if c then {} else {} end`, `union({}, {})`, whose
        # elements nothing typed): built from the enumerations as the type it is used as
        if isinstance(e, ir.Cond):
            return ir.Cond(t, e.cond, self.conv(e.then, t, span), self.conv(e.otherwise, t, span))
        if isinstance(e, ir.Quant) and e.kind == "set" and isinstance(e.body, ir.Coll) and e.body.op in ("set", "seq") \
                and not e.body.args:  # {x: T | p @ <>}: a set of one empty collection, of the type it is used as
            return replace(e, type=t, body=self.conv(e.body, t.element, span))
        if isinstance(e, ir.Coll) and e.op in _ELEMENTWISE:
            args = tuple(self.conv(a, replace(a.type, element=t.element), span) if is_collection(a.type)  # type: ignore[union-attr]
                         and a.type.element == source and (e.op != "extract" or k == 0) else a  # type: ignore[attr-defined]
                         for k, a in enumerate(e.args))
            return ir.Coll(t, e.op, args, e.text, e.span)
        if isinstance(e, ir.Coll) and e.op in ("dconcat", "Union", "Inter") and is_collection(e.args[0].type) \
                and is_collection(e.args[0].type.element) and e.args[0].type.element.element == source:  # type: ignore[attr-defined]
            outer = e.args[0].type  # of the collections whose elements make the result: each of them converted
            inner = replace(outer.element, element=t.element)  # type: ignore[attr-defined]
            return ir.Coll(t, e.op, (self.conv(e.args[0], replace(outer, element=inner), span),), e.text, e.span)
        raise not_supported(f"using a {e.type.show()} as a {t.show()}", span)

    @staticmethod
    def _conv_text(source: T.Type, target: T.Type) -> str:
        """What a conversion's run-time error calls it."""
        if source.show() != target.show():
            return f"{source.show()} as {target.show()}"
        return f"a {source.show()} stored at a nesting level of another capacity"

    def common(self, a: ir.Expr, b: ir.Expr, spans) -> tuple[ir.Expr, ir.Expr]:
        """``a`` and ``b`` (collections of one form whose capacities may differ) in one type, the
        one into which the other converts without overflowing (equality, membership)."""
        of = self.ctx.fmu.capacity_of  # type: ignore[attr-defined]
        if a.type == b.type:
            return a, b
        if fits(b.type, a.type, of):
            return a, self.conv(b, a.type, spans[1])
        return self.conv(a, b.type, spans[0]), b

    def since_type(self) -> T.Type:
        """The type of clock readings: nat when the period is whole, real otherwise."""
        return T.NAT if self.period.denominator == 1 else T.REAL

    def later(self, elapsed: ir.Expr, bound: ir.Expr, span: Span | None) -> ir.Expr:
        """elapsed > bound, compared as reals if the bound is real, else as integers."""
        t = T.REAL if bound.type == T.REAL else T.INT
        return ir.Bin(T.BOOLEAN, "gt", self.conv(elapsed, t, span), self.conv(bound, t, span))

    def _type(self, e: ast.Expr) -> T.Type:
        return self._norm(self.model.type_of(e))

    # -- atoms

    def _e_IntLit(self, e: ast.IntLit, graph: Graph) -> ir.Expr:
        return ir.Lit(T.NAT, e.value)

    def _e_RealLit(self, e: ast.RealLit, graph: Graph) -> ir.Expr:
        return ir.Lit(T.REAL, Fraction(e.text))

    def _e_StringLit(self, e: ast.StringLit, graph: Graph) -> ir.Expr:
        return ir.Lit(T.STRING, e.value)

    def _e_BoolLit(self, e: ast.BoolLit, graph: Graph) -> ir.Expr:
        return ir.Lit(T.BOOLEAN, e.value)

    def _e_Name(self, e: ast.Name, graph: Graph) -> ir.Expr:
        sym = self.model.symbol(e)
        if isinstance(sym, EnumLitSym):
            return self._literal(sym, (), e.span)
        if self._atom(e) is not None:  # type: ignore[attr-defined]  # a named function or let-bound lambda, as a value
            return self.fvalue(e, self._type(e), graph)  # type: ignore[attr-defined]
        if isinstance(sym, FuncSym) and sym.builtin is None and sym.decl is not None and not sym.params:
            return self.declared_call(sym, [], e, graph)  # type: ignore[attr-defined]  # stands for its result
        if isinstance(sym, VarSym):
            value = self.bound_value(sym, e.span)  # type: ignore[attr-defined]  # a let name, lambda parameter...
            if value is not None:
                return value
        return self.var_ref(graph, sym, e.span)

    def _e_Keyword(self, e: ast.Keyword, graph: Graph) -> ir.Expr:
        if e.word == "cycle":
            return ir.Lit(T.REAL, self.period)
        raise not_supported(f"'{e.word}'", e.span)

    def _e_Since(self, e: ast.Since, graph: Graph) -> ir.Expr:
        clock = graph.clocks.get(e.clock)
        if clock is None:
            raise not_supported(f"clock '{e.clock}' here", e.span)
        return ir.Since(self.since_type(), clock)

    def _e_SinceEntry(self, e: ast.SinceEntry, graph: Graph) -> ir.Expr:
        found = self.model.symbol(e)
        if found is None:
            raise not_supported("sinceEntry here", e.span)
        _, node = found
        nid = graph.node_ids.get(id(node))
        if nid is None:
            raise not_supported("sinceEntry of a state outside this machine", e.span)
        return ir.SinceEntry(self.since_type(), nid)

    # -- operators

    def _e_Unary(self, e: ast.Unary, graph: Graph) -> ir.Expr:
        operand = self.expr(e.operand, graph)
        if e.op == "not":
            return ir.Un(T.BOOLEAN, "not", operand)
        t = self._type(e)
        if isinstance(t, (T.VectorT, T.MatrixT)):
            return linear.negate(operand, t, self.conv, e.span)
        return ir.Un(t, "neg", self.conv(operand, t, e.span))

    def _e_Binary(self, e: ast.Binary, graph: Graph) -> ir.Expr:
        first, links = ast.chain(e)  # a loop over a flat chain of operands, not recursion
        value = self.expr(first, graph)
        for link in links:
            value = self._binary(link, value, self.expr(link.right, graph))
        return value

    def _binary(self, e: ast.Binary, a: ir.Expr, b: ir.Expr) -> ir.Expr:
        """Binary expression ``e`` on its lowered operands."""
        if e.op in ("in", "^", "cat"):
            return self._collection_binary(e, a, b)
        op = _BINARY.get(e.op)
        if op is None:
            raise not_supported(f"the operator '{e.op}'", e.span)
        if op in ("iff", "implies", "or", "and"):
            return ir.Bin(T.BOOLEAN, op, a, b)
        if op in ("eq", "ne", "lt", "le", "gt", "ge"):
            return self._comparison(e, op, a, b)
        t = self._type(e)
        if op in ("add", "sub", "mul") and any(isinstance(x.type, (T.VectorT, T.MatrixT)) for x in (a, b)):
            return linear.arithmetic(op, a, b, t, self.conv, e.span)
        if t not in T.NUMERIC:
            raise not_supported(f"'{e.op}' on {t.show()}", e.span)
        return ir.Bin(t, op, self.conv(a, t, e.left.span), self.conv(b, t, e.right.span))

    def _collection_binary(self, e: ast.Binary, a: ir.Expr, b: ir.Expr) -> ir.Expr:
        if e.op == "in":
            b = self._as_relation(b, e.right)
            return self.coll(T.BOOLEAN, "in", self.member(a, b, e.left.span, e.right.span), e)
        t = self._known(e, ((e.left, a), (e.right, b)))
        if t == T.STRING:  # two strings: only literals, joined here (a string is a number at run time)
            if isinstance(a, ir.Lit) and isinstance(b, ir.Lit):
                return ir.Lit(T.STRING, str(a.value) + str(b.value))
            raise not_supported("joining strings that are not literals (a string is one of the model's or an importer's "
                                "at run time, never a new one)", e.span)
        return self.coll(t, "cat", (self.conv(a, t, e.left.span), self.conv(b, t, e.right.span)), e)

    def member(self, x: ir.Expr, s: ir.Expr, x_span: Span | None, s_span: Span | None) -> tuple[ir.Expr, ir.Expr]:
        """The operands of ``x in s``: ``x`` as an element of ``s``, or, where it might not fit
        (a collection of a greater capacity than the elements'), ``s`` as a collection of its type."""
        assert isinstance(s.type, (T.SetT, T.SeqT))
        if fits(x.type, s.type.element, self.ctx.fmu.capacity_of) or not convertible(x.type, s.type.element):  # type: ignore[attr-defined]
            return self.conv(x, s.type.element, x_span), s
        return x, self.conv(s, replace(s.type, element=x.type), s_span)

    def _comparison(self, e: ast.Binary, op: str, a: ir.Expr, b: ir.Expr) -> ir.Expr:
        known = self.model.constant_comparison(e)  # k >= 0 for a nat k: C compilers reject the test (-Wtype-limits)
        if known is not None:
            return ir.Lit(T.BOOLEAN, known)
        if a.type in T.NUMERIC and b.type in T.NUMERIC:
            t = T.REAL if T.REAL in (a.type, b.type) else (T.NAT if a.type == b.type == T.NAT else T.INT)
            return ir.Bin(T.BOOLEAN, op, self.conv(a, t, e.left.span), self.conv(b, t, e.right.span))
        if op not in ("eq", "ne"):
            raise not_supported(f"'{e.op}' on {a.type.show()}", e.span)
        if not (is_scalar(a.type) or isinstance(a.type, (T.RecordT, T.VectorT, T.MatrixT, T.SetT, T.SeqT)) or a.type == T.STRING):
            raise not_supported(f"comparing values of type {a.type.show()}", e.span)
        if a.type != b.type and isinstance(a.type, (T.SetT, T.SeqT, T.RecordT)) and convertible(a.type, b.type):
            a, b = self.common(a, b, (e.left.span, e.right.span))  # into the one of the greater capacities
        a, b = self._one_type(a, b, e.span)
        return ir.Bin(T.BOOLEAN, op, a, b)

    def _one_type(self, a: ir.Expr, b: ir.Expr, span: Span | None) -> tuple[ir.Expr, ir.Expr]:
        """Two values to compare, of one type: a literal takes the type of the other side
        ([| 0, 0 |] is vector(nat, 2)), the narrower side the wider one's."""
        if a.type == b.type:
            return a, b
        b_as_a = self.converted(b, a.type, span)
        if b_as_a is not None:
            return a, b_as_a
        a_as_b = self.converted(a, b.type, span)
        if a_as_b is not None:
            return a_as_b, b
        raise not_supported(f"comparing a {a.type.show()} with a {b.type.show()}", span)

    def equal(self, a: ir.Expr, b: ir.Expr, span: Span | None = None) -> ir.Expr:
        """a == b, numbers compared in their common type, other values as one type."""
        if a.type in T.NUMERIC and b.type in T.NUMERIC:
            t = T.REAL if T.REAL in (a.type, b.type) else T.INT
            return ir.Bin(T.BOOLEAN, "eq", self.conv(a, t, None), self.conv(b, t, None))
        return ir.Bin(T.BOOLEAN, "eq", *self._one_type(a, b, span))

    def _e_IfExpr(self, e: ast.IfExpr, graph: Graph) -> ir.Expr:
        cond, then, other = self.expr(e.cond, graph), self.expr(e.then, graph), self.expr(e.otherwise, graph)
        t = self._known(e, ((e.then, then), (e.otherwise, other)))
        return ir.Cond(t, cond, self.conv(then, t, e.then.span), self.conv(other, t, e.otherwise.span))

    def _known(self, e: ast.Expr, parts) -> T.Type:
        """The type of ``e``; where the checker left its elements unknown (``if c then <> else
        <true> end``, ``<> ^ <true>``), that of the first of its ``parts`` (ast, lowered) whose
        elements are known."""
        if not _unknown_inside(self.model.type_of(e)):
            return self._type(e)
        known = [x.type for a, x in parts if not _unknown_inside(self.model.type_of(a))]
        return known[0] if known else self._type(e)

    def _e_MatrixOp(self, e: ast.MatrixOp, graph: Graph) -> ir.Expr:
        if e.op != "transpose":
            raise not_supported(f"the {e.op} of a matrix", e.span)
        t = self._type(e)
        assert isinstance(t, T.MatrixT)
        return linear.transpose(self.expr(e.operand, graph), t, self.conv, e.span)

    def _e_Cast(self, e: ast.Cast, graph: Graph) -> ir.Expr:
        t = self._norm(self.model.type_of(e.type))
        if e.op == "as" and isinstance(t, FunMapT):
            return self.fvalue(e.expr, t, graph)  # type: ignore[attr-defined]
        inner = self.expr(e.expr, graph)
        if e.op == "as" and t in T.NUMERIC and inner.type in T.NUMERIC:
            return ir.Conv(t, inner)
        if e.op == "as" and is_collection(t) and self.conv(inner, t, e.span).type == t:  # {} as Set(nat)
            return self.conv(inner, t, e.span)
        raise not_supported(f"'{e.op}' here", e.span)

    # -- data

    def _e_Field(self, e: ast.Field, graph: Graph) -> ir.Expr:
        base = self.expr(e.obj, graph)
        if not isinstance(base.type, T.RecordT):
            raise not_supported(f"field selection on {base.type.show()}", e.span)
        return ir.FieldOf(base.type.field(e.field), base, e.field)  # type: ignore[arg-type]  # (already concrete)

    def _e_Index(self, e: ast.Index, graph: Graph) -> ir.Expr:
        return self._index(self.expr(e.obj, graph), e, graph)

    def _index(self, base: ir.Expr, e: ast.Index, graph: Graph) -> ir.Expr:
        if isinstance(base.type, TupleT) and len(e.indices) == 1 and isinstance(e.indices[0], ast.IntLit):
            name = f"_{e.indices[0].value}"
            return ir.FieldOf(base.type.field(name), base, name)  # type: ignore[arg-type]
        if isinstance(base.type, T.SeqT) and len(e.indices) == 1:
            return ir.IndexOf(base.type.element, base, (self.conv(self.expr(e.indices[0], graph), T.INT, e.indices[0].span),))
        if isinstance(base.type, T.VectorT) and len(e.indices) == 1:
            return ir.IndexOf(base.type.element, base, (self.conv(self.expr(e.indices[0], graph), T.INT, e.indices[0].span),))
        if isinstance(base.type, T.MatrixT) and len(e.indices) == 2:
            return ir.IndexOf(base.type.element, base, tuple(self.conv(self.expr(i, graph), T.INT, i.span) for i in e.indices))
        raise not_supported(f"indexing a value of type {base.type.show()}", e.span)

    def _e_RecordLit(self, e: ast.RecordLit, graph: Graph) -> ir.Expr:
        t = self._type(e)
        assert isinstance(t, T.RecordT)
        given = {fv.name: fv.value for fv in e.fields}
        # a field the literal leaves out (RoboTool warns) has the default value of its type
        return ir.RecordLit(t, tuple((n, self.conv(self.expr(given[n], graph), ft, given[n].span) if n in given
                                      else default_expr(ft, e.span)) for n, ft in t.fields))

    def _literal(self, sym: EnumLitSym, args: tuple[ir.Expr, ...], span) -> ir.Expr:
        """An enumeration literal, given its arguments: its index, or, in an enumeration whose
        literals carry arguments, the tagged record of its index and arguments (the arguments of
        the other literals at their default)."""
        enum = self._norm(sym.enum)
        if isinstance(enum, TaggedT):
            tag = ir.Lit(enum.tag, enum.tag.literals.index(sym.literal))
            given = {n: self.conv(a, t, span) for (n, t), a in zip(enum.arg_fields(sym.literal), args)}
            return ir.RecordLit(enum, (("tag", tag),) + tuple((n, given[n] if n in given else default_expr(t, span))
                                                              for n, t in enum.fields[1:]))
        assert isinstance(enum, T.EnumT)
        return ir.Lit(enum, enum.literals.index(sym.literal))

    def _e_TupleLit(self, e: ast.TupleLit, graph: Graph) -> ir.Expr:
        items = tuple(self.expr(x, graph) for x in e.items)
        t = tuple_type(tuple(x.type for x in items))
        return ir.RecordLit(t, tuple((n, x) for (n, _), x in zip(t.fields, items)))

    def coll(self, t: T.Type, op: str, args, e: ast.Expr) -> ir.Coll:
        """A collection operation, with the expression's text and place for its run-time errors."""
        return ir.Coll(t, op, tuple(args), expr_text(e), e.span)

    def _e_SetLit(self, e: ast.SetLit, graph: Graph) -> ir.Expr:
        return self._enumeration(e, graph, "set")

    def _e_SeqLit(self, e: ast.SeqLit, graph: Graph) -> ir.Expr:
        return self._enumeration(e, graph, "seq")

    def _enumeration(self, e: ast.SetLit | ast.SeqLit, graph: Graph, op: str) -> ir.Expr:
        t = self._type(e)
        assert isinstance(t, (T.SetT, T.SeqT))
        if not isinstance(t.element, T.UnknownT):
            check_codegen_type(t, e.span, f"this {op}")
        return self.coll(t, op, (self.conv(self.expr(x, graph), t.element, x.span) for x in e.items), e)

    def _e_VectorLit(self, e: ast.VectorLit, graph: Graph) -> ir.Expr:
        t = self._type(e)
        items = tuple(self.expr(x, graph) for row in e.rows for x in row)
        elem = t.element if isinstance(t, (T.VectorT, T.MatrixT)) else T.UNKNOWN
        check_codegen_type(t, e.span, "a vector literal")
        return ir.VectorLit(t, tuple(self.conv(x, elem, e.span) for x in items))

    # -- calls

    def _e_Call(self, e: ast.Call, graph: Graph) -> ir.Expr:
        sym = self.model.symbol(e.func)
        if isinstance(sym, EnumLitSym):
            return self._literal(sym, tuple(self.expr(a, graph) for a in e.args), e.span)
        if isinstance(sym, FuncSym) and sym.builtin is not None and not hasattr(sym.builtin, "package") \
                and sym.name in ("min", "max", "abs"):
            t = self._type(e)
            if t not in T.NUMERIC or any(self._type(a) not in T.NUMERIC for a in e.args):
                raise not_supported(f"'{sym.name}' of a set or sequence", e.span)
            return ir.CallB(t, sym.name, tuple(self.conv(self.expr(a, graph), t, a.span) for a in e.args))
        if isinstance(sym, FuncSym) and sym.builtin is None and sym.decl is not None:
            return self._user_call(sym, e, graph)
        if isinstance(sym, FuncSym) and sym.builtin is not None and sym.name in RELATIONAL + FUNCTIONAL and \
                getattr(sym.builtin, "package", None) in ("relation_toolkit", "function_toolkit"):
            args = [self._as_relation(self.expr(a, graph), a) for a in e.args]
            return self.derived_call(sym.name, args, e)  # type: ignore[attr-defined]
        if isinstance(sym, FuncSym) and getattr(sym.builtin, "package", None) in TOOLKIT:
            return self._toolkit_call(sym, e, graph)
        if sym is None or isinstance(sym, VarSym):  # a function value: a lambda, override, a variable
            value = self.apply(e.func, [self.expr(a, graph) for a in e.args], e, graph)  # type: ignore[attr-defined]
            return self.conv(value, self._type(e), e.span)
        name = sym.name if isinstance(sym, FuncSym) else "?"
        raise not_supported(f"a call of function '{name}' (robogen has no implementation of it)", e.span)

    def _toolkit_call(self, sym: FuncSym, e: ast.Call, graph: Graph) -> ir.Expr:
        """A call of a toolkit function that code generation implements on sets, sequences and
        pairs (see :mod:`robogen.ir.collections`)."""
        first = T.single(self.model.type_of(e.args[0])) if e.args else None
        if sym.name == "override" and isinstance(first, T.FunctionT) and not first.relation:
            return self.fvalue(e, self._norm(first), graph)  # type: ignore[attr-defined]
        args = [self._as_relation(self.expr(a, graph), a) for a in e.args]
        t = self._type(e)
        kinds = tuple("set" if isinstance(a.type, T.SetT) else "seq" if isinstance(a.type, T.SeqT) else "pair"
                      if isinstance(a.type, TupleT) else "value" for a in args)
        op = TOOLKIT[sym.builtin.package].get((sym.name, kinds))  # type: ignore[union-attr]
        if op is None:
            shown = ", ".join(a.type.show() for a in args)
            raise not_supported(f"'{sym.name}' of {shown}", e.span)
        if op in RELATION_OPS:
            return self._relation_call(sym, op, args, t, e)
        if op in ("first", "second"):
            name = "_1" if op == "first" else "_2"
            return ir.FieldOf(args[0].type.field(name), args[0], name)  # type: ignore[union-attr, arg-type]
        if op == "maplet":
            pair = tuple_type((args[0].type, args[1].type))
            return ir.RecordLit(pair, (("_1", args[0]), ("_2", args[1])))
        if op in ("head", "last", "min", "max") and not isinstance(args[0].type.element, T.UnknownT):  # type: ignore[union-attr]
            return self.coll(args[0].type.element, op, args, e)  # an element, of the collection's own type  # type: ignore[union-attr]
        if op in ("Union", "Inter", "dconcat"):  # of the elements' elements: the outermost level's capacity
            inner = args[0].type.element  # type: ignore[union-attr]
            if op != "dconcat" and isinstance(inner, T.SeqT):  # sequences, as sets of (index, element) pairs
                args, inner = self.as_pair_sets(args[0], e.args[0])
            outer = (T.SetT if op != "dconcat" else T.SeqT)(inner.element)  # type: ignore[union-attr]
            check_codegen_type(outer, e.span, f"the result of '{sym.name}'")
            return self.conv(self.coll(outer, op, args, e), t, e.span)
        if op == "range":
            args = [self.conv(a, T.INT, x.span) for a, x in zip(args, e.args)]
        elif op == "extract":  # extract(a, q): the sequence first in the IR, as for filter(q, a)
            args = [self.conv(args[1], t, e.args[1].span), self.conv(args[0], T.SetT(T.INT), e.args[0].span)]
        elif is_collection(t) and op not in ("elems", "indices"):
            # the collections the result is made from have its elements ({} and <> take them; the
            # set that filters a sequence stays a set)
            args = [self.conv(a, replace(a.type, element=t.element), x.span) if is_collection(a.type) else a  # type: ignore[union-attr]
                    for a, x in zip(args, e.args)]
        elif op == "notin":  # an element (of any form) and a set
            args[0], args[1] = self.member(args[0], args[1], e.args[0].span, e.args[1].span)
        elif len(args) == 2 and all(is_collection(a.type) for a in args):
            common = args[1].type if _unknown_inside(self.model.type_of(e.args[0])) else args[0].type  # (prefix(<>, q))
            args = [self.conv(a, replace(a.type, element=common.element), x.span) for a, x in zip(args, e.args)]  # type: ignore[union-attr, call-arg]
        elif op in ("min", "max"):  # of a Set(int): a set of nats is converted (its C function gives an int)
            args = [self.conv(args[0], replace(args[0].type, element=T.INT), e.args[0].span)]  # type: ignore[arg-type]
        if isinstance(t, (T.SetT, T.SeqT)):
            check_codegen_type(t, e.span, f"the result of '{sym.name}'")
        return self.coll(t, op, args, e)

    def _as_relation(self, value: ir.Expr, e: ast.Expr) -> ir.Expr:
        """A function value given to the toolkit: the set of its pairs (robogen.ir.functions)."""
        if isinstance(value.type, FunMapT):
            return self.pairs_of(value, expr_text(e), e.span)  # type: ignore[attr-defined]
        return value

    def _relation_call(self, sym: FuncSym, op: str, args: list[ir.Expr], t: T.Type, e: ast.Call) -> ir.Expr:
        """A relation operation: every relation is a set of pairs (robogen.ir.collections)."""
        at = 1 if op in ("dres", "dsub", "iter") else 0
        if op == "relcomp" and _unknown_inside(self.model.type_of(e.args[1])):  # relcomp(r, {}): empty, whatever r is
            return ir.Coll(t, "set", (), expr_text(e), e.span)
        pair = args[at].type.element  # type: ignore[attr-defined]
        if not (isinstance(pair, TupleT) and len(pair.fields) == 2):
            if op in _EMPTY_IN_EMPTY_OUT and _unknown_inside(self.model.type_of(e.args[at])):  # {}: an empty relation nothing typed
                if op == "roverride":
                    return self.conv(args[1], t, e.span)  # override({}, s) is s
                return ir.Coll(t, "set" if isinstance(t, T.SetT) else "seq", (), expr_text(e), e.span)  # the result is empty too
            times = args[0]
            if op == "iter" and isinstance(times, ir.Lit) and isinstance(times.value, int) and times.value >= 0 \
                    and _unknown_inside(self.model.type_of(e.args[1])):
                # iter(n, {}) of a relation nothing typed: for n >= 1 empty, iter(0, {}) the identity,
                # each of the type it is used as
                if times.value == 0:
                    return ir.Coll(T.SetT(T.UNKNOWN), "identity", (), expr_text(e), e.span)
                return ir.Coll(T.SetT(T.UNKNOWN), "set", (), expr_text(e), e.span)
            raise not_supported(f"'{sym.name}' of {args[at].type.show()} (a relation is a set of pairs)", e.span)
        x, y = pair.field("_1"), pair.field("_2")
        if op == "iter":  # iter(n, r)
            return self.coll(args[1].type, op, (self.conv(args[0], T.INT, e.args[0].span), args[1]), e)
        # the pairs the operation works on: the result's where it is a relation (rsub({(| 1, 7 |)}, s)
        # of a Set(int) s is a nat <-> int: the relation is converted, never the set narrowed), for
        # rimage the relation's with a domain as wide as the set's elements
        result_pair = t.element if isinstance(t, T.SetT) else None  # type: ignore[attr-defined]
        if op == "rinv" and isinstance(result_pair, TupleT) and len(result_pair.fields) == 2:
            result_pair = tuple_type((result_pair.field("_2"), result_pair.field("_1")))  # the pairs of its argument, swapped
        if op in _SAME_PAIRS and isinstance(result_pair, TupleT) and len(result_pair.fields) == 2 and result_pair != pair:
            x, y = result_pair.field("_1"), result_pair.field("_2")
            args[at] = self.conv(args[at], T.SetT(result_pair), e.args[at].span)
        elif op == "rimage" and isinstance(args[1].type, T.SetT):
            wide = T.element_join(x, args[1].type.element)  # type: ignore[attr-defined]
            if wide is not None and wide != x and isinstance(t, T.SetT):
                x = wide
                args[0] = self.conv(args[0], T.SetT(tuple_type((x, t.element))), e.args[0].span)  # type: ignore[attr-defined]
        wanted = {"dres": (T.SetT(x), None), "dsub": (T.SetT(x), None), "rres": (None, T.SetT(y)),
                  "rsub": (None, T.SetT(y)), "rimage": (None, T.SetT(x)), "roverride": (None, args[0].type)}.get(op, (None, None))
        args = [self.conv(a, w, x_.span) if w is not None else a for a, w, x_ in zip(args, wanted, e.args)]
        check_codegen_type(t, e.span, f"the result of '{sym.name}'")
        return self.coll(t, op, args, e)

    def _user_call(self, sym: FuncSym, e: ast.Call, graph: Graph) -> ir.Expr:
        """A call of a function the model declares (robogen.ir.declared)."""
        args = [self.expr(a, graph) for a in e.args]
        return self.declared_call(sym, args, e, graph, list(e.args))  # type: ignore[attr-defined]

    # -- RoboSim inputs

    def _e_Dollar(self, e: ast.Dollar, graph: Graph) -> ir.Expr:
        sym = self.model.symbol(e)
        if isinstance(sym, EventSym):
            ev = self.machine.event(e.name)
            if ev is None:
                raise not_supported(f"'${e.name}'", e.span)
            return ir.Occurred(T.BOOLEAN, ev.index)
        return self.var_ref(graph, sym, e.span)

    def _e_DollarInput(self, e: ast.DollarInput, graph: Graph) -> ir.Expr:
        ev = self.machine.event(e.event)
        if ev is None:
            raise not_supported(f"'${e.event}?{e.var}'", e.span)
        var = self.model.bound_var(e)
        guard: ir.Expr = self.bind_in(ev, self.var_ref(graph, var, e.var_span), e.span)
        if e.predicate is not None:
            guard = ir.Bin(T.BOOLEAN, "and", guard, self.expr(e.predicate, graph))
        return guard

    def _e_DollarValue(self, e: ast.DollarValue, graph: Graph) -> ir.Expr:
        ev = self.machine.event(e.event)
        if ev is None or ev.type is None:
            raise not_supported(f"'${e.event}.v'", e.span)
        value = self.expr(e.value, graph)
        return ir.Bin(T.BOOLEAN, "and", ir.Occurred(T.BOOLEAN, ev.index), self.equal(ir.Payload(ev.type, ev.index), value))


__all__ = ["ExpressionLowering"]
