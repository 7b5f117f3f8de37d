"""The C bodies of the set and sequence operations, one function per operation and collection
type (:mod:`robogen.codegen.collections` collects which the model needs). Each computes what
:mod:`robogen.ir.collections` computes, step for step.

A body is made by ``body(t, k)``: ``t`` the collection type, ``k`` what it needs of the FMU's
collection code (the capacity of a type, the comparison and membership functions of an element
type, with the model data as their first argument where the elements hold strings, which are
ordered by their text).
"""

from __future__ import annotations

from typing import Protocol

from robogen.codegen.cnames import ctype, elem_tag
from robogen.semantics import types as T


class Needs(Protocol):
    def cap(self, t: T.Type) -> int: ...
    def cmp(self, t: T.Type) -> str: ...  # "rg_cmp_X(" or "rg_cmp_X(d, ": call text up to the operands
    def has(self, t: T.Type) -> str: ...  # likewise for membership in a collection of type t
    def data_param(self, t: T.Type) -> str: ...  # "const rg_model_data *d, " where t's elements hold strings


def function(op: str, t: T.Type) -> str:
    """The C name of operation ``op`` on (or making) collections of type ``t``."""
    return f"rg_{op}_{ctype(t)[3:]}"


def cmp_function(t: T.Type) -> str:
    return f"rg_cmp_{elem_tag(t)}"


def sig(result: str, name: str, params: str) -> str:
    return f"static {result} {name}({params}) RG_MAYBE_UNUSED;\nstatic {result} {name}({params})"


def fault(site: str) -> str:
    return f"d->fault = RG_FAULT_COLLECTION; d->fault_site = {site}"


def cmp(t: T.Type, k: Needs) -> str:
    """The order of elements of type ``t`` (robogen.ir.collections.compare)."""
    c = ctype(t)
    if isinstance(t, T.RecordT):
        tests = "\n".join(f"    if ((c = {k.cmp(ft)}a.{n}, b.{n})) != 0) return c;" for n, ft in t.fields)
        body = f"    int c;\n{tests}\n    return 0;"
    elif isinstance(t, (T.SetT, T.SeqT)):
        body = (f"    uint64_t i;\n    int c;\n    for (i = 0; i < a.n && i < b.n; i++)\n"
                f"        if ((c = {k.cmp(t.element)}a.a[i], b.a[i])) != 0) return c;\n    return (a.n > b.n) - (a.n < b.n);")
    elif isinstance(t, (T.VectorT, T.MatrixT)):
        size = t.size if isinstance(t, T.VectorT) else (t.rows or 0) * (t.columns or 0)
        body = (f"    int i, c;\n    for (i = 0; i < {size}; i++)\n"
                f"        if ((c = {k.cmp(t.element)}a.a[i], b.a[i])) != 0) return c;\n    return 0;")
    elif t == T.STRING:  # by the text, byte by byte (UTF-8: the order of code points)
        body = "    int c;\n    if (a == b) return 0;\n    c = strcmp(rg_text(d, a), rg_text(d, b));\n    return (c > 0) - (c < 0);"
    else:
        body = "    return (a > b) - (a < b);"
    return f"{sig('int', cmp_function(t), f'{k.data_param(t)}{c} a, {c} b')}\n{{\n{body}\n}}"


def make(t, k: Needs) -> str:
    c, e = ctype(t), ctype(t.element)
    if isinstance(t, T.SetT):
        body = (f"    uint64_t i;\n    {c} s;\n    memset(&s, 0, sizeof s);\n"
                f"    for (i = 0; i < n; i++) {function('insert', t)}(d, site, &s, items[i]);\n    return s;")
    else:
        body = (f"    uint64_t i;\n    {c} s;\n    memset(&s, 0, sizeof s);\n    if (n > {k.cap(t)}) {{ {fault('site')}; return s; }}\n"
                f"    for (i = 0; i < n; i++) s.a[i] = items[i];\n    s.n = n;\n    return s;")
    return f"{sig(c, function('make', t), f'rg_model_data *d, int32_t site, uint64_t n, const {e} *items')}\n{{\n{body}\n}}"


def insert(t, k: Needs) -> str:
    c, e = ctype(t), ctype(t.element)
    body = (f"    uint64_t i, j;\n    int c = 1;\n    for (i = 0; i < s->n; i++)\n"
            f"        if ((c = {k.cmp(t.element)}s->a[i], x)) >= 0) break;\n"
            f"    if (i < s->n && c == 0) return;\n"
            f"    if (s->n >= {k.cap(t)}) {{ {fault('site')}; return; }}\n"
            f"    for (j = s->n; j > i; j--) s->a[j] = s->a[j - 1];\n    s->a[i] = x;\n    s->n++;")
    return f"{sig('void', function('insert', t), f'rg_model_data *d, int32_t site, {c} *s, {e} x')}\n{{\n{body}\n}}"


def has(t, k: Needs) -> str:
    c, e = ctype(t), ctype(t.element)
    if isinstance(t, T.SetT):
        body = (f"    uint64_t i;\n    int c;\n    for (i = 0; i < s.n; i++)\n"
                f"        if ((c = {k.cmp(t.element)}s.a[i], x)) >= 0) return c == 0;\n    return false;")
    else:
        body = (f"    uint64_t i;\n    for (i = 0; i < s.n; i++)\n"
                f"        if ({k.cmp(t.element)}s.a[i], x) == 0) return true;\n    return false;")
    return f"{sig('bool', function('has', t), f'{k.data_param(t)}{c} s, {e} x')}\n{{\n{body}\n}}"


def binary_set(op: str):
    def body_of(t, k: Needs) -> str:
        c = ctype(t)
        has_, ins = k.has(t), function("insert", t)
        if op in ("union", "symdiff"):
            keep_a = "" if op == "union" else f"if (!{has_}b, a.a[i])) "
            keep_b = "" if op == "union" else f"if (!{has_}a, b.a[i])) "
            body = (f"    uint64_t i;\n    {c} r;\n    memset(&r, 0, sizeof r);\n"
                    f"    for (i = 0; i < a.n && !d->fault; i++) {keep_a}{ins}(d, site, &r, a.a[i]);\n"
                    f"    for (i = 0; i < b.n && !d->fault; i++) {keep_b}{ins}(d, site, &r, b.a[i]);\n    return r;")
        else:
            test = "" if op == "inter" else "!"
            body = (f"    uint64_t i;\n    {c} r;\n    (void)d; (void)site;\n    memset(&r, 0, sizeof r);\n"
                    f"    for (i = 0; i < a.n; i++) if ({test}{has_}b, a.a[i])) r.a[r.n++] = a.a[i];\n    return r;")
        return f"{sig(c, function(op, t), f'rg_model_data *d, int32_t site, {c} a, {c} b')}\n{{\n{body}\n}}"
    return body_of


def subset(op: str):
    def body_of(t, k: Needs) -> str:
        c = ctype(t)
        strict = " && a.n < b.n" if op == "subset" else ""
        body = (f"    uint64_t i;\n    for (i = 0; i < a.n; i++) if (!{k.has(t)}b, a.a[i])) return false;\n"
                f"    return true{strict};")
        return f"{sig('bool', function(op, t), f'{k.data_param(t)}{c} a, {c} b')}\n{{\n{body}\n}}"
    return body_of


def cat(t, k: Needs) -> str:
    c = ctype(t)
    body = (f"    uint64_t i;\n    {c} r = a;\n    if (a.n + b.n > {k.cap(t)}) {{ {fault('site')}; r.n = 0; return r; }}\n"
            f"    for (i = 0; i < b.n; i++) r.a[a.n + i] = b.a[i];\n    r.n = a.n + b.n;\n    return r;")
    return f"{sig(c, function('cat', t), f'rg_model_data *d, int32_t site, {c} a, {c} b')}\n{{\n{body}\n}}"


def end(op: str):
    def body_of(t, k: Needs) -> str:
        c, e = ctype(t), ctype(t.element)
        at = "0" if op in ("head", "min") else "s.n - 1"
        body = (f"    {e} zero;\n    if (s.n == 0) {{ memset(&zero, 0, sizeof zero); {fault('site + 1')}; return zero; }}\n"
                f"    return s.a[{at}];")
        return f"{sig(e, function(op, t), f'rg_model_data *d, int32_t site, {c} s')}\n{{\n{body}\n}}"
    return body_of


def shrink(op: str):
    def body_of(t, k: Needs) -> str:
        c = ctype(t)
        if op == "reverse":
            body = (f"    uint64_t i;\n    {c} r = s;\n    for (i = 0; i < s.n; i++) r.a[i] = s.a[s.n - 1 - i];\n"
                    "    (void)d; (void)site;\n    return r;")
        else:
            move = "    for (i = 1; i < s.n; i++) r.a[i - 1] = s.a[i];\n" if op == "tail" else ""
            body = (f"    uint64_t i;\n    {c} r = s;\n    if (s.n == 0) {{ {fault('site + 1')}; return r; }}\n"
                    f"{move}    r.n = s.n - 1;\n    memset(&r.a[r.n], 0, sizeof r.a[0]);\n    (void)i;\n    return r;")
        return f"{sig(c, function(op, t), f'rg_model_data *d, int32_t site, {c} s')}\n{{\n{body}\n}}"
    return body_of


def canon(t, k: Needs) -> str:
    """The value an FMU input gives: at most the capacity, zeros after the last element, a set
    in canonical order (inserting never overflows: the result has at most s.n elements)."""
    c = ctype(t)
    cap = k.cap(t)
    if isinstance(t, T.SetT):
        body = (f"    uint64_t i;\n    {c} r;\n    memset(&r, 0, sizeof r);\n"
                f"    for (i = 0; i < s.n && i < {cap}; i++) {function('insert', t)}(d, 0, &r, s.a[i]);\n    return r;")
    else:
        body = (f"    uint64_t i;\n    (void)d;\n    if (s.n > {cap}) s.n = {cap};\n"
                f"    for (i = s.n; i < {cap}; i++) memset(&s.a[i], 0, sizeof s.a[i]);\n    return s;")
    return f"{sig(c, function('canon', t), f'rg_model_data *d, {c} s')}\n{{\n{body}\n}}"


def building(result: str, name: str, params: str, loop: str) -> str:
    """A function that builds its result ``r`` (zeroed first) in the one loop ``loop`` over i."""
    body = f"    uint64_t i;\n    {result} r;\n    memset(&r, 0, sizeof r);\n    {loop}\n    return r;"
    return f"{sig(result, name, params)}\n{{\n{body}\n}}"


def elems(t, k: Needs) -> str:
    c, s = ctype(t), ctype(T.SetT(t.element))
    loop = f"for (i = 0; i < q.n && !d->fault; i++) {function('insert', T.SetT(t.element))}(d, site, &r, q.a[i]);"
    return building(s, function("elems", t), f"rg_model_data *d, int32_t site, {c} q", loop)


def indices(t, k: Needs) -> str:
    loop = "for (i = 0; i < q.n; i++) r.a[r.n++] = i + 1;"
    return building("rg_set_u", function("indices", t), f"{ctype(t)} q", loop)


def pairs(t, k: Needs, result: T.Type) -> str:
    """A sequence as the set of its (index, element) pairs (of the same capacity)."""
    loop = "for (i = 0; i < q.n; i++) { r.a[i]._1 = i + 1; r.a[i]._2 = q.a[i]; } r.n = q.n;"
    return building(ctype(result), function("pairs", t), f"{ctype(t)} q", loop)


def filter_(t, k: Needs) -> str:
    c, s = ctype(t), ctype(T.SetT(t.element))
    loop = f"for (i = 0; i < q.n; i++) if ({k.has(T.SetT(t.element))}s, q.a[i])) r.a[r.n++] = q.a[i];"
    return building(c, function("filter", t), f"{k.data_param(t)}{c} q, {s} s", loop)


def extract(t, k: Needs) -> str:
    c, s = ctype(t), ctype(T.SetT(T.INT))
    loop = f"for (i = 0; i < q.n; i++) if ({function('has', T.SetT(T.INT))}(s, (int64_t)(i + 1))) r.a[r.n++] = q.a[i];"
    return building(c, function("extract", t), f"{c} q, {s} s", loop)


def range_(t, k: Needs) -> str:
    c = ctype(t)
    body = (f"    {c} r;\n    memset(&r, 0, sizeof r);\n    if (high >= low && (uint64_t)high - (uint64_t)low >= {k.cap(t)}) "
            f"{{ {fault('site')}; return r; }}\n"
            f"    for (; low <= high; low++) {{ r.a[r.n++] = low; if (low == INT64_MAX) break; }}\n    return r;")
    return f"{sig(c, function('range', t), 'rg_model_data *d, int32_t site, int64_t low, int64_t high')}\n{{\n{body}\n}}"


def fix(op: str):
    def body_of(t, k: Needs) -> str:
        c, compare = ctype(t), k.cmp(t.element)
        starts = {"prefix": ("0", "0"), "suffix": ("b.n - a.n", "b.n - a.n"), "infix": ("0", "b.n - a.n")}[op]
        body = (f"    uint64_t i, k;\n    if (a.n > b.n) return false;\n"
                f"    for (i = {starts[0]}; i <= {starts[1]}; i++) {{\n"
                f"        for (k = 0; k < a.n; k++) if ({compare}a.a[k], b.a[i + k]) != 0) break;\n"
                f"        if (k == a.n) return true;\n    }}\n    return false;")
        return f"{sig('bool', function(op, t), f'{k.data_param(t)}{c} a, {c} b')}\n{{\n{body}\n}}"
    return body_of


def injective(t, k: Needs) -> str:
    """isInjectiveSequence: no element twice."""
    c = ctype(t)
    body = (f"    uint64_t i, j;\n    for (i = 0; i < q.n; i++)\n        for (j = i + 1; j < q.n; j++)\n"
            f"            if ({k.cmp(t.element)}q.a[i], q.a[j]) == 0) return false;\n    return true;")
    return f"{sig('bool', function('injective', t), f'{k.data_param(t)}{c} q')}\n{{\n{body}\n}}"


def flatten(op: str):
    """``Union`` of a set of sets, ``dconcat`` of a sequence of sequences (robogen.ir.collections)."""
    def body_of(t, k: Needs) -> str:
        inner = t.element
        c, r = ctype(t), ctype(_outer(inner))
        if op == "Union":
            add = f"{function('insert', _outer(inner))}(d, site, &r, a.a[i].a[j])"
        else:
            add = f"{{ if (r.n >= {k.cap(_outer(inner))}) {{ {fault('site')}; return r; }} r.a[r.n++] = a.a[i].a[j]; }}"
        body = (f"    uint64_t i, j;\n    {r} r;\n    memset(&r, 0, sizeof r);\n"
                f"    for (i = 0; i < a.n && !d->fault; i++)\n        for (j = 0; j < a.a[i].n && !d->fault; j++) {add};\n    return r;")
        return f"{sig(r, function(op, t), f'rg_model_data *d, int32_t site, {c} a')}\n{{\n{body}\n}}"
    return body_of


def inter_all(t, every: list[str] | None, k: Needs) -> str:
    """``Inter`` of a set of sets: the elements of the first in all the others; of the empty set,
    every value of a finite element type (``every``), else the site's second fault."""
    inner = t.element
    c, r = ctype(t), ctype(_outer(inner))
    if every is None:
        empty = f"{fault('site + 1')}; return r;"
    elif len(every) > k.cap(_outer(inner)):  # more values than the capacity
        empty = f"{fault('site')}; return r;"
    else:
        empty = "".join(f"r.a[r.n++] = {v}; " for v in every) + "return r;"
    body = (f"    uint64_t i, j;\n    {r} r;\n    memset(&r, 0, sizeof r);\n    (void)d; (void)site;\n"
            f"    if (a.n == 0) {{ {empty} }}\n"
            f"    for (i = 0; i < a.a[0].n; i++) {{\n"
            f"        for (j = 1; j < a.n; j++) if (!{k.has(inner)}a.a[j], a.a[0].a[i])) break;\n"
            f"        if (j == a.n) r.a[r.n++] = a.a[0].a[i];\n    }}\n    return r;")
    return f"{sig(r, function('Inter', t), f'rg_model_data *d, int32_t site, {c} a')}\n{{\n{body}\n}}"


def _outer(t: T.Type) -> T.Type:
    """The outermost level's collection of ``t``'s form and elements (a nested one's type)."""
    return T.SetT(t.element) if isinstance(t, T.SetT) else T.SeqT(t.element)  # type: ignore[attr-defined]


BODIES = {
    "make": make, "canon": canon, "insert": insert, "has": has, "cat": cat, "elems": elems, "indices": indices,
    "filter": filter_, "extract": extract, "range": range_, "reverse": shrink("reverse"), "tail": shrink("tail"),
    "front": shrink("front"), "injective": injective, "Union": flatten("Union"), "dconcat": flatten("dconcat"),
    **{op: binary_set(op) for op in ("union", "inter", "diff", "symdiff")},
    **{op: subset(op) for op in ("subseteq", "subset")},
    **{op: end(op) for op in ("head", "last", "min", "max")},
    **{op: fix(op) for op in ("prefix", "suffix", "infix")},
}


__all__ = ["BODIES", "Needs", "cmp", "cmp_function", "function", "sig", "fault", "building", "inter_all", "pairs"]
