"""Lowering of quantifiers (``forall``, ``exists``, ``exists1``), definite descriptions (``the``),
set comprehensions ``{x: T | p @ e}``, set ranges ``{a to b}`` and ranges ``[a, b]`` as values.

A bound variable becomes machine memory (one per occurrence, as an inlined operation's
parameters) that takes the values of a finite *domain* (:class:`robogen.ir.model.Domain`),
found in the predicate's conjuncts or in the variable's type, in this order:

- a conjunct ``x in s`` whose ``s`` reads no variable bound with or after ``x``: the elements of
  ``s`` (of a sequence, the set of them; ``x in {a to b}`` and ``x in range(a, b)`` are the
  integers a..b without building the set);
- an enumeration or ``boolean``: every value;
- an integer ``x`` with bounds in conjuncts ``a <= x``, ``x < b``, ``x == c``, ... (either way
  round; a ``nat`` has the lower bound 0): the integers between them (a strict bound is taken as
  the wider one; the predicate excludes it).

The predicate is evaluated for every value but for the conjuncts ``x in s`` that give domains
(they hold for each value of their variable).

A variable with none has an infinite domain and no finite meaning: a located error says so
(robogen.ir.finite gives the semantics).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from robogen.ir import model as ir
from robogen.ir.region_tree import Graph
from robogen.ir.supported import InnerSeqT, InnerSetT, check_codegen_type, not_supported, tuple_type
from robogen.semantics import types as T
from robogen.semantics.model import FuncSym, VarSym
from robogen.syntax import ast
from robogen.syntax.printer import expr as expr_text

if TYPE_CHECKING:
    from robogen.semantics.model import SemanticModel

INT_MAX = (1 << 63) - 1
_FLIP = {"<": ">", "<=": ">=", ">": "<", ">=": "<=", "==": "=="}


def _conjuncts(p: ast.Expr | None) -> list[ast.Expr]:
    if p is None:
        return []
    if isinstance(p, ast.Binary) and p.op == "/\\":
        return _conjuncts(p.left) + _conjuncts(p.right)
    return [p]


def _names(node) -> list[ast.Name]:
    """Every name inside an AST node."""
    found = [node] if isinstance(node, ast.Name) else []
    for field in getattr(node, "__dataclass_fields__", {}):
        if field == "span" or field.endswith("_span"):
            continue
        child = getattr(node, field)
        for c in child if isinstance(child, (tuple, list)) else (child,):
            if isinstance(c, ast.Node):
                found += _names(c)
    return found


class BinderLowering:
    """The quantifier steps of :class:`~robogen.ir.machines.MachineLowering` (a mixin)."""

    model: SemanticModel
    machine: ir.Machine
    site: int

    def _e_Binder(self, e: ast.Binder, graph: Graph) -> ir.Expr:
        if e.kind == "lambda":  # a function value (robogen.ir.functions)
            return self.fvalue(e, self._type(e), graph)  # type: ignore[attr-defined]
        return self._quantified(e.kind, e.decls, e.such_that, e.body, e, graph)

    def _e_SetComprehension(self, e: ast.SetComprehension, graph: Graph) -> ir.Expr:
        return self._quantified("set", e.decls, e.such_that, e.body, e, graph)

    def _e_SetRange(self, e: ast.SetRange, graph: Graph) -> ir.Expr:
        bounds = [self.conv(self.expr(x, graph), T.INT, x.span) for x in (e.low, e.high)]  # type: ignore[attr-defined]
        return self.coll(T.SetT(T.INT), "range", bounds, e)  # type: ignore[attr-defined]

    def _e_Range(self, e: ast.Range, graph: Graph) -> ir.Expr:
        """``[a, b]``, ``(a, b]``...: the integers between a and b, as a set."""
        bounds = [self.expr(x, graph) for x in (e.low, e.high)]  # type: ignore[attr-defined]
        if any(b.type not in (T.NAT, T.INT) for b in bounds):
            raise not_supported("a range of reals as a value (it has infinitely many elements)", e.span)
        low, high = (self.conv(b, T.INT, x.span) for b, x in zip(bounds, (e.low, e.high)))  # type: ignore[attr-defined]
        if not e.low_closed:
            low = ir.Bin(T.INT, "add", low, ir.Lit(T.INT, 1))
        if not e.high_closed:
            high = ir.Bin(T.INT, "sub", high, ir.Lit(T.INT, 1))
        return self.coll(T.SetT(T.INT), "range", (low, high), e)  # type: ignore[attr-defined]

    # -- quantifiers

    def _quantified(self, kind: str, decls: tuple[ast.Decl, ...], such_that: ast.Expr | None, body: ast.Expr | None,
                    e: ast.Expr, graph: Graph) -> ir.Expr:
        self.site += 1
        bound = []
        for d in decls:
            t = self._norm(self.model.type_of(d.type))  # type: ignore[attr-defined]
            check_codegen_type(t, d.span, f"the bound variable '{d.name}'")
            var = ir.Var(f"{d.name}#{self.site}", t, "local", None, d.span, False, len(self.machine.vars))
            self.machine.vars.append(var)
            bound.append(var)
        conjuncts = _conjuncts(such_that)
        with self.binding([(id(d), ir.Ref(v.type, v)) for d, v in zip(decls, bound)]):  # type: ignore[attr-defined]
            domains = self._domains(kind, list(zip(decls, bound)), conjuncts, graph)
            pred = None  # the conjuncts left: an 'x in s' a variable ranges over holds for each of its values
            for c in conjuncts:
                if not any(c is used for used in self._ranged):
                    value = self.expr(c, graph)  # type: ignore[attr-defined]
                    pred = value if pred is None else ir.Bin(T.BOOLEAN, "and", pred, value)
            value = self.expr(body, graph) if body is not None else None  # type: ignore[attr-defined]
        if value is None:  # {x: T | p}: the values of x (of the tuple of the variables)
            refs = [ir.Ref(v.type, v) for v in bound]
            value = refs[0] if len(refs) == 1 else ir.RecordLit(tuple_type(tuple(r.type for r in refs)),
                                                                 tuple((f"_{i + 1}", r) for i, r in enumerate(refs)))
        if kind in ("forall", "exists", "exists1"):
            t: T.Type = T.BOOLEAN
        else:
            t = self._type(e)  # type: ignore[attr-defined]
            check_codegen_type(t, e.span, "this comprehension" if kind == "set" else "this definite description")
        value = self.conv(value, t.element if kind == "set" else t, e.span)  # type: ignore[attr-defined]
        return ir.Quant(t, kind, domains, pred, value, expr_text(e), e.span)

    def as_pair_sets(self, a: ir.Expr, at: ast.Expr) -> tuple[list[ir.Expr], T.Type]:
        """A set of sequences as the set of their sets of (index, element) pairs (RoboChart's
        sequences are such sets): ``{q | q in a @ pairs(q)}``; and the type of its elements."""
        self.site += 1
        seq = a.type.element  # type: ignore[attr-defined]
        var = ir.Var(f"q#{self.site}", seq, "local", None, at.span, False, len(self.machine.vars))
        self.machine.vars.append(var)
        pair = tuple_type((T.NAT, seq.element))
        inner: T.Type = InnerSetT(pair, seq.capacity) if isinstance(seq, InnerSeqT) else T.SetT(pair)
        body = ir.Coll(inner, "pairs", (ir.Ref(seq, var),), expr_text(at), at.span)
        sets = ir.Quant(T.SetT(inner), "set", (ir.Domain(var, "set", set=a),), None, body, expr_text(at), at.span)
        return [sets], inner

    def _domains(self, kind: str, pending: list[tuple[ast.Decl, ir.Var]], conjuncts: list[ast.Expr],
                 graph: Graph) -> tuple[ir.Domain, ...]:
        """The domains of the bound variables, in the order of the loops: each time, the first
        variable (as declared) whose domain reads no variable still unbound. ``_ranged``: the
        conjuncts 'x in s' that give domains."""
        domains: list[ir.Domain] = []
        self._ranged: list[ast.Expr] = []
        while pending:
            unbound = {id(d) for d, _ in pending}
            for k, (d, var) in enumerate(pending):
                domain = self._domain(d, var, conjuncts, unbound, graph)
                if domain is not None:
                    domains.append(domain)
                    del pending[k]
                    break
            else:
                d, var = pending[0]
                hint = f"'{d.name} in s'" + (f" or '0 <= {d.name} /\\ {d.name} <= n'" if var.type in (T.NAT, T.INT) else "")
                raise not_supported(f"'{kind}' over '{d.name}: {var.type.show()}' without a finite domain ({var.type.show()} "
                                    f"has infinitely many values; bound '{d.name}' in the predicate, as {hint})", d.span)
        return tuple(domains)

    def _domain(self, d: ast.Decl, var: ir.Var, conjuncts: list[ast.Expr], later: set[int],
                graph: Graph) -> ir.Domain | None:
        """Where bound variable ``var`` (declared by ``d``) ranges (see the module documentation;
        None: nowhere finite); ``later``: the declarations of the variables still unbound, which
        its domain may not read."""
        def mine(x: ast.Expr) -> bool:
            sym = self.model.symbol(x) if isinstance(x, ast.Name) else None
            return isinstance(sym, VarSym) and sym.decl is d

        def free(x: ast.Expr) -> bool:
            return not any(isinstance(s := self.model.symbol(n), VarSym) and id(s.decl) in later for n in _names(x))

        for c in conjuncts:
            if isinstance(c, ast.Binary) and c.op == "in" and mine(c.left) and free(c.right):
                self._ranged.append(c)
                return self._set_domain(var, c.right, d, graph)
        if var.type == T.BOOLEAN or (isinstance(var.type, T.EnumT) and not var.type.literal_args):
            return ir.Domain(var, "values")
        if var.type in (T.NAT, T.INT):
            low, high = self._bounds(conjuncts, mine, free, graph)
            if var.type == T.NAT and low is None:
                low = ir.Lit(T.INT, 0)
            if low is not None and high is not None:
                return ir.Domain(var, "range", low=low, high=high)
        return None

    def _set_domain(self, var: ir.Var, s: ast.Expr, d: ast.Decl, graph: Graph) -> ir.Domain:
        if isinstance(s, ast.SetRange) or (isinstance(s, ast.Call) and isinstance(self.model.symbol(s.func), FuncSym)
                                           and self.model.symbol(s.func).name == "range" and len(s.args) == 2 and  # type: ignore[union-attr]
                                           getattr(self.model.symbol(s.func).builtin, "package", None) == "sequence_toolkit"):  # type: ignore[union-attr]
            if var.type in (T.NAT, T.INT):
                low, high = (s.low, s.high) if isinstance(s, ast.SetRange) else s.args  # type: ignore[union-attr]
                return ir.Domain(var, "range", low=self._int_bound(self.expr(low, graph), low.span),  # type: ignore[attr-defined]
                                 high=self._int_bound(self.expr(high, graph), high.span))  # type: ignore[attr-defined]
        value = self.expr(s, graph)  # type: ignore[attr-defined]
        if isinstance(value.type, T.SeqT):
            value = self.coll(T.SetT(value.type.element), "elems", (value,), s)  # type: ignore[attr-defined]
        element = value.type.element  # type: ignore[attr-defined]
        if element == var.type or (element == T.NAT and var.type == T.INT):
            return ir.Domain(var, "set", set=value)
        if element == T.INT and var.type == T.NAT:
            return ir.Domain(var, "set", set=value, natural=True)
        converted = self.conv(value, T.SetT(var.type), s.span)  # type: ignore[attr-defined]
        if converted.type != T.SetT(var.type):
            raise not_supported(f"'{d.name}: {var.type.show()}' ranging over a {value.type.show()}", s.span)
        return ir.Domain(var, "set", set=converted)

    def _bounds(self, conjuncts: list[ast.Expr], mine, free, graph: Graph) -> tuple[ir.Expr | None, ir.Expr | None]:
        """The first lower and upper integer bounds of the variable in the conjuncts."""
        low = high = None
        for c in conjuncts:
            if not (isinstance(c, ast.Binary) and c.op in _FLIP):
                continue
            if mine(c.left) and free(c.right):
                op, other = c.op, c.right
            elif mine(c.right) and free(c.left):
                op, other = _FLIP[c.op], c.left
            else:
                continue
            value = self.expr(other, graph)  # type: ignore[attr-defined]
            if value.type not in (T.NAT, T.INT):
                continue
            bound = self._int_bound(value, other.span)
            if op in (">", ">=", "==") and low is None:
                low = bound
            if op in ("<", "<=", "==") and high is None:
                high = bound
        return low, high

    def _int_bound(self, value: ir.Expr, span) -> ir.Expr:
        """A bound as an int: a nat beyond the largest int is the largest int."""
        if value.type == T.NAT:
            big = ir.Bin(T.BOOLEAN, "gt", value, ir.Lit(T.NAT, INT_MAX))
            return ir.Cond(T.INT, big, ir.Lit(T.INT, INT_MAX), ir.Conv(T.INT, value))
        return self.conv(value, T.INT, span)  # type: ignore[attr-defined]


__all__ = ["BinderLowering"]
