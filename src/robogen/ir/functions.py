"""Lowering of function values: lambdas, named functions, ``override`` of a function with a set
enumeration of pairs, casts of them, and function-typed variables, applied to arguments.

Code generation has no run-time representation of a function. A function value is a piece of
the model known at generation time, and applying it inlines it:

- ``(lambda x: T @ e)(a)``: ``e`` with ``x`` standing for ``a`` (expressions have no side
  effects, so the argument may be read more than once), also through a ``let`` name bound to
  the lambda (``let f == lambda x: T @ e @ override(f, ...)``);
- ``f(a)`` of a function the model declares: its call (:mod:`robogen.ir.declared`);
- ``(override(f, {(| k1, v1 |), ...}) as X -> Y)(a)``: ``if a == k1 then v1 else ... else f(a)``
  (the first pair written whose key matches wins);
- a function-typed variable holds the number of one of the function values the machine assigns
  to it (1, 2, ... in the order the machine's text writes them; 0 before any assignment), and
  applying it tests which. Applying it before any assignment is a run-time error. A value stored
  in a variable may not read the machine's variables (its meaning would change with them);
  only its parameters, constants and literals.
"""

from __future__ import annotations

from robogen.ir import model as ir
from robogen.ir.region_tree import Graph
from robogen.ir.supported import not_supported, tuple_type
from robogen.semantics import types as T
from robogen.semantics.model import FuncSym, VarSym
from robogen.syntax import ast
from robogen.syntax.printer import expr as expr_text


class FunctionValues:
    """The function-value steps of :class:`~robogen.ir.machines.MachineLowering` (a mixin)."""

    # -- application

    def apply(self, f: ast.Expr, args: list[ir.Expr], e: ast.Expr, graph: Graph) -> ir.Expr:
        """The value of function value ``f`` applied to the lowered ``args``."""
        while isinstance(f, ast.Cast) and f.op == "as":
            f = f.expr
        if isinstance(f, ast.Binder) and f.kind == "lambda":
            return self.lambda_applied(f, None, args, e.span, graph)
        if isinstance(f, ast.Call) and isinstance(f.func, ast.Name) and _toolkit(self.model.symbol(f.func)) == "override":
            return self._apply_override(f, args, e, graph)
        if isinstance(f, ast.Name):
            sym = self.model.symbol(f)
            if isinstance(sym, VarSym) and sym.kind in ("binder", "let") and id(sym.decl) in self.bound:
                bound = self.bound[id(sym.decl)]
                if isinstance(bound, ast.Expr):  # a name standing for a function value
                    return self.apply(bound, args, e, graph)
                if isinstance(bound, tuple):  # a let name bound to a lambda (with its scope)
                    return self.lambda_applied(bound[0], bound[1], args, e.span, graph)
            if isinstance(sym, VarSym) and isinstance(T.single(sym.type), T.FunctionT):
                return self._apply_variable(sym, f, args, e, graph)
            if isinstance(sym, FuncSym) and sym.builtin is None and sym.decl is not None:
                return self.declared_call(sym, args, e, graph)
        raise not_supported(f"applying {expr_text(f)}", e.span)

    def lambda_applied(self, lam: ast.Binder, scope: dict | None, args: list[ir.Expr], span, graph: Graph) -> ir.Expr:
        """The body of ``lam`` with each parameter standing for its argument, converted to the
        parameter's type, in ``scope`` (the names of where a let name's lambda was defined;
        None: here)."""
        if lam.such_that is not None or len(lam.decls) != len(args):
            raise not_supported(f"applying {expr_text(lam)} to {len(args)} arguments", span)
        saved = self.bound
        self.bound = dict(self.bound if scope is None else scope)
        try:
            for d, a in zip(lam.decls, args):
                self.bound[id(d)] = self.conv(a, self._norm(self.model.type_of(d.type)), span)
            return self.expr(lam.body, graph)
        finally:
            self.bound = saved

    def _apply_override(self, f: ast.Call, args: list[ir.Expr], e: ast.Expr, graph: Graph) -> ir.Expr:
        base, pairs = f.args
        if not isinstance(pairs, ast.SetLit) or not all(isinstance(p, ast.TupleLit) and len(p.items) == 2 for p in pairs.items):
            raise not_supported("override with a second argument other than a set enumeration of pairs (| k, v |)", pairs.span)
        result = self.apply(base, args, e, graph)
        key = args[0] if len(args) == 1 else ir.RecordLit(tuple_type(tuple(a.type for a in args)),
                                                          tuple((f"_{i + 1}", a) for i, a in enumerate(args)))
        for p in reversed(pairs.items):  # type: ignore[attr-defined]
            k, v = (self.expr(x, graph) for x in p.items)
            if isinstance(key.type, T.RecordT) and isinstance(k, ir.RecordLit):
                k = self.conv(k, key.type, p.span)
            test = self.equal(key, k) if not isinstance(key.type, T.RecordT) else ir.Bin(T.BOOLEAN, "eq", key, k)
            result = ir.Cond(result.type, test, self.conv(v, result.type, p.span), result)
        return result

    def _apply_variable(self, sym: VarSym, f: ast.Name, args: list[ir.Expr], e: ast.Expr, graph: Graph) -> ir.Expr:
        ref = self.var_ref(graph, sym, f.span)
        values = self.function_table(sym.name)
        ftype = T.single(sym.type)
        assert isinstance(ftype, T.FunctionT)
        result_t = self._norm(ftype.range)
        result: ir.Expr = ir.Coll(result_t, "undefined", (), f"function variable '{sym.name}' applied before it has a value",
                                  e.span)
        for n in range(len(values), 0, -1):
            value = self.conv(self.apply(values[n - 1], args, e, graph), result_t, e.span)
            result = ir.Cond(result_t, ir.Bin(T.BOOLEAN, "eq", ref, ir.Lit(T.INT, n)), value, result)
        return result

    # -- storing

    def function_value(self, target: ir.Expr, value: ast.Expr, span) -> ir.Expr:
        """The number that a function-typed variable stores for ``value``."""
        name = target.var.name if isinstance(target, ir.Ref) else "?"
        values = self.function_table(name)
        text = expr_text(value)
        for n, v in enumerate(values, 1):
            if expr_text(v) == text:
                return ir.Lit(T.INT, n)
        raise not_supported(f"storing {text} in function variable '{name}' here", span)  # pragma: no cover

    def function_table(self, name: str) -> list[ast.Expr]:
        """The function values the machine stores in variable ``name``, in the order written."""
        if self.fn_tables is None:
            self.fn_tables = {}
            for target, value in _assignments(self.scope):
                sym = target if isinstance(target, VarSym) else self.model.symbol(target) if isinstance(target, ast.Name) else None
                if isinstance(sym, VarSym) and isinstance(T.single(sym.type), T.FunctionT):
                    table = self.fn_tables.setdefault(sym.name, [])
                    if expr_text(value) not in [expr_text(v) for v in table]:
                        self._check_storable(value, sym.name)
                        table.append(value)
        return self.fn_tables.get(name, [])

    def _check_storable(self, value: ast.Expr, name: str) -> None:
        """A value stored in a function variable reads no machine variable (see the module doc)."""
        for node in _walk(value):
            if isinstance(node, ast.Name):
                sym = self.model.symbol(node)
                if isinstance(sym, VarSym) and sym.kind in ("var", "param") and not isinstance(T.single(sym.type), T.FunctionT):
                    raise not_supported(f"a function stored in '{name}' that reads variable '{sym.name}'", node.span)


def _toolkit(sym) -> str | None:
    b = getattr(sym, "builtin", None)
    return b.name if b is not None and hasattr(b, "package") else None


def _walk(node):
    """Every AST node inside ``node`` (expressions, statements), depth first."""
    yield node
    for name in getattr(node, "__dataclass_fields__", {}):
        if name == "span" or name.endswith("_span"):
            continue
        child = getattr(node, name)
        for c in child if isinstance(child, (tuple, list)) else (child,):
            if isinstance(c, ast.Node):
                yield from _walk(c)
            elif isinstance(c, tuple):
                for cc in c:
                    if isinstance(cc, ast.Node):
                        yield from _walk(cc)


def _assignments(scope) -> list[tuple[object, ast.Expr]]:
    """(target, value) of every variable initialiser (the variable's symbol) and assignment (the
    target expression) of a machine, in text order."""
    out: list[tuple[object, ast.Expr]] = [(v, v.init) for v in scope.vars.values() if v.init is not None]
    for node in _walk(scope.node):
        if isinstance(node, ast.Assign):
            out.append((node.target, node.value))
    return out


__all__ = ["FunctionValues"]
