"""Quantifiers and set comprehensions in C: each :class:`robogen.ir.model.Quant` becomes a static
function of the machine, ``rg_quant_<site>(d, m)``, whose nested loops follow
:mod:`robogen.ir.finite` step for step (the bound variables are the machine's memory, as
inlined operations' are). It has three sites in ``rg_sites``: its result overflows, a range is
too long, ``the`` has not exactly one value; on a fault it returns at once and the caller ends
the run."""

from __future__ import annotations

from robogen.codegen.cnames import ctype
from robogen.codegen.collection_ops import fault
from robogen.ir import model as ir
from robogen.ir.collections import LOOP_LIMIT
from robogen.ir.finite import messages
from robogen.semantics import types as T


class _Writer:
    """The lines of one quantifier's function, written by an Emitter (its expressions)."""

    def __init__(self, em, e: ir.Quant, site: int):
        self.em, self.e, self.site = em, e, site
        self.decls: list[str] = []
        self.used_done = False

    def value(self, x: ir.Expr, indent: str, into: str) -> list[str]:
        """``into = x;``, then the return a fault of x needs."""
        self.em.fallible = False
        text = self.em.expr(x)
        lines = [f"{indent}{into} = {text};"]
        if self.em.fallible:
            lines.append(f"{indent}if (d->fault) return r;")
        return lines

    def loops(self, k: int, indent: str) -> list[str]:
        e = self.e
        if k == len(e.domains):
            return self.visit(indent)
        dom = e.domains[k]
        var = self.em.expr(ir.Ref(dom.var.type, dom.var))
        inner = indent + "    "
        if dom.kind == "values":
            self.decls.append(f"uint64_t k{k};")
            count = 2 if dom.var.type == T.BOOLEAN else len(dom.var.type.literals)  # type: ignore[attr-defined]
            value = f"k{k} == 1" if dom.var.type == T.BOOLEAN else f"(int64_t)k{k}"
            return [f"{indent}for (k{k} = 0; k{k} < {count}; k{k}++) {{", f"{inner}{var} = {value};",
                    *self.loops(k + 1, inner), f"{indent}}}"]
        if dom.kind == "range":
            self.decls += [f"int64_t lo{k}, hi{k};", f"uint64_t c{k};"]
            lines = self.value(dom.low, indent, f"lo{k}") + self.value(dom.high, indent, f"hi{k}")  # type: ignore[arg-type]
            if dom.var.type == T.NAT:
                lines.append(f"{indent}if (lo{k} < 0) lo{k} = 0;")
            span = f"(uint64_t)hi{k} - (uint64_t)lo{k}"
            value = f"(int64_t)((uint64_t)lo{k} + c{k})"
            if dom.var.type == T.NAT:
                value = f"(uint64_t)lo{k} + c{k}"
            return lines + [
                f"{indent}if (hi{k} >= lo{k} && {span} >= {LOOP_LIMIT}) {{ {fault(f'{self.site} + 1')}; return r; }}",
                f"{indent}if (hi{k} >= lo{k})", f"{indent}for (c{k} = 0; c{k} <= {span}; c{k}++) {{",
                f"{inner}{var} = {value};", *self.loops(k + 1, inner), f"{indent}}}"]
        self.decls += [f"{ctype(dom.set.type)} s{k};", f"uint64_t k{k};"]  # type: ignore[union-attr]
        element = f"s{k}.a[k{k}]"
        source = dom.set.type.element  # type: ignore[union-attr]
        skip = [f"{inner}if ({element} < 0) continue;"] if dom.natural else []
        if dom.natural:
            element = f"(uint64_t){element}"
        elif source == T.NAT and dom.var.type == T.INT:
            element = f"rg_u_to_i({element})"
        return self.value(dom.set, indent, f"s{k}") + [  # type: ignore[arg-type]
            f"{indent}for (k{k} = 0; k{k} < s{k}.n; k{k}++) {{", *skip, f"{inner}{var} = {element};",
            *self.loops(k + 1, inner), f"{indent}}}"]

    def visit(self, indent: str) -> list[str]:
        """Where every variable has its value: the predicate, and what holds it."""
        e = self.e
        inner = indent + "    "
        lines: list[str] = []
        if e.pred is not None:
            self.decls.append("bool p_;")
            lines += self.value(e.pred, indent, "p_") + [f"{indent}if (p_) {{"]
        else:
            inner = indent
        if e.kind == "set":
            self.decls.append(f"{ctype(e.type.element)} v_;")  # type: ignore[attr-defined]
            insert = self.em.collections.need("insert", e.type)
            lines += self.value(e.body, inner, "v_") + [  # type: ignore[arg-type]
                f"{inner}{insert}(d, {self.site}, &r, v_);", f"{inner}if (d->fault) return r;"]
        elif e.kind == "the":
            lines.append(f"{inner}if (found++ > 0) {{ {fault(f'{self.site} + 2')}; return r; }}")
            lines += [f"{inner}w{k} = {self.em.expr(ir.Ref(dom.var.type, dom.var))};" for k, dom in enumerate(e.domains)]
        else:
            self.decls.append("bool b_;")
            lines += self.value(e.body, inner, "b_")  # type: ignore[arg-type]
            self.used_done = True
            if e.kind == "forall":
                lines.append(f"{inner}if (!b_) {{ r = false; goto done; }}")
            elif e.kind == "exists":
                lines.append(f"{inner}if (b_) {{ r = true; goto done; }}")
            else:
                lines.append(f"{inner}if (b_ && ++found > 1) {{ r = false; goto done; }}")
        if e.pred is not None:
            lines.append(f"{indent}}}")
        return lines


def quantifier(em, e: ir.Quant) -> str:
    """The call of the function computing ``e`` (its text added to ``em.helpers``)."""
    site = len(em.sites)
    em.sites += list(messages(e, em.fmu.place(e.span), em.fmu.capacity_of(e.type)))
    name = f"rg_quant_{site}"  # named after its first site: one name per quantifier of the FMU
    w = _Writer(em, e, site)
    loops = w.loops(0, "    ")
    after: list[str] = []
    if e.kind == "exists1":
        after = ["    r = found == 1;"]
    elif e.kind == "the":
        after = [f"    if (found == 0) {{ {fault(f'{site} + 2')}; return r; }}"]
        after += [f"    {em.expr(ir.Ref(dom.var.type, dom.var))} = w{k};" for k, dom in enumerate(e.domains)]
        after += w.value(e.body, "    ", "r")  # type: ignore[arg-type]
        w.decls += [f"{ctype(dom.var.type)} w{k};" for k, dom in enumerate(e.domains)]
    if e.kind in ("exists1", "the"):
        w.decls.append("uint64_t found = 0;")
    start = {"forall": "    r = true;", "exists": "    r = false;", "exists1": "    r = false;"}.get(e.kind, "    memset(&r, 0, sizeof r);")
    decls = [f"    {x}" for x in dict.fromkeys(w.decls)]
    done = ["done:"] if w.used_done else []
    rt = ctype(e.type)
    body = "\n".join([f"    {rt} r;", *decls, "    (void)d; (void)m;", start, *loops, *after, *done, "    return r;"])
    comment = f"/* {e.kind}: {e.text.replace('*/', '* /')} ({em.fmu.place(e.span)}) */"
    # after the functions of the quantifiers inside it, which its loops call
    em.helpers.append(f"{comment}\nstatic {rt} {name}(rg_model_data *d, rg_machine_{em.m.index} *m)\n{{\n{body}\n}}")
    em.fallible = True
    return f"{name}(d, m)"


__all__ = ["quantifier"]
