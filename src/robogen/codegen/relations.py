"""Relations in C: the bodies of the relation operations (a relation is a set of pairs), as
:mod:`robogen.ir.collections` computes them, step for step; :mod:`robogen.codegen.collections`
collects which the model needs."""

from __future__ import annotations

from robogen.codegen import collection_ops as O
from robogen.codegen.cnames import ctype, literal
from robogen.ir.collections import LOOP_LIMIT, all_values
from robogen.semantics import types as T

FILTERS = ("dres", "dsub", "rres", "rsub")


def relation_body(op: str, name: str, types: list, result: T.Type, code) -> str:
    """The C function ``name`` of relation operation ``op`` on arguments of ``types`` giving
    ``result``; ``code``: the FMU's CollectionCode (the functions it calls)."""
    if op == "iter":
        return _iter(name, types, result, code)
    if op == "closure":
        return _closure(name, types[0], code)
    at = 1 if op in ("dres", "dsub") else 0
    rel = types[at]
    x, y = rel.element.field("_1"), rel.element.field("_2")
    r = ctype(result)
    params = ", ".join(f"{ctype(t)} {n}" for t, n in zip(types, "ab"))
    ins = code.need("insert", result) if isinstance(result, T.SetT) and op not in FILTERS else ""
    lines = ["    uint64_t i, j;", f"    {r} r;", "    memset(&r, 0, sizeof r);", "    (void)d; (void)site; (void)j;"]
    A = "ab"[at]
    if op in ("dom", "ran"):
        lines.append(f"    for (i = 0; i < a.n && !d->fault; i++) {ins}(d, site, &r, a.a[i]._{1 if op == 'dom' else 2});")
    elif op == "rinv":
        lines.append(f"    for (i = 0; i < a.n && !d->fault; i++) {{ {ctype(result.element)} p; p._1 = a.a[i]._2; "
                     f"p._2 = a.a[i]._1; {ins}(d, site, &r, p); }}")
    elif op in FILTERS:
        key, kt = ("_1", x) if op in ("dres", "dsub") else ("_2", y)
        has = code.has(T.SetT(kt))
        test = "" if op in ("dres", "rres") else "!"
        other = "a" if A == "b" else "b"
        lines.append(f"    for (i = 0; i < {A}.n; i++) if ({test}{has}{other}, {A}.a[i].{key})) r.a[r.n++] = {A}.a[i];")
    elif op in ("haskey", "at"):  # a function value's pairs (robogen.ir.functions): the (first) pair of key b
        cmp = code.cmp(x)
        found = "return true;" if op == "haskey" else "return a.a[i]._2;"
        lines = ["    uint64_t i;", f"    {r} r;", "    memset(&r, 0, sizeof r);",
                 f"    for (i = 0; i < a.n; i++) if ({cmp}a.a[i]._1, b) == 0) {found}",
                 "    (void)d; (void)site;" if op == "haskey" else f"    {O.fault('site + 1')};"]
    elif op == "rimage":
        has = code.has(T.SetT(x))
        lines.append(f"    for (i = 0; i < a.n && !d->fault; i++) if ({has}b, a.a[i]._1)) {ins}(d, site, &r, a.a[i]._2);")
    elif op == "roverride":
        cmp = code.cmp(x)
        lines += [f"    for (i = 0; i < b.n && !d->fault; i++) {ins}(d, site, &r, b.a[i]);",
                  "    for (i = 0; i < a.n && !d->fault; i++) {",
                  f"        for (j = 0; j < b.n; j++) if ({cmp}b.a[j]._1, a.a[i]._1) == 0) break;",
                  f"        if (j == b.n) {ins}(d, site, &r, a.a[i]);", "    }"]
    elif op == "relcomp":
        cmp = code.cmp(y)
        lines += ["    for (i = 0; i < a.n && !d->fault; i++)", "        for (j = 0; j < b.n && !d->fault; j++)",
                  f"            if ({cmp}a.a[i]._2, b.a[j]._1) == 0) {{ {ctype(result.element)} p; p._1 = a.a[i]._1; "
                  f"p._2 = b.a[j]._2; {ins}(d, site, &r, p); }}"]
    else:  # squash: the second components, in the order of the first
        lines.append("    for (i = 0; i < a.n; i++) r.a[r.n++] = a.a[i]._2;")
    lines.append("    return r;")
    body = "\n".join(lines)
    return f"{O.sig(r, name, f'rg_model_data *d, int32_t site, {params}')}\n{{\n{body}\n}}"


def _iter(name: str, types: list, result: T.Type, code) -> str:
    """``iter(n, r)``: r composed with itself n times (of its inverse for a negative n), the
    identity relation for 0 where the element type is finite; the powers stop when one repeats
    the one before (robogen.ir.collections)."""
    rel = types[1]
    r = ctype(rel)
    x = rel.element.field("_1")
    compose = code.need_relation("relcomp", [rel, rel], rel)
    inverse = code.need_relation("rinv", [rel], rel)
    values = all_values(x)
    if values is None:
        identity = f"{O.fault('site + 1')};"
    elif len(values) > code.cap(rel):
        identity = f"{O.fault('site')};"
    else:
        identity = " ".join(f"r.a[{k}]._1 = r.a[{k}]._2 = {literal(v, x)};" for k, v in enumerate(values)) + f" r.n = {len(values)};"
    cmp = code.cmp(rel.element)
    lines = [
        "    uint64_t i, k, count;", f"    {r} r, p;", "    memset(&r, 0, sizeof r);",
        f"    if (n == 0) {{ {identity} return r; }}",
        "    if (n < 0) { a = " + f"{inverse}(d, site, a); if (d->fault) return r; }}",
        "    count = n < 0 ? (uint64_t)0 - (uint64_t)n : (uint64_t)n;",
        "    r = a;",
        "    for (k = 1; k < count; k++) {",
        f"        if (k >= {LOOP_LIMIT}) {{ {O.fault('site + 1')}; return r; }}",
        f"        p = {compose}(d, site, a, r);",
        "        if (d->fault) return p;",
        "        if (p.n == r.n) {",
        f"            for (i = 0; i < p.n; i++) if ({cmp}p.a[i], r.a[i]) != 0) break;",
        "            if (i == p.n) break;  /* the power repeats the one before: so do all after it */",
        "        }",
        "        r = p;",
        "    }",
        "    return r;",
    ]
    body = "\n".join(lines)
    return f"{O.sig(r, name, f'rg_model_data *d, int32_t site, int64_t n, {r} a')}\n{{\n{body}\n}}"


def _closure(name: str, rel: T.Type, code) -> str:
    """``tr_closure(r)``: t with t;r until it grows no more (the union only grows, so the same
    size is the same set; the capacity bounds the loop)."""
    r = ctype(rel)
    compose = code.need_relation("relcomp", [rel, rel], rel)
    union = code.need("union", rel)
    body = "\n".join([
        f"    {r} t = a, p, q;",
        "    for (;;) {",
        f"        p = {compose}(d, site, t, a);",
        "        if (d->fault) return t;",
        f"        q = {union}(d, site, t, p);",
        "        if (d->fault || q.n == t.n) return q;",
        "        t = q;",
        "    }",
    ])
    return f"{O.sig(r, name, f'rg_model_data *d, int32_t site, {r} a')}\n{{\n{body}\n}}"


__all__ = ["relation_body", "FILTERS"]
