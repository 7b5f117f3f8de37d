"""Lowering of function values: lambdas, named functions, ``override``, casts of them, sets of
pairs, function-typed variables and parameters, applied to arguments or kept as values.

**Applied where it is written**, a function value is inlined:

- ``(lambda x: T @ e)(a)``: ``e`` with ``x`` standing for ``a`` (expressions have no side
  effects, so the argument may be read more than once), also through a ``let`` name bound to
  the lambda (``let f == lambda x: T @ e @ override(f, ...)``);
- ``f(a)`` of a function the model declares: its call (:mod:`robogen.ir.declared`);
- ``(override(f, {(| k1, v1 |), ...}) as X -> Y)(a)``: ``if a == k1 then v1 else ... else f(a)``
  (the first pair written whose key matches wins).

**As a value** (stored in a variable, passed to a function, returned by one, updated by the
toolkit: ``positions = fdiff(nextApple, positions)``), a function ``D -> R`` is a finite map
with a default (:class:`~robogen.ir.supported.FunMapT`): ``pairs``, a set of (argument, result)
pairs with one pair per argument, and ``base``, the number of a *static* function value - a
lambda or a named function the state machines' text writes, numbered 1, 2, ... in the order
written (:meth:`FunctionValues.atoms`) - that gives the result outside ``pairs``; 0
for none. Applying it: the pair's result where the argument has a pair, else the static value
``base`` applied, else (``base`` 0) a run-time error naming the application and its model line
(a variable applied before it has a value is this error too).

- a lambda or named function is ``{pairs = {}, base = its number}``; a lambda that reads the
  machine's variables has its value fixed when it is stored: over a finite domain (``boolean``,
  an enumeration) it is tabulated into ``pairs`` then, over any other domain it is a located
  not-supported error (infinitely many results would depend on the variables' current values);
- ``override(f, g)``: the pairs of ``g`` win over those of ``f``; a ``g`` with a default (a
  lambda) is ``g`` itself; a set of pairs is ``g``'s pairs;
- a set of pairs, a relation, is a finite map without default; the other way, the toolkit's
  relation operations (``dom``, ``ran``, ``dres``, ``rres``, ``dsub``, ``rsub``, ``rimage``,
  ``rinv``, ``relcomp``, ``in``, ``size``...) take a function value as the set of its pairs: one
  with a default has no finite set of pairs, a run-time error naming the expression;
- ``==`` compares pairs and defaults (two equal lambdas written alike are one static value).
"""

from __future__ import annotations

from robogen.ir import model as ir
from robogen.ir.region_tree import Graph
from robogen.ir.supported import FunMapT, not_supported, tuple_type
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
        if _is_override(self.model, f) and _pair_enumeration(f.args[1]):  # type: ignore[attr-defined]
            return self._apply_override(f, args, e, graph)  # type: ignore[arg-type]
        if isinstance(f, ast.Name):
            sym = self.model.symbol(f)
            if isinstance(sym, VarSym) and sym.decl is not None and id(sym.decl) in self.bound:
                bound = self.bound[id(sym.decl)]
                if isinstance(bound, tuple):  # a let name bound to a lambda (with its scope)
                    return self.lambda_applied(bound[0], bound[1], args, e.span, graph)
                return self.apply_map(bound, args, e, graph, f"'{sym.name}'")  # a parameter of function type
            if isinstance(sym, VarSym) and isinstance(T.single(sym.type), T.FunctionT):
                return self.apply_map(self.var_ref(graph, sym, f.span), args, e, graph, f"function variable '{sym.name}'")
            if isinstance(sym, FuncSym) and sym.builtin is None and sym.decl is not None:
                return self.declared_call(sym, args, e, graph)
        t = self._norm(self.model.type_of(f.args[0] if _is_override(self.model, f) else f))  # type: ignore[attr-defined]
        if isinstance(t, FunMapT):  # a function computed at run time: a call's result, an override
            return self.apply_map(self.fvalue(f, t, graph), args, e, graph, f"the function {expr_text(f)}")
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
        result = self.apply(base, args, e, graph)
        key = _key(args)
        for p in reversed(pairs.items):  # type: ignore[attr-defined]
            k, v = (self.expr(x, graph) for x in p.items)
            if isinstance(key.type, T.RecordT) and isinstance(k, ir.RecordLit):
                k = self.conv(k, key.type, p.span)
            test = self.equal(key, k) if not isinstance(key.type, T.RecordT) else ir.Bin(T.BOOLEAN, "eq", key, k)
            result = ir.Cond(result.type, test, self.conv(v, result.type, p.span), result)
        return result

    def apply_map(self, value: ir.Expr, args: list[ir.Expr], e: ast.Expr, graph: Graph, what: str) -> ir.Expr:
        """Function value ``value`` (a :class:`FunMapT`) applied: the result of the argument's
        pair, else that of its static value, else a run-time error naming ``what``."""
        t = value.type
        assert isinstance(t, FunMapT)
        domain, result_t = t.pair.field("_1"), t.pair.field("_2")
        assert domain is not None and result_t is not None
        key = self.conv(_key(args), domain, e.span)
        text = expr_text(e)
        result: ir.Expr = ir.Coll(result_t, "undefined", (), f"{what} applied outside its domain (or before it has a value)",
                                  e.span)
        atoms = self.atoms()
        for n in range(len(atoms), 0, -1):
            if _fits(atoms[n - 1][0], t):  # (the others are never stored in a function of this type)
                v = self.conv(self.apply(atoms[n - 1][1], args, e, graph), result_t, e.span)
                result = ir.Cond(result_t, ir.Bin(T.BOOLEAN, "eq", _part(value, "base"), ir.Lit(T.INT, n)), v, result)
        pairs = _part(value, "pairs")
        return ir.Cond(result_t, ir.Coll(T.BOOLEAN, "haskey", (pairs, key), text, e.span),
                       ir.Coll(result_t, "at", (pairs, key), text, e.span), result)

    # -- function values as values

    def fvalue(self, e: ast.Expr, t: FunMapT, graph: Graph) -> ir.Expr:
        """The run-time value (of type ``t``) of function-typed expression ``e``."""
        while isinstance(e, ast.Cast) and e.op == "as":
            e = e.expr
        atom = self._atom(e)
        if atom is not None:
            return self._static(atom, t, e, graph)
        if _is_override(self.model, e):
            return self._override_value(e, t, graph)  # type: ignore[arg-type]
        if isinstance(e, ast.Name):
            sym = self.model.symbol(e)
            value = self.bound.get(id(sym.decl)) if isinstance(sym, VarSym) and sym.decl is not None else None
            value = value if isinstance(value, ir.Expr) else self.var_ref(graph, sym, e.span)
        else:
            value = self.expr(e, graph)
        converted = self.conv(value, t, e.span)
        if converted.type != t:
            raise not_supported(f"using {expr_text(e)}, a {value.type.show()}, as a function of type {t.show()}", e.span)
        return converted

    def map_of_pairs(self, pairs: ir.Expr, t: FunMapT) -> ir.Expr:
        """The function value of a set of pairs (no default)."""
        return ir.RecordLit(t, (("pairs", pairs), ("base", ir.Lit(T.INT, 0))))

    def pairs_of(self, value: ir.Expr, text: str, span) -> ir.Expr:
        """Function value ``value`` as the set of its pairs (a relation); one with a default has
        none: a run-time error naming ``text``."""
        t = value.type
        assert isinstance(t, FunMapT)
        base = _part(value, "base")
        if isinstance(base, ir.Lit) and base.value == 0:
            return _part(value, "pairs")
        fault = ir.Coll(t.pairs, "undefined", (), f"{text}: a function given by a lambda or named function has no finite "
                        "set of pairs", span)
        return ir.Cond(t.pairs, ir.Bin(T.BOOLEAN, "eq", base, ir.Lit(T.INT, 0)), _part(value, "pairs"), fault)

    def _atom(self, e: ast.Expr) -> ast.Expr | None:
        """The static function value ``e`` denotes (a lambda, a named function), or None."""
        if isinstance(e, ast.Binder) and e.kind == "lambda":
            return e
        if isinstance(e, ast.Name):
            sym = self.model.symbol(e)
            if isinstance(sym, FuncSym) and sym.builtin is None and sym.decl is not None and sym.params:
                return e
            if isinstance(sym, VarSym) and sym.decl is not None and isinstance(self.bound.get(id(sym.decl)), tuple):
                return self.bound[id(sym.decl)][0]  # a let name bound to a lambda
        return None

    def _static(self, atom: ast.Expr, t: FunMapT, e: ast.Expr, graph: Graph) -> ir.Expr:
        """A lambda or named function as a value: its number, or its table where it reads the
        machine's variables (over a finite domain)."""
        reads = _reads_state(self.model, atom)
        if reads is not None:
            return self._tabulated(atom, t, e, graph, reads)
        texts = [expr_text(a) for _, a in self.atoms()]
        text = expr_text(atom)
        if text not in texts or not _fits(self.atoms()[texts.index(text)][0], t):
            raise not_supported(f"the function value {text} here (robogen numbers the function values a state machine "
                                "writes; this one is written elsewhere)", e.span)
        return ir.RecordLit(t, (("pairs", ir.Coll(t.pairs, "set", (), "{}", e.span)), ("base", ir.Lit(T.INT, texts.index(text) + 1))))

    def _tabulated(self, atom: ast.Expr, t: FunMapT, e: ast.Expr, graph: Graph, reads: ast.Name) -> ir.Expr:
        """A lambda that reads the machine's variable ``reads``, as the pairs of every argument of
        its finite domain, computed when it is stored."""
        domain, pair = t.pair.field("_1"), t.pair
        keys = _finite(domain)
        if keys is None:
            raise not_supported(f"a function over {domain.show()} that reads variable '{reads.text}' as a value (its "  # type: ignore[union-attr]
                                "results, fixed when it is stored, would be infinitely many; over a boolean or an "
                                "enumeration it is tabulated)", reads.span)
        items = []
        for k in keys:
            arg = ir.Lit(domain, k)  # type: ignore[arg-type]
            value = self.conv(self.apply(atom, [arg], e, graph), pair.field("_2"), e.span)
            items.append(ir.RecordLit(pair, (("_1", arg), ("_2", value))))
        return self.map_of_pairs(ir.Coll(t.pairs, "set", tuple(items), expr_text(atom), e.span), t)

    def _override_value(self, e: ast.Call, t: FunMapT, graph: Graph) -> ir.Expr:
        """``override(f, g)`` as a value: g's pairs win; a g with a default is g."""
        f = self.fvalue(e.args[0], t, graph)
        g_type = T.single(self.model.type_of(e.args[1]))
        g = self.fvalue(e.args[1], t, graph) if isinstance(g_type, T.FunctionT) and not g_type.relation else \
            self.map_of_pairs(self.conv(self.expr(e.args[1], graph), t.pairs, e.args[1].span), t)
        if g.type != t:
            raise not_supported(f"override of a {t.show()} with a {g.type.show()}", e.span)
        merged = ir.Coll(t.pairs, "roverride", (_part(f, "pairs"), _part(g, "pairs")), expr_text(e), e.span)
        g_base = _part(g, "base")
        if isinstance(g_base, ir.Lit) and g_base.value == 0:
            return ir.RecordLit(t, (("pairs", merged), ("base", _part(f, "base"))))
        total = ir.Bin(T.BOOLEAN, "ne", g_base, ir.Lit(T.INT, 0))
        return ir.RecordLit(t, (("pairs", ir.Cond(t.pairs, total, _part(g, "pairs"), merged)),
                                ("base", ir.Cond(T.INT, total, g_base, _part(f, "base")))))

    # -- the static function values

    def atoms(self) -> list[tuple[FunMapT, ast.Expr]]:
        """(type, value) of the static function values the FMU's state machines write as values
        (not applied where written), numbered from 1 in the order written: those of the machines,
        of the functions the model declares (their postconditions) and of its operations. One numbering for the
        FMU, so that machines may pass function values to one another; a function value of a
        type takes the numbers of those that fit it (:func:`_fits`)."""
        ctx = self.ctx
        if ctx.fn_atoms is None:
            ctx.fn_atoms = []
            scopes = [scope for _, scope, _ in self.boundary.machines]
            roots = [v.init for scope in scopes for v in scope.vars.values() if v.init is not None]
            roots += [scope.node for scope in scopes]
            roots += [m for f in self.model.files for d in f.items if isinstance(d, ast.FunctionDef) for m in d.members]
            roots += _operations(self.model.files)  # inlined where the machines call them
            texts: set[str] = set()
            for root in roots:
                for node in _values(root):
                    atom = self._atom_in_text(node)
                    if atom is not None and expr_text(atom[1]) not in texts:
                        texts.add(expr_text(atom[1]))
                        ctx.fn_atoms.append(atom)
        return ctx.fn_atoms

    def _atom_in_text(self, node) -> tuple[FunMapT, ast.Expr] | None:
        """(its type, itself) of a static function value that reads no variable, found in the text."""
        if not isinstance(node, ast.Expr):
            return None
        if not (isinstance(node, ast.Binder) and node.kind == "lambda"):
            sym = self.model.symbol(node) if isinstance(node, ast.Name) else None
            if not (isinstance(sym, FuncSym) and sym.builtin is None and sym.decl is not None and sym.params):
                return None
        t = T.single(self.model.type_of(node))
        if not isinstance(t, T.FunctionT) or t.relation or "?" in t.show() or _reads_state(self.model, node) is not None:
            return None
        nt = self._norm(t)
        return (nt, node) if isinstance(nt, FunMapT) else None


def _part(value: ir.Expr, name: str) -> ir.Expr:
    """Field ``name`` of a function value (of a record literal: the field's expression)."""
    if isinstance(value, ir.RecordLit):
        return dict(value.values)[name]
    assert isinstance(value.type, FunMapT)
    return ir.FieldOf(value.type.pairs if name == "pairs" else T.INT, value, name)


def _fits(atom: FunMapT, t: FunMapT) -> bool:
    """May a static function value of type ``atom`` be stored in a function value of type ``t``?
    Its domain and range are those of ``t``, or numbers where ``t``'s are (converted)."""
    def same(a: T.Type | None, b: T.Type | None) -> bool:
        return a == b or (a in T.NUMERIC and b in T.NUMERIC)
    return all(same(atom.pair.field(n), t.pair.field(n)) for n in ("_1", "_2"))


def _key(args: list[ir.Expr]) -> ir.Expr:
    """The argument of an application as one value: a tuple of several."""
    if len(args) == 1:
        return args[0]
    return ir.RecordLit(tuple_type(tuple(a.type for a in args)), tuple((f"_{i + 1}", a) for i, a in enumerate(args)))


def _finite(t: T.Type | None) -> list | None:
    """Every value of a finite domain (booleans, enumeration literals by index), or None."""
    if t == T.BOOLEAN:
        return [False, True]
    if isinstance(t, T.EnumT) and not any(t.literal_args):
        return list(range(len(t.literals)))
    return None


def _is_override(model, e: ast.Expr) -> bool:
    if not (isinstance(e, ast.Call) and isinstance(e.func, ast.Name) and len(e.args) == 2):
        return False
    b = getattr(model.symbol(e.func), "builtin", None)
    return b is not None and hasattr(b, "package") and b.name == "override"


def _pair_enumeration(e: ast.Expr) -> bool:
    return isinstance(e, ast.SetLit) and all(isinstance(p, ast.TupleLit) and len(p.items) == 2 for p in e.items)


def _reads_state(model, value: ast.Expr) -> ast.Name | None:
    """The first name in ``value`` of a machine variable or parameter, or of a name bound outside
    it (a let, a binder, a function's parameter): what makes its meaning change with the state
    (constants, literals and its own parameters do not)."""
    own = {id(d) for node in _walk(value) if isinstance(node, ast.Binder) for d in node.decls}
    own |= {id(d) for node in _walk(value) if isinstance(node, ast.Let) for d in node.defs}
    for node in _walk(value):
        if isinstance(node, ast.Name):
            sym = model.symbol(node)
            if isinstance(sym, VarSym) and sym.kind != "const" and id(sym.decl) not in own:
                return node
    return None


def _operations(files) -> list[ast.OperationDef]:
    """The operation definitions of ``files``, at the top level and in controllers."""
    found = []
    for f in files:
        for d in f.items:
            members = d.members if isinstance(d, ast.Controller) else (d,)
            found += [m for m in members if isinstance(m, ast.OperationDef)]
    return found


def _values(node, applied: bool = False):
    """Every expression inside ``node`` that is not applied where it is written (the function
    of a call, and what an applied override or cast is made of, are)."""
    if isinstance(node, ast.Expr) and not applied:
        yield node
    if isinstance(node, ast.Cast):
        yield from _values(node.expr, applied)
        return
    if isinstance(node, ast.Call):
        yield from _values(node.func, True)
        override = applied and isinstance(node.func, ast.Name) and node.func.last == "override"
        for a in node.args:
            yield from _values(a, override)
        return
    for child in _children(node):
        yield from _values(child)


def _children(node):
    for name in getattr(node, "__dataclass_fields__", {}):
        if name == "span" or name.endswith("_span"):
            continue
        child = getattr(node, name)
        for c in child if isinstance(child, (tuple, list)) else (child,):
            if isinstance(c, ast.Node):
                yield c
            elif isinstance(c, tuple):
                yield from (cc for cc in c if isinstance(cc, ast.Node))


def _walk(node):
    """Every AST node inside ``node`` (expressions, statements), depth first."""
    yield node
    for c in _children(node):
        yield from _walk(c)


__all__ = ["FunctionValues"]
