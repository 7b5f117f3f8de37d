"""Sets and sequences in C: per element type, the functions of the collection operations the
model uses, generated into model.c. They compute what :mod:`robogen.ir.collections` computes,
step for step (the same insertion into the canonical order, the same linear membership test,
the same order of elements in every result).

A collection is a value (``rg_set_<e>`` or ``rg_seq_<e>``: a count ``n`` and an array of the
FMU's capacity, declared in config.h). A function whose result would hold more than the
capacity, or that needs an element of an empty collection, sets the model's fault code to
``RG_FAULT_COLLECTION`` and ``fault_site`` to its site (the index of the message in model.c's
``rg_sites``: the expression and its model line; the site after it for an empty collection)
and returns an empty or zero value, which the machine's run turns into ``fmi3Error``.
"""

from __future__ import annotations

from robogen.codegen.c import ctype, elem_tag
from robogen.ir import model as ir
from robogen.ir.collections import EMPTY_FAULTS, RELATION_OPS
from robogen.semantics import types as T

SET_OPS = {"union", "inter", "diff", "symdiff"}


def collection_ctype(t: T.SetT | T.SeqT) -> str:
    return ctype(t)


def typedef(t: T.SetT | T.SeqT, capacity: int) -> str:
    kind = "set (ascending, no duplicates)" if isinstance(t, T.SetT) else "sequence"
    return (f"typedef struct {{ uint64_t n; {ctype(t.element)} a[{capacity}]; }} {collection_ctype(t)};"
            f"  /* {t.show()}: a {kind} of at most {capacity} elements */")


def function(op: str, t: T.SetT | T.SeqT) -> str:
    """The C name of operation ``op`` on (or making) collections of type ``t``."""
    return f"rg_{op}_{collection_ctype(t)[3:]}"


def cmp_function(t: T.Type) -> str:
    return f"rg_cmp_{elem_tag(t)}"


class CollectionCode:
    """The functions model.c needs, collected while the machines are emitted: ``need(op, t)``
    for each operation on a collection type, then :meth:`text` in dependency order."""

    def __init__(self, capacity: int):
        self.capacity = capacity
        self.needed: dict[tuple[str, T.Type], None] = {}  # insertion-ordered
        self.types: dict[T.Type, None] = {}  # collection types used (for their typedefs)
        self.elements: dict[T.Type, None] = {}  # element types compared
        self.extra: dict[str, str] = {}  # C function -> its text: conversions, values that do not exist

    def need(self, op: str, t: T.SetT | T.SeqT) -> str:
        """Record that the model uses ``op`` on ``t``; the name of its C function."""
        if (op, t) not in self.needed:
            for dep, dt in _DEPENDS(op, t):
                self.need(dep, dt)
            self.needed[(op, t)] = None
            self.types[t] = None
            if op == "indices":
                self.types[T.SetT(T.NAT)] = None
            if isinstance(t.element, T.RecordT) or op != "make":
                self._element(t.element)
        return function(op, t)

    def _element(self, t: T.Type) -> None:
        if isinstance(t, T.RecordT):
            for _, ft in t.fields:
                self._element(ft)
        self.elements[t] = None

    def need_conv(self, source: T.SetT | T.SeqT, target: T.SetT | T.SeqT) -> str:
        """The function converting each number of a ``source`` collection to ``target``'s
        element type (as robogen.codegen.c converts one number)."""
        name = f"rg_conv_{collection_ctype(target)[3:]}_{elem_tag(source.element)}"
        self.types[source] = self.types[target] = None
        insert = self.need("insert", target) if isinstance(target, T.SetT) else None
        s, t = source.element, target.element
        if t == T.REAL:
            x = "(double)s.a[i]"
        elif s == T.REAL:
            x = f"rg_r_to_{'u' if t == T.NAT else 'i'}(d, s.a[i])"
        elif s == T.NAT and t == T.INT:
            x = "rg_u_to_i(s.a[i])"
        else:
            x = f"(({ctype(t)})s.a[i])"
        c = collection_ctype(target)
        store = f"{insert}(d, 0, &r, {x})" if insert else f"r.a[i] = {x}"
        count = "" if insert else "    r.n = s.n;\n"
        body = (f"    uint64_t i;\n    {c} r;\n    memset(&r, 0, sizeof r);\n{count}"
                f"    for (i = 0; i < s.n; i++) {store};\n    (void)d;\n    return r;")
        self.extra[name] = f"{_sig(c, name, f'rg_model_data *d, {collection_ctype(source)} s')}\n{{\n{body}\n}}"
        return name

    def need_relation(self, op: str, types: list, result: T.Type) -> str:
        """The function of relation operation ``op`` on arguments of ``types`` (relations: sets
        of pairs) giving ``result``, as robogen.ir.collections computes it."""
        name = f"rg_{op}_" + "_".join(ctype(t)[3:] if isinstance(t, (T.SetT, T.SeqT)) else elem_tag(t) for t in types)
        if name in self.extra:
            return name
        at = 1 if op in ("dres", "dsub") else 0
        rel = types[at]
        x, y = rel.element.field("_1"), rel.element.field("_2")
        for t in (*types, result):
            if isinstance(t, (T.SetT, T.SeqT)):
                self.types[t] = None
                self._element(t.element)
        r = ctype(result)
        params = ", ".join(f"{ctype(t)} {n}" for t, n in zip(types, "ab"))
        ins = self.need("insert", result) if isinstance(result, T.SetT) and op not in _FILTERS else ""
        lines = ["    uint64_t i, j;", f"    {r} r;", "    memset(&r, 0, sizeof r);", "    (void)d; (void)site; (void)j;"]
        A = "ab"[at]
        if op in ("dom", "ran"):
            lines.append(f"    for (i = 0; i < a.n && !d->fault; i++) {ins}(d, site, &r, a.a[i]._{1 if op == 'dom' else 2});")
        elif op == "rinv":
            lines.append(f"    for (i = 0; i < a.n && !d->fault; i++) {{ {ctype(result.element)} p; p._1 = a.a[i]._2; "
                         f"p._2 = a.a[i]._1; {ins}(d, site, &r, p); }}")
        elif op in _FILTERS:
            key, kt = ("_1", x) if op in ("dres", "dsub") else ("_2", y)
            has = self.need("has", T.SetT(kt))
            test = "" if op in ("dres", "rres") else "!"
            other = "a" if A == "b" else "b"
            lines.append(f"    for (i = 0; i < {A}.n; i++) if ({test}{has}({other}, {A}.a[i].{key})) r.a[r.n++] = {A}.a[i];")
        elif op in ("haskey", "at"):  # a function value's pairs: the (first) pair of key b
            cmp = cmp_function(x)
            found = "return true;" if op == "haskey" else "return a.a[i]._2;"
            lines = ["    uint64_t i;", f"    {r} r;", "    memset(&r, 0, sizeof r);",
                     f"    for (i = 0; i < a.n; i++) if ({cmp}(a.a[i]._1, b) == 0) {found}",
                     "    (void)d; (void)site;" if op == "haskey" else f"    {_fault('site + 1')};"]
        elif op == "rimage":
            has = self.need("has", T.SetT(x))
            lines.append(f"    for (i = 0; i < a.n && !d->fault; i++) if ({has}(b, a.a[i]._1)) {ins}(d, site, &r, a.a[i]._2);")
        elif op == "roverride":
            cmp = cmp_function(x)
            lines += [f"    for (i = 0; i < b.n && !d->fault; i++) {ins}(d, site, &r, b.a[i]);",
                      "    for (i = 0; i < a.n && !d->fault; i++) {",
                      f"        for (j = 0; j < b.n; j++) if ({cmp}(b.a[j]._1, a.a[i]._1) == 0) break;",
                      f"        if (j == b.n) {ins}(d, site, &r, a.a[i]);", "    }"]
        elif op == "relcomp":
            cmp = cmp_function(y)
            lines += ["    for (i = 0; i < a.n && !d->fault; i++)", "        for (j = 0; j < b.n && !d->fault; j++)",
                      f"            if ({cmp}(a.a[i]._2, b.a[j]._1) == 0) {{ {ctype(result.element)} p; p._1 = a.a[i]._1; "
                      f"p._2 = b.a[j]._2; {ins}(d, site, &r, p); }}"]
        else:  # squash: the second components, in the order of the first
            lines.append("    for (i = 0; i < a.n; i++) r.a[r.n++] = a.a[i]._2;")
        lines.append("    return r;")
        body = "\n".join(lines)
        self.extra[name] = f"{_sig(r, name, f'rg_model_data *d, int32_t site, {params}')}\n{{\n{body}\n}}"
        return name

    def fallible(self, op: str) -> bool:
        """Does the C function of ``op`` take the model data and a site (it may fail)?"""
        return op in FALLIBLE

    def call(self, e: ir.Coll, args: list[str], site: int) -> str:
        return call(self, e, args, site)

    def text(self) -> str:
        parts: dict[str, str] = {}  # by function name: an enumeration's elements are int64_t, as int's
        for t in self.elements:
            parts.setdefault(cmp_function(t), _cmp(t))
        for op, t in self.needed:
            parts.setdefault(function(op, t), _BODIES[op](t, self.capacity))
        parts.update(self.extra)
        return "\n\n".join(parts.values())


def _DEPENDS(op: str, t: T.SetT | T.SeqT) -> list[tuple[str, T.SetT | T.SeqT]]:
    s = T.SetT(t.element)
    if op in ("make", "canon") and isinstance(t, T.SetT):
        return [("insert", t)]
    if op in ("union", "symdiff"):
        return [("insert", t), ("has", t)]
    if op in ("inter", "diff", "subseteq", "subset"):
        return [("has", t)]
    if op == "elems":
        return [("insert", s)]
    if op == "filter":
        return [("has", s)]
    if op == "extract":
        return [("has", T.SetT(T.INT))]
    return []


def _sig(result: str, name: str, params: str) -> str:
    return f"static {result} {name}({params}) RG_MAYBE_UNUSED;\nstatic {result} {name}({params})"


def _fault(site: str) -> str:
    return f"d->fault = RG_FAULT_COLLECTION; d->fault_site = {site}"


def _cmp(t: T.Type) -> str:
    c = ctype(t)
    if isinstance(t, T.RecordT):
        tests = "\n".join(f"    if ((c = {cmp_function(ft)}(a.{n}, b.{n})) != 0) return c;" for n, ft in t.fields)
        body = f"    int c;\n{tests}\n    return 0;"
    else:
        body = "    return (a > b) - (a < b);"
    return f"{_sig('int', cmp_function(t), f'{c} a, {c} b')}\n{{\n{body}\n}}"


def _make(t, cap: int) -> str:
    c, e = collection_ctype(t), ctype(t.element)
    if isinstance(t, T.SetT):
        body = (f"    uint64_t i;\n    {c} s;\n    memset(&s, 0, sizeof s);\n"
                f"    for (i = 0; i < n; i++) {function('insert', t)}(d, site, &s, items[i]);\n    return s;")
    else:
        body = (f"    uint64_t i;\n    {c} s;\n    memset(&s, 0, sizeof s);\n    if (n > {cap}) {{ {_fault('site')}; return s; }}\n"
                f"    for (i = 0; i < n; i++) s.a[i] = items[i];\n    s.n = n;\n    return s;")
    return f"{_sig(c, function('make', t), f'rg_model_data *d, int32_t site, uint64_t n, const {e} *items')}\n{{\n{body}\n}}"


def _insert(t, cap: int) -> str:
    c, e = collection_ctype(t), ctype(t.element)
    body = (f"    uint64_t i, j;\n    int c = 1;\n    for (i = 0; i < s->n; i++)\n"
            f"        if ((c = {cmp_function(t.element)}(s->a[i], x)) >= 0) break;\n"
            f"    if (i < s->n && c == 0) return;\n"
            f"    if (s->n >= {cap}) {{ {_fault('site')}; return; }}\n"
            f"    for (j = s->n; j > i; j--) s->a[j] = s->a[j - 1];\n    s->a[i] = x;\n    s->n++;")
    return f"{_sig('void', function('insert', t), f'rg_model_data *d, int32_t site, {c} *s, {e} x')}\n{{\n{body}\n}}"


def _has(t, cap: int) -> str:
    c, e = collection_ctype(t), ctype(t.element)
    if isinstance(t, T.SetT):
        body = (f"    uint64_t i;\n    int c;\n    for (i = 0; i < s.n; i++)\n"
                f"        if ((c = {cmp_function(t.element)}(s.a[i], x)) >= 0) return c == 0;\n    return false;")
    else:
        body = (f"    uint64_t i;\n    for (i = 0; i < s.n; i++)\n"
                f"        if ({cmp_function(t.element)}(s.a[i], x) == 0) return true;\n    return false;")
    return f"{_sig('bool', function('has', t), f'{c} s, {e} x')}\n{{\n{body}\n}}"


def _binary_set(op: str):
    def body_of(t, cap: int) -> str:
        c = collection_ctype(t)
        has, insert = function("has", t), function("insert", t)
        if op in ("union", "symdiff"):
            keep_a = "" if op == "union" else f"if (!{has}(b, a.a[i])) "
            keep_b = "" if op == "union" else f"if (!{has}(a, b.a[i])) "
            body = (f"    uint64_t i;\n    {c} r;\n    memset(&r, 0, sizeof r);\n"
                    f"    for (i = 0; i < a.n && !d->fault; i++) {keep_a}{insert}(d, site, &r, a.a[i]);\n"
                    f"    for (i = 0; i < b.n && !d->fault; i++) {keep_b}{insert}(d, site, &r, b.a[i]);\n    return r;")
        else:
            test = "" if op == "inter" else "!"
            body = (f"    uint64_t i;\n    {c} r;\n    (void)d; (void)site;\n    memset(&r, 0, sizeof r);\n"
                    f"    for (i = 0; i < a.n; i++) if ({test}{has}(b, a.a[i])) r.a[r.n++] = a.a[i];\n    return r;")
        return f"{_sig(c, function(op, t), f'rg_model_data *d, int32_t site, {c} a, {c} b')}\n{{\n{body}\n}}"
    return body_of


def _subset(op: str):
    def body_of(t, cap: int) -> str:
        c = collection_ctype(t)
        strict = " && a.n < b.n" if op == "subset" else ""
        body = (f"    uint64_t i;\n    for (i = 0; i < a.n; i++) if (!{function('has', t)}(b, a.a[i])) return false;\n"
                f"    return true{strict};")
        return f"{_sig('bool', function(op, t), f'{c} a, {c} b')}\n{{\n{body}\n}}"
    return body_of


def _cat(t, cap: int) -> str:
    c = collection_ctype(t)
    body = (f"    uint64_t i;\n    {c} r = a;\n    if (a.n + b.n > {cap}) {{ {_fault('site')}; r.n = 0; return r; }}\n"
            f"    for (i = 0; i < b.n; i++) r.a[a.n + i] = b.a[i];\n    r.n = a.n + b.n;\n    return r;")
    return f"{_sig(c, function('cat', t), f'rg_model_data *d, int32_t site, {c} a, {c} b')}\n{{\n{body}\n}}"


def _end(op: str):
    def body_of(t, cap: int) -> str:
        c, e = collection_ctype(t), ctype(t.element)
        at = "0" if op in ("head", "min") else "s.n - 1"
        body = (f"    {e} zero;\n    if (s.n == 0) {{ memset(&zero, 0, sizeof zero); {_fault('site + 1')}; return zero; }}\n"
                f"    return s.a[{at}];")
        return f"{_sig(e, function(op, t), f'rg_model_data *d, int32_t site, {c} s')}\n{{\n{body}\n}}"
    return body_of


def _shrink(op: str):
    def body_of(t, cap: int) -> str:
        c = collection_ctype(t)
        if op == "reverse":
            body = (f"    uint64_t i;\n    {c} r = s;\n    for (i = 0; i < s.n; i++) r.a[i] = s.a[s.n - 1 - i];\n"
                    "    (void)d; (void)site;\n    return r;")
        else:
            move = "    for (i = 1; i < s.n; i++) r.a[i - 1] = s.a[i];\n" if op == "tail" else ""
            body = (f"    uint64_t i;\n    {c} r = s;\n    if (s.n == 0) {{ {_fault('site + 1')}; return r; }}\n"
                    f"{move}    r.n = s.n - 1;\n    memset(&r.a[r.n], 0, sizeof r.a[0]);\n    (void)i;\n    return r;")
        return f"{_sig(c, function(op, t), f'rg_model_data *d, int32_t site, {c} s')}\n{{\n{body}\n}}"
    return body_of


def _canon(t, cap: int) -> str:
    """The value an FMU input gives: at most the capacity, zeros after the last element, a set
    in canonical order (inserting never overflows: the result has at most s.n elements)."""
    c = collection_ctype(t)
    if isinstance(t, T.SetT):
        body = (f"    uint64_t i;\n    {c} r;\n    memset(&r, 0, sizeof r);\n"
                f"    for (i = 0; i < s.n && i < {cap}; i++) {function('insert', t)}(d, 0, &r, s.a[i]);\n    return r;")
    else:
        body = (f"    uint64_t i;\n    (void)d;\n    if (s.n > {cap}) s.n = {cap};\n"
                f"    for (i = s.n; i < {cap}; i++) memset(&s.a[i], 0, sizeof s.a[i]);\n    return s;")
    return f"{_sig(c, function('canon', t), f'rg_model_data *d, {c} s')}\n{{\n{body}\n}}"


def _building(result: str, name: str, params: str, loop: str) -> str:
    """A function that builds its result ``r`` (zeroed first) in the one loop ``loop`` over i."""
    body = f"    uint64_t i;\n    {result} r;\n    memset(&r, 0, sizeof r);\n    {loop}\n    return r;"
    return f"{_sig(result, name, params)}\n{{\n{body}\n}}"


def _elems(t, cap: int) -> str:
    c, s = collection_ctype(t), collection_ctype(T.SetT(t.element))
    loop = f"for (i = 0; i < q.n && !d->fault; i++) {function('insert', T.SetT(t.element))}(d, site, &r, q.a[i]);"
    return _building(s, function("elems", t), f"rg_model_data *d, int32_t site, {c} q", loop)


def _indices(t, cap: int) -> str:
    loop = "for (i = 0; i < q.n; i++) r.a[r.n++] = i + 1;"
    return _building("rg_set_u", function("indices", t), f"{collection_ctype(t)} q", loop)


def _filter(t, cap: int) -> str:
    c, s = collection_ctype(t), collection_ctype(T.SetT(t.element))
    loop = f"for (i = 0; i < q.n; i++) if ({function('has', T.SetT(t.element))}(s, q.a[i])) r.a[r.n++] = q.a[i];"
    return _building(c, function("filter", t), f"{c} q, {s} s", loop)


def _extract(t, cap: int) -> str:
    c, s = collection_ctype(t), collection_ctype(T.SetT(T.INT))
    loop = f"for (i = 0; i < q.n; i++) if ({function('has', T.SetT(T.INT))}(s, (int64_t)(i + 1))) r.a[r.n++] = q.a[i];"
    return _building(c, function("extract", t), f"{c} q, {s} s", loop)


def _range(t, cap: int) -> str:
    c = collection_ctype(t)
    body = (f"    {c} r;\n    memset(&r, 0, sizeof r);\n    if (high >= low && (uint64_t)high - (uint64_t)low >= {cap}) "
            f"{{ {_fault('site')}; return r; }}\n"
            f"    for (; low <= high; low++) {{ r.a[r.n++] = low; if (low == INT64_MAX) break; }}\n    return r;")
    return f"{_sig(c, function('range', t), 'rg_model_data *d, int32_t site, int64_t low, int64_t high')}\n{{\n{body}\n}}"


def _fix(op: str):
    def body_of(t, cap: int) -> str:
        c = collection_ctype(t)
        cmp = cmp_function(t.element)
        starts = {"prefix": ("0", "0"), "suffix": ("b.n - a.n", "b.n - a.n"), "infix": ("0", "b.n - a.n")}[op]
        body = (f"    uint64_t i, k;\n    if (a.n > b.n) return false;\n"
                f"    for (i = {starts[0]}; i <= {starts[1]}; i++) {{\n"
                f"        for (k = 0; k < a.n; k++) if ({cmp}(a.a[k], b.a[i + k]) != 0) break;\n"
                f"        if (k == a.n) return true;\n    }}\n    return false;")
        return f"{_sig('bool', function(op, t), f'{c} a, {c} b')}\n{{\n{body}\n}}"
    return body_of


_BODIES = {
    "make": _make, "canon": _canon, "insert": _insert, "has": _has, "cat": _cat, "elems": _elems, "indices": _indices,
    "filter": _filter, "extract": _extract, "range": _range, "reverse": _shrink("reverse"), "tail": _shrink("tail"),
    "front": _shrink("front"), **{op: _binary_set(op) for op in SET_OPS},
    **{op: _subset(op) for op in ("subseteq", "subset")},
    **{op: _end(op) for op in ("head", "last", "min", "max")},
    **{op: _fix(op) for op in ("prefix", "suffix", "infix")},
}

assert set(EMPTY_FAULTS) <= set(_BODIES)

# operations whose C function takes the model data and a site: they can fail (or build a result)
_FILTERS = ("dres", "dsub", "rres", "rsub")

FALLIBLE = {*RELATION_OPS, "undefined", "conv", "set", "seq", "union", "inter", "diff", "symdiff", "cat", "head", "last", "tail", "front", "reverse",
            "elems", "range", "min", "max"}


def call(code: CollectionCode, e: ir.Coll, args: list[str], site: int) -> str:
    """The C expression of collection operation ``e`` on the C expressions ``args``."""
    op = e.op
    if op in ("set", "seq"):
        t = e.type
        assert isinstance(t, (T.SetT, T.SeqT))
        items = f"(const {ctype(t.element)}[]){{ {', '.join(args)} }}" if args else "NULL"
        return f"{code.need('make', t)}(d, {site}, {len(args)}, {items})"
    if op in ("in", "notin"):
        test = f"{code.need('has', e.args[1].type)}({args[1]}, {args[0]})"  # type: ignore[arg-type]
        return test if op == "in" else f"(!{test})"
    if op == "size":
        return f"(({args[0]}).n)"
    if op == "nonempty":
        return f"(({args[0]}).n > 0)"
    if op == "range":
        return f"{code.need('range', e.type)}(d, {site}, {args[0]}, {args[1]})"  # type: ignore[arg-type]
    if op in RELATION_OPS:
        name = code.need_relation(op, [a.type for a in e.args], e.type)
        return f"{name}(d, {site}, {', '.join(args)})"
    if op == "conv":
        return f"{code.need_conv(e.args[0].type, e.type)}(d, {args[0]})"  # type: ignore[arg-type]
    if op == "undefined":  # a run-time error in place of a value of type e.type
        shaped = isinstance(e.type, (T.SetT, T.SeqT, T.VectorT, T.MatrixT))  # elem_tag names only scalars and records
        name = f"rg_undefined_{ctype(e.type)[3:] if shaped else elem_tag(e.type)}"
        c = ctype(e.type)
        code.extra[name] = (f"{_sig(c, name, 'rg_model_data *d, int32_t site')}\n{{\n    {c} zero;\n"
                                f"    memset(&zero, 0, sizeof zero);\n    {_fault('site')};\n    return zero;\n}}")
        return f"{name}(d, {site})"
    name = code.need(op, e.args[0].type)  # type: ignore[arg-type]
    if op in FALLIBLE:
        return f"{name}(d, {site}, {', '.join(args)})"
    return f"{name}({', '.join(args)})"


__all__ = ["CollectionCode", "collection_ctype", "typedef", "function", "call", "FALLIBLE", "SET_OPS"]
