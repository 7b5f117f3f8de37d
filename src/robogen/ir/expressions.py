"""Lowering of expressions: checked AST expressions become typed IR expressions.

Numeric operands get explicit conversions (``Conv``) to the type of the operation, so the C
emitter and the interpreter never infer types. One step per expression form (``_e_<Form>``);
a form without a step has no code-generation meaning yet and is reported as not supported.
"""

from __future__ import annotations

from fractions import Fraction
from typing import TYPE_CHECKING

from robogen.diagnostics import Span, working_on
from robogen.ir import model as ir
from robogen.ir.region_tree import Graph
from robogen.ir.supported import check_codegen_type, is_scalar, not_supported
from robogen.semantics import types as T
from robogen.semantics.model import EnumLitSym, EventSym, FuncSym, VarSym
from robogen.syntax import ast

if TYPE_CHECKING:  # the attributes MachineLowering provides
    from robogen.semantics.model import SemanticModel

_UNSUPPORTED = {
    ast.StringLit: "a string",
    ast.Binder: "a quantifier, lambda or definite description",
    ast.TupleLit: "a tuple",
    ast.SeqLit: "a sequence",
    ast.SetLit: "a set",
    ast.SetRange: "a set",
    ast.SetComprehension: "a set comprehension",
    ast.Range: "a range",
    ast.MatrixOp: "inverse/transpose",
}

_BINARY = {
    "iff": "iff", "=>": "implies", "\\/": "or", "/\\": "and",
    "==": "eq", "!=": "ne", "<": "lt", "<=": "le", ">": "gt", ">=": "ge",
    "+": "add", "-": "sub", "*": "mul", "/": "div", "%": "mod",
}


class ExpressionLowering:
    """The expression steps of :class:`~robogen.ir.machines.MachineLowering` (a mixin). It uses
    the machine lowering's ``_norm`` (concrete types), ``_declare_var`` (a shared variable met
    first in a called operation) and ``user_function`` (record a user function's use)."""

    model: SemanticModel
    machine: ir.Machine
    vars: dict[str, ir.Var]
    period: Fraction  # the FMU's cycle period (RoboChart: 1)

    # -- entry points

    def expr(self, e: ast.Expr, graph: Graph) -> ir.Expr:
        with working_on(e.span):
            step = getattr(self, "_e_" + type(e).__name__, None)
            if step is None:
                raise not_supported(_UNSUPPORTED.get(type(e), type(e).__name__), e.span)
            return step(e, graph)

    def lvalue(self, e: ast.Expr, graph: Graph) -> ir.Expr:
        if isinstance(e, ast.Name):
            return self.var_ref(graph, self.model.symbol(e), e.span)
        if isinstance(e, ast.Field):
            base = self.lvalue(e.obj, graph)
            assert isinstance(base.type, T.RecordT)
            return ir.FieldOf(self._norm(base.type.field(e.field)), base, e.field)  # type: ignore[arg-type]
        if isinstance(e, ast.Index):
            return self._index(self.lvalue(e.obj, graph), e, graph)
        raise not_supported("this assignment target", e.span)

    def var_ref(self, graph: Graph, sym, span: Span | None) -> ir.Expr:
        if not isinstance(sym, VarSym):
            raise not_supported("this variable reference", span)
        var = graph.env.get(sym.name) or self.vars.get(sym.name)
        if var is None and sym.shared and sym.kind == "var":
            # a variable the controller provides, used by an operation the machine calls
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
        if isinstance(t, T.RecordT) and isinstance(e, ir.RecordLit):
            return ir.RecordLit(t, tuple((n, self.conv(v, t.field(n), span)) for n, v in e.values))
        return e

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

    def _e_BoolLit(self, e: ast.BoolLit, graph: Graph) -> ir.Expr:
        return ir.Lit(T.BOOLEAN, e.value)

    def _e_Name(self, e: ast.Name, graph: Graph) -> ir.Expr:
        sym = self.model.symbol(e)
        if isinstance(sym, EnumLitSym):
            enum = self._norm(sym.enum)
            assert isinstance(enum, T.EnumT)
            return ir.Lit(enum, enum.literals.index(sym.literal))
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
        return ir.Un(t, "neg", self.conv(operand, t, e.span))

    def _e_Binary(self, e: ast.Binary, graph: Graph) -> ir.Expr:
        first, links = ast.chain(e)  # a loop over a flat chain of operands, not recursion
        value = self.expr(first, graph)
        for link in links:
            value = self._binary(link, value, self.expr(link.right, graph))
        return value

    def _binary(self, e: ast.Binary, a: ir.Expr, b: ir.Expr) -> ir.Expr:
        """Binary expression ``e`` on its lowered operands."""
        op = _BINARY.get(e.op)
        if op is None:
            raise not_supported(f"the operator '{e.op}'", e.span)
        if op in ("iff", "implies", "or", "and"):
            return ir.Bin(T.BOOLEAN, op, a, b)
        if op in ("eq", "ne", "lt", "le", "gt", "ge"):
            return self._comparison(e, op, a, b)
        t = self._type(e)
        if t not in T.NUMERIC:
            raise not_supported(f"'{e.op}' on {t.show()}", e.span)
        return ir.Bin(t, op, self.conv(a, t, e.left.span), self.conv(b, t, e.right.span))

    def _comparison(self, e: ast.Binary, op: str, a: ir.Expr, b: ir.Expr) -> ir.Expr:
        if a.type in T.NUMERIC and b.type in T.NUMERIC:
            t = T.REAL if T.REAL in (a.type, b.type) else (T.NAT if a.type == b.type == T.NAT else T.INT)
            return ir.Bin(T.BOOLEAN, op, self.conv(a, t, e.left.span), self.conv(b, t, e.right.span))
        if op not in ("eq", "ne"):
            raise not_supported(f"'{e.op}' on {a.type.show()}", e.span)
        if not (is_scalar(a.type) or isinstance(a.type, (T.RecordT, T.VectorT, T.MatrixT))):
            raise not_supported(f"comparing values of type {a.type.show()}", e.span)
        if a.type != b.type:  # a literal takes the type of the other side: [| 0, 0 |] is vector(nat, 2)
            if self.conv(b, a.type, e.right.span).type == a.type:
                b = self.conv(b, a.type, e.right.span)
            elif self.conv(a, b.type, e.left.span).type == b.type:
                a = self.conv(a, b.type, e.left.span)
            else:
                raise not_supported(f"comparing a {a.type.show()} with a {b.type.show()}", e.span)
        return ir.Bin(T.BOOLEAN, op, a, b)

    def equal(self, a: ir.Expr, b: ir.Expr) -> ir.Expr:
        """a == b, numbers compared in their common type."""
        if a.type in T.NUMERIC and b.type in T.NUMERIC:
            t = T.REAL if T.REAL in (a.type, b.type) else T.INT
            return ir.Bin(T.BOOLEAN, "eq", self.conv(a, t, None), self.conv(b, t, None))
        return ir.Bin(T.BOOLEAN, "eq", a, b)

    def _e_IfExpr(self, e: ast.IfExpr, graph: Graph) -> ir.Expr:
        t = self._type(e)
        return ir.Cond(t, self.expr(e.cond, graph), self.conv(self.expr(e.then, graph), t, e.then.span),
                       self.conv(self.expr(e.otherwise, graph), t, e.otherwise.span))

    def _e_Cast(self, e: ast.Cast, graph: Graph) -> ir.Expr:
        t = self._norm(self.model.type_of(e.type))
        inner = self.expr(e.expr, graph)
        if e.op == "as" and t in T.NUMERIC and inner.type in T.NUMERIC:
            return ir.Conv(t, inner)
        raise not_supported(f"'{e.op}' here", e.span)

    # -- data

    def _e_Field(self, e: ast.Field, graph: Graph) -> ir.Expr:
        base = self.expr(e.obj, graph)
        if not isinstance(base.type, T.RecordT):
            raise not_supported(f"field selection on {base.type.show()}", e.span)
        return ir.FieldOf(self._norm(base.type.field(e.field)), base, e.field)  # type: ignore[arg-type]

    def _e_Index(self, e: ast.Index, graph: Graph) -> ir.Expr:
        return self._index(self.expr(e.obj, graph), e, graph)

    def _index(self, base: ir.Expr, e: ast.Index, graph: Graph) -> ir.Expr:
        if isinstance(base.type, T.VectorT) and len(e.indices) == 1:
            return ir.IndexOf(base.type.element, base, (self.conv(self.expr(e.indices[0], graph), T.INT, e.indices[0].span),))
        if isinstance(base.type, T.MatrixT) and len(e.indices) == 2:
            return ir.IndexOf(base.type.element, base, tuple(self.conv(self.expr(i, graph), T.INT, i.span) for i in e.indices))
        raise not_supported(f"indexing a value of type {base.type.show()}", e.span)

    def _e_RecordLit(self, e: ast.RecordLit, graph: Graph) -> ir.Expr:
        t = self._type(e)
        assert isinstance(t, T.RecordT)
        given = {fv.name: fv.value for fv in e.fields}
        return ir.RecordLit(t, tuple((n, self.conv(self.expr(given[n], graph), ft, given[n].span)) for n, ft in t.fields))

    def _e_VectorLit(self, e: ast.VectorLit, graph: Graph) -> ir.Expr:
        t = self._type(e)
        items = tuple(self.expr(x, graph) for row in e.rows for x in row)
        elem = t.element if isinstance(t, (T.VectorT, T.MatrixT)) else T.UNKNOWN
        check_codegen_type(t, e.span, "a vector literal")
        return ir.VectorLit(t, tuple(self.conv(x, elem, e.span) for x in items))

    # -- calls

    def _e_Call(self, e: ast.Call, graph: Graph) -> ir.Expr:
        applied = self.applied_lambda(e, graph)  # type: ignore[attr-defined]
        if applied is not None:
            return applied
        sym = self.model.symbol(e.func)
        if isinstance(sym, EnumLitSym):
            raise not_supported("an enumeration literal with arguments", e.span)
        if isinstance(sym, FuncSym) and sym.builtin is not None and sym.name in ("min", "max", "abs"):
            t = self._type(e)
            if t not in T.NUMERIC or any(self._type(a) not in T.NUMERIC for a in e.args):
                raise not_supported(f"'{sym.name}' of a set or sequence", e.span)
            return ir.CallB(t, sym.name, tuple(self.conv(self.expr(a, graph), t, a.span) for a in e.args))
        if isinstance(sym, FuncSym) and sym.builtin is None and sym.decl is not None:
            return self._user_call(sym, e, graph)
        name = sym.name if isinstance(sym, FuncSym) else "?"
        raise not_supported(f"a call of function '{name}' (robogen has no implementation of it)", e.span)

    def _user_call(self, sym: FuncSym, e: ast.Call, graph: Graph) -> ir.Expr:
        """A call of a function the model declares by its contract only: the code generator
        takes its implementation from the user (the reference interpreter from Python)."""
        params = tuple((n, self._norm(t)) for n, t in sym.params)
        result = self._norm(sym.result)
        for n, t in params + (("result", result),):
            if not is_scalar(t):
                raise not_supported(f"function '{sym.name}': {n} of type {t.show()}", e.span)
        self.user_function(sym, e, params, result)
        args = tuple(self.conv(self.expr(a, graph), pt, a.span) for a, (_, pt) in zip(e.args, params))
        return ir.CallU(result, sym.name, args)

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
        guard: ir.Expr = ir.BindIn(T.BOOLEAN, ev.index, self.var_ref(graph, var, e.var_span))
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
