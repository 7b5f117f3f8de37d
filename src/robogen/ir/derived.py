"""Lowering of the toolkit functions that are not operations of :mod:`robogen.ir.collections` but
have a finite meaning on the finite relations robogen holds, each written with other IR:

- ``funcomp(s, r)``: ``relcomp(r, s)``; ``tr_closure(r)``: the operation ``closure``;
- ``id()`` on an enumeration or ``boolean``: the set of the pairs (v, v); ``refl_tr_closure(r)``:
  ``tr_closure(r)`` with it;
- ``isInjection(f)``, ``isFiniteInjection(f)``: ``forall p, q | p in f /\\ q in f @ p[1] == q[1]
  iff p[2] == q[2]``; ``disjoint(f)``: ``forall p, q | p in f /\\ q in f /\\ p != q @
  inter(p[2], q[2]) == {}``; ``partitions(f, a)``: ``disjoint(f) /\\ Union(ran(f)) == a``;
- ``isTotal(f)`` (of a finite domain type): ``size(dom(f))`` is the number of values of the type;
  ``isSurjection(f)`` likewise with ``ran``; ``isTotalInjection``, ``isTotalSurjection``,
  ``isBijection`` their conjunctions;
- ``isFinite``, ``isFiniteFunction``: true (every value robogen holds is finite).

On an infinite type (``id()``, ``isTotal`` of ``int -> nat``...) they quantify over every value of
the type and have no finite meaning: a located error says so.
"""

from __future__ import annotations

from robogen.ir import model as ir
from robogen.ir.collections import all_values
from robogen.ir.supported import not_supported
from robogen.semantics import types as T
from robogen.syntax import ast
from robogen.syntax.printer import expr as expr_text

RELATIONAL = ("funcomp", "tr_closure", "id", "refl_tr_closure")
FUNCTIONAL = ("isInjection", "isFiniteInjection", "disjoint", "partitions", "isTotal", "isSurjection", "isTotalInjection",
              "isTotalSurjection", "isBijection", "isFinite", "isFiniteFunction")


class DerivedLowering:
    """The derived toolkit steps of :class:`~robogen.ir.machines.MachineLowering` (a mixin)."""

    def derived_call(self, name: str, args: list[ir.Expr], e: ast.Call) -> ir.Expr:
        if any(not isinstance(a.type, T.SetT) for a in args[:1]) and name != "id":
            raise not_supported(f"'{name}' of {args[0].type.show()} (robogen's relations are sets of pairs)", e.span)
        if name == "funcomp":
            return self.coll(args[0].type, "relcomp", (args[1], self.conv(args[0], args[1].type, e.span)), e)  # type: ignore[attr-defined]
        if name == "tr_closure":
            return self.coll(args[0].type, "closure", (args[0],), e)  # type: ignore[attr-defined]
        if name in ("id", "refl_tr_closure"):
            t = self._type(e) if name == "id" else args[0].type  # type: ignore[attr-defined]
            identity = self._identity(t, name, e)
            if name == "id":
                return identity
            return self.coll(t, "union", (self.coll(t, "closure", (args[0],), e), identity), e)  # type: ignore[attr-defined]
        if name in ("isFinite", "isFiniteFunction"):
            return ir.Lit(T.BOOLEAN, True)
        if name in ("isInjection", "isFiniteInjection", "disjoint"):
            return self._pairwise(name, args[0], e)
        if name == "partitions":
            union = self.coll(T.SetT(args[0].type.element.field("_2").element), "Union",  # type: ignore[attr-defined]
                              (self.coll(T.SetT(args[0].type.element.field("_2")), "ran", (args[0],), e),), e)  # type: ignore[attr-defined]
            same = ir.Bin(T.BOOLEAN, "eq", self.conv(union, args[1].type, e.span), args[1])  # type: ignore[attr-defined]
            return ir.Bin(T.BOOLEAN, "and", self._pairwise("disjoint", args[0], e), same)
        return self._whole(name, args[0], e)

    def _identity(self, t: T.Type, name: str, e: ast.Call) -> ir.Expr:
        """The identity relation on the finite type of ``t``'s pairs, as a set enumeration (of a
        type the call does not tell, ``id()`` whose checked type keeps its ``?X``, the identity
        the value it is used as takes: ``conv``)."""
        checked = self.model.type_of(e) if name == "id" else None  # type: ignore[attr-defined]
        if isinstance(checked, T.FunctionT) and isinstance(checked.domain, (T.TypeVarT, T.UnknownT)) or \
                isinstance(t.element.field("_1"), (T.TypeVarT, T.UnknownT)):  # type: ignore[attr-defined]
            return ir.Coll(T.SetT(T.UNKNOWN), "identity", (), expr_text(e), e.span)
        return identity(t, name, expr_text(e), e.span)

    def _pairwise(self, name: str, f: ir.Expr, e: ast.Call) -> ir.Expr:
        """``forall p, q | p in f /\\ q in f ... @ ...`` of isInjection and disjoint."""
        pair = f.type.element  # type: ignore[attr-defined]
        self.site += 1  # type: ignore[attr-defined]
        p, q = (ir.Var(f"{n}#{self.site}", pair, "local", None, e.span, False, len(self.machine.vars) + k)  # type: ignore[attr-defined]
                for k, n in enumerate("pq"))
        self.machine.vars += [p, q]  # type: ignore[attr-defined]
        rp, rq = ir.Ref(pair, p), ir.Ref(pair, q)

        def part(r: ir.Expr, k: int) -> ir.Expr:
            return ir.FieldOf(pair.field(f"_{k}"), r, f"_{k}")

        pred = None
        if name == "disjoint":
            pred = ir.Bin(T.BOOLEAN, "ne", rp, rq)
            common = self.coll(part(rp, 2).type, "inter", (part(rp, 2), part(rq, 2)), e)  # type: ignore[attr-defined]
            body: ir.Expr = ir.Bin(T.BOOLEAN, "eq", ir.Coll(T.NAT, "size", (common,)), ir.Lit(T.NAT, 0))
        else:
            body = ir.Bin(T.BOOLEAN, "iff", self.equal(part(rp, 1), part(rq, 1)), self.equal(part(rp, 2), part(rq, 2)))  # type: ignore[attr-defined]
        domains = (ir.Domain(p, "set", set=f), ir.Domain(q, "set", set=f))
        return ir.Quant(T.BOOLEAN, "forall", domains, pred, body, expr_text(e), e.span)

    def _whole(self, name: str, f: ir.Expr, e: ast.Call) -> ir.Expr:
        """isTotal, isSurjection and their conjunctions: every value of a finite type is in the
        domain (range) of f."""
        parts = {"isTotalInjection": ("isTotal", "isInjection"), "isTotalSurjection": ("isTotal", "isSurjection"),
                 "isBijection": ("isTotal", "isInjection", "isSurjection")}.get(name, (name,))
        tests = []
        for part in parts:
            if part == "isInjection":
                tests.append(self._pairwise(part, f, e))
                continue
            side = "_1" if part == "isTotal" else "_2"
            t = f.type.element.field(side)  # type: ignore[attr-defined]
            values = all_values(t)
            if values is None:
                raise not_supported(f"'{name}' of {f.type.show()} (it asks about every value of {t.show()}, an infinite "
                                    "type)", e.span)
            found = self.coll(T.SetT(t), "dom" if side == "_1" else "ran", (f,), e)  # type: ignore[attr-defined]
            tests.append(ir.Bin(T.BOOLEAN, "eq", ir.Coll(T.NAT, "size", (found,)), ir.Lit(T.NAT, len(values))))
        result = tests[0]
        for x in tests[1:]:
            result = ir.Bin(T.BOOLEAN, "and", result, x)
        return result


def identity(t: T.Type, name: str, text: str, span) -> ir.Expr:
    """The identity relation of type ``t`` (a set of pairs of a finite type), as a set enumeration."""
    pair = t.element  # type: ignore[attr-defined]
    x = pair.field("_1")
    values = all_values(x)
    if values is None:
        raise not_supported(f"'{name}' on {x.show()} (the identity relation on an infinite type)", span)
    items = tuple(ir.RecordLit(pair, (("_1", ir.Lit(x, v)), ("_2", ir.Lit(x, v)))) for v in values)
    return ir.Coll(t, "set", items, text, span)


__all__ = ["DerivedLowering", "RELATIONAL", "FUNCTIONAL", "identity"]
