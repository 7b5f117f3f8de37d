"""Sets and sequences in C: per element type, the functions of the collection operations the
model uses, generated into model.c. They compute what :mod:`robogen.ir.collections` computes,
step for step (the same insertion into the canonical order, the same linear membership test,
the same order of elements in every result).

A collection is a value (``rg_set_<e>`` or ``rg_seq_<e>``: a count ``n`` and an array of its
capacity, declared in config.h; one nested in another collection at a level of another
capacity is ``rg_set<capacity>_<e>``). A function whose result would hold more than the
capacity, or that needs an element of an empty collection, sets the model's fault code to
``RG_FAULT_COLLECTION`` and ``fault_site`` to its site (the index of the message in model.c's
``rg_sites``: the expression and its model line; the site after it for its second fault) and
returns an empty or zero value, which the machine's run turns into ``fmi3Error``. Where the
elements hold strings, the functions that compare them take the model data first (a string is
ordered by its text: ``rg_text``).

The bodies of the operations are :mod:`robogen.codegen.collection_ops`'s; relations, with
``iter``, :mod:`robogen.codegen.relations`'.
"""

from __future__ import annotations

from robogen.codegen import collection_ops as O
from robogen.codegen.cnames import ctype, elem_tag, literal, mangle
from robogen.codegen.relations import relation_body
from robogen.ir import model as ir
from robogen.ir.collections import EMPTY_FAULTS, RELATION_OPS, all_values
from robogen.ir.supported import holds_string
from robogen.semantics import types as T

SET_OPS = {"union", "inter", "diff", "symdiff"}
function = O.function
cmp_function = O.cmp_function


def collection_ctype(t: T.SetT | T.SeqT) -> str:
    return ctype(t)


def typedef(t: T.SetT | T.SeqT, capacity: int) -> str:
    kind = "set (ascending, no duplicates)" if isinstance(t, T.SetT) else "sequence"
    return (f"typedef struct {{ uint64_t n; {ctype(t.element)} a[{capacity}]; }} {collection_ctype(t)};"
            f"  /* {t.show()}: a {kind} of at most {capacity} elements */")


class CollectionCode:
    """The functions model.c needs, collected while the machines are emitted: ``need(op, t)``
    for each operation on a collection type, then :meth:`text` in dependency order."""

    def __init__(self, fmu: ir.Fmu):
        self.capacity = fmu.capacity
        self.capacity_of = fmu.capacity_of
        self.needed: dict[tuple[str, T.Type], None] = {}  # insertion-ordered
        self.types: dict[T.Type, None] = {}  # collection types used (for their typedefs)
        self.elements: dict[T.Type, None] = {}  # element types compared
        self.extra: dict[str, str] = {}  # C function -> its text: conversions, relations, values that do not exist

    # -- what the bodies need (collection_ops.Needs)

    def cap(self, t: T.Type) -> int:
        return self.capacity_of(t)

    def data_param(self, t: T.Type) -> str:
        """The model data as the first parameter of a function comparing elements of ``t`` (a
        collection: of its elements) where they hold strings."""
        return "const rg_model_data *d, " if holds_string(t) else ""

    def data_arg(self, t: T.Type) -> str:
        return "d, " if holds_string(t) else ""

    def cmp(self, t: T.Type) -> str:
        self._element(t)
        return f"{cmp_function(t)}({self.data_arg(t)}"

    def has(self, t: T.Type) -> str:
        return f"{self.need('has', t)}({self.data_arg(t)}"

    @property
    def texts(self) -> bool:
        """Whether a comparison reads the text of strings (model.c needs rg_text)."""
        return any(t == T.STRING for t in self.elements)

    # -- collecting

    def need(self, op: str, t: T.SetT | T.SeqT) -> str:
        """Record that the model uses ``op`` on ``t``; the name of its C function."""
        if (op, t) not in self.needed:
            for dep, dt in _depends(op, t):
                self.need(dep, dt)
            self.needed[(op, t)] = None
            self.types[t] = None
            if op == "indices":
                self.types[T.SetT(T.NAT)] = None
            if op in ("Union", "Inter", "dconcat"):
                self.types[_outer(t.element)] = None
            if isinstance(t.element, (T.RecordT, T.SetT, T.SeqT, T.VectorT, T.MatrixT)) or op != "make":
                self._element(t.element)
        return function(op, t)

    def _element(self, t: T.Type) -> None:
        if t in self.elements:
            return
        if isinstance(t, T.RecordT):
            for _, ft in t.fields:
                self._element(ft)
        elif isinstance(t, (T.SetT, T.SeqT, T.VectorT, T.MatrixT)):
            self._element(t.element)
            if isinstance(t, (T.SetT, T.SeqT)):
                self.types[t] = None
        self.elements[t] = None

    def need_conv(self, source: T.Type, target: T.Type) -> str:
        """The function converting a value of ``source`` to ``target`` (the same form: numbers
        converted as robogen.codegen.c converts one number, collections rebuilt element by element
        with ``target``'s capacity: robogen.ir.collections.convert)."""
        name = f"rg_conv_{ctype(target)[3:]}_from_{ctype(source)[3:]}"
        if name in self.extra:
            return name
        self.extra[name] = ""  # reserved: a type converts no value of itself
        for t in (source, target):
            if isinstance(t, (T.SetT, T.SeqT)):
                self.types[t] = None
                self._element(t.element)
        c = ctype(target)
        lines = [f"    {c} r;", "    memset(&r, 0, sizeof r);", "    (void)d; (void)site;"]
        if isinstance(target, (T.SetT, T.SeqT)):
            x = self._converted("s.a[i]", source.element, target.element)  # type: ignore[attr-defined]
            if isinstance(target, T.SetT):
                store = f"{self.need('insert', target)}(d, site, &r, x);"
            else:
                store = f"if (r.n >= {self.cap(target)}) {{ {O.fault('site')}; return r; }} r.a[r.n++] = x;"
            lines = ["    uint64_t i;", *lines, "    for (i = 0; i < s.n && !d->fault; i++) {",
                     f"        {ctype(target.element)} x = {x};", "        if (d->fault) return r;", f"        {store}", "    }"]
        elif isinstance(target, T.RecordT):
            lines += [f"    r.{n} = {self._converted('s.' + n, source.field(n), ft)};"  # type: ignore[attr-defined, arg-type]
                      for n, ft in target.fields]
        else:  # a vector or a matrix
            size = target.size if isinstance(target, T.VectorT) else (target.rows or 0) * (target.columns or 0)  # type: ignore[attr-defined]
            x = self._converted("s.a[i]", source.element, target.element)  # type: ignore[attr-defined]
            lines = ["    int i;", *lines, f"    for (i = 0; i < {size}; i++) r.a[i] = {x};"]
        lines.append("    return r;")
        body = "\n".join(lines)
        self.extra.pop(name)
        self.extra[name] = f"{O.sig(c, name, f'rg_model_data *d, int32_t site, {ctype(source)} s')}\n{{\n{body}\n}}"
        return name

    def _converted(self, x: str, source: T.Type, target: T.Type) -> str:
        """The C expression of value ``x`` of ``source`` as a ``target``."""
        if source == target:
            return x
        if target == T.REAL:
            return f"(double){x}"
        if source == T.REAL:
            return f"rg_r_to_{'u' if target == T.NAT else 'i'}(d, {x})"
        if source == T.NAT and target == T.INT:
            return f"rg_u_to_i({x})"
        if source in T.NUMERIC:
            return f"(({ctype(target)}){x})"
        return f"{self.need_conv(source, target)}(d, site, {x})"

    def need_relation(self, op: str, types: list, result: T.Type) -> str:
        """The function of relation operation ``op`` on arguments of ``types`` (relations: sets
        of pairs) giving ``result``, as robogen.ir.collections computes it."""
        name = f"rg_{op}_" + "_".join(elem_tag(t) for t in types)  # (a function value's key: any type)
        if op == "iter":  # its identity relation is every value of an enumeration: one function per enumeration
            name = f"rg_iter_{ctype(types[1])[3:]}{_finite_suffix(types[1].element.field('_1'))}"
        if name not in self.extra:
            for t in (*types, result):
                if isinstance(t, (T.SetT, T.SeqT)):
                    self.types[t] = None
                    self._element(t.element)
            self.extra[name] = ""  # reserved while the functions it calls are made
            text = relation_body(op, name, types, result, self)
            self.extra.pop(name)
            self.extra[name] = text
        return name

    def need_inter(self, t: T.SetT) -> str:
        """``Inter`` of a set of sets of type ``t``."""
        name = function("Inter", t) + _finite_suffix(t.element.element)  # type: ignore[attr-defined]
        if name not in self.extra:
            self.types[t] = self.types[_outer(t.element)] = None
            self._element(t.element)
            inner = t.element.element  # type: ignore[attr-defined]
            values = all_values(inner)
            every = None if values is None else [literal(v, inner) for v in values]
            self.extra[name] = O.inter_all(t, every, self).replace(function("Inter", t) + "(", name + "(")
        return name

    def fallible(self, op: str) -> bool:
        """Does the C function of ``op`` take the model data and a site (it may fail)?"""
        return op in FALLIBLE

    def call(self, e: ir.Coll, args: list[str], site: int) -> str:
        return call(self, e, args, site)

    def text(self) -> str:
        parts: dict[str, str] = {}  # by function name: an enumeration's elements are int64_t, as int's
        for t in self.elements:
            parts.setdefault(cmp_function(t), O.cmp(t, self))
        for op, t in self.needed:
            parts.setdefault(function(op, t), O.BODIES[op](t, self))
        parts.update(self.extra)
        return "\n\n".join(parts.values())


def _finite_suffix(t: T.Type) -> str:
    """What tells apart the functions that list every value of an enumeration (Inter, iter) when
    enumerations share one C type."""
    return f"_{mangle(t.qname)}" if isinstance(t, T.EnumT) else ""


def _outer(t: T.Type) -> T.Type:
    return T.SetT(t.element) if isinstance(t, T.SetT) else T.SeqT(t.element)  # type: ignore[attr-defined]


def _depends(op: str, t: T.SetT | T.SeqT) -> list[tuple[str, T.SetT | T.SeqT]]:
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
    if op == "Union":
        return [("insert", _outer(t.element))]  # type: ignore[list-item]
    return []


# operations whose C function takes the model data and a site: they can fail (or build a result)
FALLIBLE = {*RELATION_OPS, "undefined", "conv", "set", "seq", "union", "inter", "diff", "symdiff", "cat", "head", "last", "tail",
            "front", "reverse", "elems", "range", "min", "max", "Union", "Inter", "dconcat"}
# operations whose C function compares elements without a site: the model data first where they hold strings
COMPARING = {"in", "notin", "subseteq", "subset", "prefix", "suffix", "infix", "filter", "injective"}

assert set(EMPTY_FAULTS) <= set(O.BODIES)


def call(code: CollectionCode, e: ir.Coll, args: list[str], site: int) -> str:
    """The C expression of collection operation ``e`` on the C expressions ``args``."""
    op = e.op
    if op in ("set", "seq"):
        t = e.type
        assert isinstance(t, (T.SetT, T.SeqT))
        items = f"(const {ctype(t.element)}[]){{ {', '.join(args)} }}" if args else "NULL"
        return f"{code.need('make', t)}(d, {site}, {len(args)}, {items})"
    if op in ("in", "notin"):
        test = f"{code.has(e.args[1].type)}{args[1]}, {args[0]})"
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
        return f"{code.need_conv(e.args[0].type, e.type)}(d, {site}, {args[0]})"
    if op == "Inter":
        return f"{code.need_inter(e.args[0].type)}(d, {site}, {args[0]})"  # type: ignore[arg-type]
    if op == "pairs":
        name = function("pairs", e.args[0].type)
        code.types[e.type] = None
        code.extra.setdefault(name, O.pairs(e.args[0].type, code, e.type))
        return f"{name}({args[0]})"
    if op == "undefined":  # a run-time error in place of a value of type e.type
        name = f"rg_undefined_{elem_tag(e.type)}"
        c = ctype(e.type)
        code.extra[name] = (f"{O.sig(c, name, 'rg_model_data *d, int32_t site')}\n{{\n    {c} zero;\n"
                            f"    memset(&zero, 0, sizeof zero);\n    {O.fault('site')};\n    return zero;\n}}")
        return f"{name}(d, {site})"
    t = e.args[0].type
    name = code.need(op, t)  # type: ignore[arg-type]
    if op in FALLIBLE:
        return f"{name}(d, {site}, {', '.join(args)})"
    if op in COMPARING:
        return f"{name}({code.data_arg(t.element)}{', '.join(args)})"  # type: ignore[attr-defined]
    return f"{name}({', '.join(args)})"


__all__ = ["CollectionCode", "collection_ctype", "typedef", "function", "call", "FALLIBLE", "SET_OPS"]
