"""The C types of model types and the C names made from model names: the one place that makes
them (robogen.codegen.c, the collection and quantifier code and the templates use these)."""

from __future__ import annotations

import re

from robogen.ir.supported import ArrayT, FunMapT, TupleT
from robogen.semantics import types as T


def ctype(t: T.Type) -> str:
    # a string: its number among the model's strings
    if t == T.INT or t == T.STRING or isinstance(t, T.EnumT):
        return "int64_t"
    if t == T.NAT:
        return "uint64_t"
    if t == T.REAL:
        return "double"
    if t == T.BOOLEAN:
        return "bool"
    if isinstance(t, FunMapT):  # a function value: its pairs and its default (robogen.ir.functions); inside
        # collections of other capacities its pairs have that level's: rg_fun<capacity>_
        return f"rg_fun{getattr(t.pairs, 'capacity', '')}_{elem_tag(t.pair)}"
    if isinstance(t, TupleT):  # by its arity and components: a prefix code, one name per tuple type
        return f"rg_tup{len(t.fields)}_" + "_".join(elem_tag(ft) for _, ft in t.fields)
    if isinstance(t, T.RecordT):  # one inside collections of other capacities: rg_rec<level>_
        return f"rg_rec{getattr(t, 'level', 0) or ''}_" + mangle(t.qname)
    if isinstance(t, T.VectorT):
        return f"rg_vec_{tag(t.element)}_{t.size}"
    if isinstance(t, T.MatrixT):
        return f"rg_mat_{tag(t.element)}_{t.rows}_{t.columns}"
    if isinstance(t, ArrayT):
        return f"rg_arr_{tag(t.element)}_" + "x".join(map(str, t.dims))
    if isinstance(t, (T.SetT, T.SeqT)):  # a nested one of another capacity: rg_seq<capacity>_
        kind = "set" if isinstance(t, T.SetT) else "seq"
        return f"rg_{kind}{getattr(t, 'capacity', '')}_{elem_tag(t.element)}"
    raise TypeError(f"no C type for {t.show()}")


def tag(t: T.Type) -> str:
    if t == T.NAT:
        return "u"
    if t == T.REAL:
        return "r"
    if t == T.BOOLEAN:
        return "b"
    return "i"  # int and enumerations


def elem_tag(t: T.Type) -> str:
    """The part of a collection's C names that names its element type (a string: ``s``)."""
    if t == T.STRING:
        return "s"
    return ctype(t)[3:] if isinstance(t, (T.RecordT, T.SetT, T.SeqT, T.VectorT, T.MatrixT)) else tag(t)


def mangle(name: str) -> str:
    """A C identifier part for a model name (qualified names, '#', '.' become '_')."""
    return re.sub(r"[^A-Za-z0-9_]", "_", name.replace("::", "_"))


def literal(value: object, t: T.Type) -> str:
    if t == T.BOOLEAN:
        return "true" if value else "false"
    if t == T.REAL:
        f = float(value)  # type: ignore[arg-type]
        text = repr(f)
        return text if ("." in text or "e" in text or "inf" in text or "nan" in text) else text + ".0"
    v = int(value)  # type: ignore[arg-type]
    if t == T.NAT:
        return f"UINT64_C({v & ((1 << 64) - 1)})"
    v &= (1 << 64) - 1
    if v >> 63:
        return f"(int64_t)UINT64_C({v})"
    return f"INT64_C({v})"


__all__ = ["ctype", "tag", "elem_tag", "mangle", "literal"]
