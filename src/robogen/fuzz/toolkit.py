"""The expression forms of the toolkits, relations and the switches that are off by default, as
a part of :class:`robogen.fuzz.exprs.Exprs` (a mixin): :meth:`ToolkitForms.toolkit_forms` offers
the forms that give a value of a requested type, :meth:`ToolkitForms.predicates` the boolean
ones. A form that could fail at run time on an empty collection (``head``, ``min``, ``q[1]``) is
written behind a test of its size."""

from __future__ import annotations

from robogen.fuzz.typegen import NUMBERS, SCALARS, is_tagged, name, type_ast
from robogen.semantics import types as T
from robogen.syntax import ast


def _call(f: str, *args: ast.Expr) -> ast.Call:
    return ast.Call(name(f), args)


def _guarded(q: ast.Expr, value: ast.Expr, otherwise: ast.Expr) -> ast.Expr:
    """``if size(q) > 0 then value else otherwise end``."""
    return ast.IfExpr(ast.Binary(">", _call("size", q), ast.IntLit(0)), value, otherwise)


class ToolkitForms:
    """Forms of :class:`~robogen.fuzz.exprs.Exprs` that use the toolkits (a mixin)."""

    def toolkit_forms(self, t: T.Type, sc) -> list:
        on, out = self.on, []  # type: ignore[attr-defined]
        if "sequences" in on and (t in SCALARS or isinstance(t, T.EnumT) and not is_tagged(t)):
            out.append((2, lambda d: self._from_sequence(t, sc, d)))
        if t in (T.INT, T.REAL) and "sets" in on:
            out.append((1, lambda d: self._least(t, sc, d)))
        if isinstance(t, T.ProductT) and len(t.items) == 2 and "tuples" in on:
            out.append((1, lambda d: self._maplet(t, sc, d)))
        if t in SCALARS and "tuples" in on:
            out.append((1, lambda d: self._projection(t, sc, d)))
        if t == T.REAL and sc.robosim:
            out.append((1, lambda d: (ast.Keyword("cycle"), T.REAL)))
        if isinstance(t, T.SetT) and "sets" in on:
            out += self._set_forms(t, sc)
        if isinstance(t, T.SeqT) and "sequences" in on:
            out += self._seq_forms(t, sc)
        if isinstance(t, T.MatrixT) and "matrix_ops" in on:
            out.append((1, lambda d: (ast.MatrixOp("transpose", self.expr(T.MatrixT(t.element, t.columns, t.rows), sc, d)[0]), t)))
        if t in NUMBERS and "lets" in on and t != T.NAT:
            out.append((1, lambda d: (ast.Cast("as", self.expr(T.NAT if t == T.INT else T.INT, sc, d)[0], type_ast(t)), t)))
        return out

    # ---------------------------------------------------------------- elements

    def _from_sequence(self, t: T.Type, sc, d: int):
        """``head(q)``, ``last(q)`` or ``q[1]`` of a sequence that is not empty."""
        self.toolkits.add("sequence_toolkit")  # type: ignore[attr-defined]
        q = self.operand(T.SeqT(t), sc, d)  # type: ignore[attr-defined]
        form = self.rng.choice(("head", "last", "index"))  # type: ignore[attr-defined]
        value = ast.Index(q, (ast.IntLit(1),)) if form == "index" else _call(form, q)
        return _guarded(q, value, self.literal(t, sc)), t  # type: ignore[attr-defined]

    def _least(self, t: T.Type, sc, d: int):
        self.toolkits.add("sequence_toolkit")  # type: ignore[attr-defined]
        s = self.operand(T.SetT(T.INT), sc, d)  # type: ignore[attr-defined]
        return _guarded(s, _call(self.rng.choice(("min", "max")), s), ast.IntLit(0)), T.INT  # type: ignore[attr-defined]

    def _maplet(self, t: T.ProductT, sc, d: int):
        self.toolkits.add("relation_toolkit")  # type: ignore[attr-defined]
        a, at = self.expr(t.items[0], sc, d)  # type: ignore[attr-defined]
        b, bt = self.expr(t.items[1], sc, d)  # type: ignore[attr-defined]
        return _call("maplet", a, b), T.ProductT((at, bt))

    def _projection(self, t: T.Type, sc, d: int):
        self.toolkits.add("relation_toolkit")  # type: ignore[attr-defined]
        other = self.env.scalar("field")  # type: ignore[attr-defined]
        first = self.rng.random() < 0.5  # type: ignore[attr-defined]
        pair, actual = self.expr(T.ProductT((t, other) if first else (other, t)), sc, d)  # type: ignore[attr-defined]
        items = actual.items if isinstance(actual, T.ProductT) else (t, t)
        return _call("first" if first else "second", pair), items[0 if first else 1]

    # ---------------------------------------------------------------- sets and relations

    def _set_forms(self, t: T.SetT, sc) -> list:
        out: list = []
        e = t.element
        if e == T.INT:
            out.append((1, lambda d: self._ranges(sc, d)))
        if isinstance(e, T.ProductT) and len(e.items) == 2 and "tuples" in self.on:  # type: ignore[attr-defined]
            out.append((2, lambda d: self._relation(t, sc, d)))
        if e in SCALARS and "tuples" in self.on:  # type: ignore[attr-defined]
            out.append((1, lambda d: self._domain(t, sc, d)))
        if "comprehensions" in self.on:  # type: ignore[attr-defined]
            out.append((1, lambda d: self._comprehension(t, sc, d)))
        if "union_inter" in self.on and "nested_collections" in self.on:  # type: ignore[attr-defined]
            out.append((1, lambda d: self._union_inter(t, sc, d)))
        return out

    def _union_inter(self, t: T.SetT, sc, d: int):
        """``Union({a, b})`` or ``Inter({a, b})`` of two sets of type ``t``."""
        self.toolkits.add("set_toolkit")  # type: ignore[attr-defined]
        return _call(self.rng.choice(("Union", "Inter")), ast.SetLit((self.operand(t, sc, d), self.operand(t, sc, d)))), t  # type: ignore[attr-defined]

    def _ranges(self, sc, d: int):
        """``{a to b}``, ``[a, b]``, ``(a, b]`` (switch comprehensions), else ``ran(range(a, b))``."""
        rng = self.rng  # type: ignore[attr-defined]
        low = rng.randint(-2, 2)
        high = low + rng.randint(0, 3)
        a, b = (ast.IntLit(low) if low >= 0 else ast.Unary("-", ast.IntLit(-low))), ast.IntLit(high) if high >= 0 else \
            ast.Unary("-", ast.IntLit(-high))
        if "comprehensions" in self.on and rng.random() < 0.6:  # type: ignore[attr-defined]
            if rng.random() < 0.5:
                return ast.SetRange(a, b), T.SetT(T.INT)
            return ast.Range(a, b, rng.random() < 0.7, rng.random() < 0.7), T.SetT(T.INT)
        self.toolkits.update(("relation_toolkit", "sequence_toolkit"))  # type: ignore[attr-defined]
        return _call("ran", _call("range", a, b)), T.SetT(T.INT)

    def _relation(self, t: T.SetT, sc, d: int):
        """A relation (a set of pairs) made by the relation toolkit."""
        self.toolkits.add("relation_toolkit")  # type: ignore[attr-defined]
        x, y = t.element.items  # type: ignore[attr-defined]
        rng = self.rng  # type: ignore[attr-defined]
        forms = ("rinv", "dres", "rres", "dsub", "rsub", "override", "relcomp")
        if x == y and "iter_dconcat" in self.on and "nested_collections" in self.on:  # type: ignore[attr-defined]
            forms += ("iter",)
        form = rng.choice(forms)
        if form == "iter":  # r composed with itself 1 to 3 times (iter(0, r) is the identity: finite on enumerations only)
            self.toolkits.add("sequence_toolkit")  # type: ignore[attr-defined]
            return _call("iter", ast.IntLit(rng.randint(1, 3)), self.operand(t, sc, d)), t  # type: ignore[attr-defined]
        if form == "rinv":
            return _call("rinv", self.operand(T.SetT(T.ProductT((y, x))), sc, d)), t  # type: ignore[attr-defined]
        r = self.operand(t, sc, d)  # type: ignore[attr-defined]
        if form in ("dres", "dsub"):
            return _call(form, self.operand(T.SetT(x), sc, d), r), t  # type: ignore[attr-defined]
        if form in ("rres", "rsub"):
            return _call(form, r, self.operand(T.SetT(y), sc, d)), t  # type: ignore[attr-defined]
        if form == "override":
            return _call("override", r, self.operand(t, sc, d)), t  # type: ignore[attr-defined]
        return _call("relcomp", self.operand(T.SetT(T.ProductT((x, x))), sc, d), r), t  # type: ignore[attr-defined]

    def _domain(self, t: T.SetT, sc, d: int):
        """``dom(r)``, ``ran(r)`` or ``rimage(r, a)`` of a relation."""
        self.toolkits.add("relation_toolkit")  # type: ignore[attr-defined]
        other = self.rng.choice(SCALARS)  # type: ignore[attr-defined]
        form = self.rng.choice(("dom", "ran", "rimage"))  # type: ignore[attr-defined]
        if form == "dom":
            return _call("dom", self.operand(T.SetT(T.ProductT((t.element, other))), sc, d)), t  # type: ignore[attr-defined]
        r = self.operand(T.SetT(T.ProductT((other, t.element))), sc, d)  # type: ignore[attr-defined]
        if form == "ran":
            return _call("ran", r), t
        return _call("rimage", r, self.operand(T.SetT(other), sc, d)), t  # type: ignore[attr-defined]

    def _comprehension(self, t: T.SetT, sc, d: int):
        """``{x: T | x in s @ e}`` over a set ``s`` (switch comprehensions)."""
        x = self.fresh("c")  # type: ignore[attr-defined]
        domain = t.element if self.rng.random() < 0.5 else self.env.scalar("elem")  # type: ignore[attr-defined]
        s = self.exact_set(domain, sc, d)  # type: ignore[attr-defined]
        inner = sc.with_syms(self.sym(x, domain))  # type: ignore[attr-defined]
        body, bt = self.expr(t.element, inner, d) if domain != t.element or self.rng.random() < 0.5 else (None, domain)  # type: ignore[attr-defined]
        such = ast.Binary("in", ast.Name((x,)), s)
        # its type is the body's (a Set(int) for an int body asked for a Set(real)), else the domain's
        return ast.SetComprehension((ast.Decl(x, type_ast(domain)),), such, body), T.SetT(bt)

    # ---------------------------------------------------------------- sequences

    def _seq_forms(self, t: T.SeqT, sc) -> list:
        out: list = [(1, lambda d: (_call("extract", self._positions(), self.operand(t, sc, d)), t))]  # type: ignore[attr-defined]
        if t.element == T.INT:
            out.append((1, lambda d: (_call("range", ast.IntLit(self.rng.randint(0, 2)),  # type: ignore[attr-defined]
                                            ast.IntLit(self.rng.randint(0, 4))), t)))  # type: ignore[attr-defined]
            self.toolkits.add("sequence_toolkit")  # type: ignore[attr-defined]
        if "iter_dconcat" in self.on and "nested_collections" in self.on:  # type: ignore[attr-defined]
            self.toolkits.add("sequence_toolkit")  # type: ignore[attr-defined]
            out.append((1, lambda d: (_call("dconcat", ast.SeqLit((self.operand(t, sc, d), self.operand(t, sc, d)))), t)))  # type: ignore[attr-defined]
        return out

    def _positions(self) -> ast.Expr:
        self.toolkits.add("sequence_toolkit")  # type: ignore[attr-defined]
        return ast.SetLit(tuple(ast.IntLit(self.rng.randint(1, 3)) for _ in range(self.rng.randint(1, 2))))  # type: ignore[attr-defined]

    # ---------------------------------------------------------------- predicates

    def predicates(self, sc) -> list:
        """Boolean forms of the toolkits, and quantifiers (switch quantifiers)."""
        out = []
        if "sets" in self.on:  # type: ignore[attr-defined]
            out.append((1, self._set_test))
        if "sequences" in self.on:  # type: ignore[attr-defined]
            out.append((1, self._seq_test))
        if "quantifiers" in self.on:  # type: ignore[attr-defined]
            out.append((1, self._quantifier))
        return out

    def _set_test(self, sc, d: int) -> ast.Expr:
        self.toolkits.add("set_toolkit")  # type: ignore[attr-defined]
        e = self.env.scalar("elem")  # type: ignore[attr-defined]
        form = self.rng.choice(("subseteq", "subset", "notin", "hasMin"))  # type: ignore[attr-defined]
        if form == "notin":
            return _call("notin", self.expr(e, sc, d)[0], self.operand(T.SetT(e), sc, d))  # type: ignore[attr-defined]
        if form == "hasMin":
            self.toolkits.add("sequence_toolkit")  # type: ignore[attr-defined]
            return _call(self.rng.choice(("hasMin", "hasMax")), self.operand(T.SetT(T.INT), sc, d))  # type: ignore[attr-defined]
        return _call(form, self.operand(T.SetT(e), sc, d), self.operand(T.SetT(e), sc, d))  # type: ignore[attr-defined]

    def _seq_test(self, sc, d: int) -> ast.Expr:
        self.toolkits.add("sequence_toolkit")  # type: ignore[attr-defined]
        q = T.SeqT(self.env.scalar("elem"))  # type: ignore[attr-defined]
        form = self.rng.choice(("isNonEmpty", "prefix", "suffix", "infix"))  # type: ignore[attr-defined]
        if form == "isNonEmpty":
            return _call(form, self.operand(q, sc, d))  # type: ignore[attr-defined]
        return _call(form, self.operand(q, sc, d), self.operand(q, sc, d))  # type: ignore[attr-defined]

    def _quantifier(self, sc, d: int) -> ast.Expr:
        """``forall x: T | x in s @ p`` over a set, or ``exists x: E @ p`` over an enumeration."""
        rng = self.rng  # type: ignore[attr-defined]
        kind = rng.choice(("forall", "exists", "exists1"))
        x = self.fresh("q")  # type: ignore[attr-defined]
        enums = [e for e in self.env.enums if not is_tagged(e)]  # type: ignore[attr-defined]
        if enums and rng.random() < 0.4:
            e = rng.choice(enums)
            body = self.boolean(sc.with_syms(self.sym(x, e)), d)  # type: ignore[attr-defined]
            return ast.Binder(kind, (ast.Decl(x, type_ast(e)),), None, body)
        e = self.env.scalar("elem")  # type: ignore[attr-defined]
        s = self.exact_set(e, sc, d)  # type: ignore[attr-defined]
        body = self.boolean(sc.with_syms(self.sym(x, e)), d)  # type: ignore[attr-defined]
        return ast.Binder(kind, (ast.Decl(x, type_ast(e)),), ast.Binary("in", ast.Name((x,)), s), body)


__all__ = ["ToolkitForms"]
