"""Semantic types of RoboChart/RoboSim and the built-in library (core types and toolkits).

Types are frozen values. ``UNKNOWN`` stands for the type of an expression that already failed
to check: it is compatible with everything, so one mistake gives one message.

Compatibility is structural where RoboTool's translations rely on it: two enumerations with the
same literals, two records with the same fields, or two given types of the same simple name are
the same type (the RoboChart-to-RoboSim translation re-declares types in other packages).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Sequence


@dataclass(frozen=True, slots=True)
class Type:
    def show(self) -> str:  # pragma: no cover - overridden
        return "?"

    def __str__(self) -> str:
        return self.show()


@dataclass(frozen=True, slots=True)
class Prim(Type):
    name: str  # nat int real boolean string

    def show(self) -> str:
        return self.name


@dataclass(frozen=True, slots=True)
class Given(Type):
    qname: str

    @property
    def simple(self) -> str:
        return self.qname.rsplit("::", 1)[-1]

    def show(self) -> str:
        return self.qname


@dataclass(frozen=True, slots=True)
class RecordT(Type):
    qname: str
    fields: tuple[tuple[str, Type], ...]

    def field(self, name: str) -> Type | None:
        for n, t in self.fields:
            if n == name:
                return t
        return None

    def show(self) -> str:
        return self.qname


@dataclass(frozen=True, slots=True)
class EnumT(Type):
    qname: str
    literals: tuple[str, ...]
    literal_args: tuple[tuple[Type, ...], ...] = ()

    @property
    def simple(self) -> str:
        return self.qname.rsplit("::", 1)[-1]

    def show(self) -> str:
        return self.qname


@dataclass(frozen=True, slots=True)
class SetT(Type):
    element: Type

    def show(self) -> str:
        return f"Set({self.element.show()})"


@dataclass(frozen=True, slots=True)
class SeqT(Type):
    element: Type

    def show(self) -> str:
        return f"Seq({self.element.show()})"


@dataclass(frozen=True, slots=True)
class ProductT(Type):
    items: tuple[Type, ...]

    def show(self) -> str:
        return " * ".join(_paren(t) for t in self.items)


@dataclass(frozen=True, slots=True)
class FunctionT(Type):
    domain: Type
    range: Type
    relation: bool = False

    def show(self) -> str:
        arrow = "<->" if self.relation else "->"
        return f"{_paren(self.domain)} {arrow} {self.range.show()}"


@dataclass(frozen=True, slots=True)
class VectorT(Type):
    element: Type
    size: int | None  # None: not a literal/constant known to the checker

    def show(self) -> str:
        return f"vector({self.element.show()}, {self.size if self.size is not None else '?'})"


@dataclass(frozen=True, slots=True)
class MatrixT(Type):
    element: Type
    rows: int | None
    columns: int | None

    def show(self) -> str:
        return f"matrix({self.element.show()}, {self.rows}, {self.columns})"


@dataclass(frozen=True, slots=True)
class TypeVarT(Type):
    name: str

    def show(self) -> str:
        return f"?{self.name}"


@dataclass(frozen=True, slots=True)
class UnknownT(Type):
    def show(self) -> str:
        return "<unknown>"


def _paren(t: Type) -> str:
    return f"({t.show()})" if isinstance(t, (ProductT, FunctionT)) else t.show()


NAT, INT, REAL, BOOLEAN, STRING = Prim("nat"), Prim("int"), Prim("real"), Prim("boolean"), Prim("string")
UNKNOWN = UnknownT()
PRIMITIVES = {t.name: t for t in (NAT, INT, REAL, BOOLEAN, STRING)}
NUMERIC = (NAT, INT, REAL)


def is_numeric(t: Type) -> bool:
    return t in NUMERIC or isinstance(t, (UnknownT, TypeVarT))


def is_integral(t: Type) -> bool:
    return t in (NAT, INT) or isinstance(t, (UnknownT, TypeVarT))


def is_boolean(t: Type) -> bool:
    return t == BOOLEAN or isinstance(t, (UnknownT, TypeVarT))


def numeric_join(a: Type, b: Type) -> Type:
    """The type of a + b for numeric a, b: real if either is real, else int (nat - nat may be < 0)."""
    if isinstance(a, UnknownT) or isinstance(b, UnknownT):
        return UNKNOWN
    if REAL in (a, b):
        return REAL
    if a == NAT and b == NAT:
        return NAT
    return INT


def same(a: Type, b: Type) -> bool:
    """Structural type equality (see the module docstring)."""
    if a == b or isinstance(a, (UnknownT, TypeVarT)) or isinstance(b, (UnknownT, TypeVarT)):
        return True
    if isinstance(a, Given) and isinstance(b, Given):
        return a.simple == b.simple
    if isinstance(a, EnumT) and isinstance(b, EnumT):
        return a.literals == b.literals
    if isinstance(a, RecordT) and isinstance(b, RecordT):
        if a.qname == b.qname:  # one declaration (a recursive one refers to itself without its fields)
            return True
        return len(a.fields) == len(b.fields) and all(
            na == nb and same(ta, tb) for (na, ta), (nb, tb) in zip(a.fields, b.fields)
        )
    if type(a) is not type(b):
        return False
    if isinstance(a, (SetT, SeqT)):
        return same(a.element, b.element)  # type: ignore[attr-defined]
    if isinstance(a, ProductT):
        return len(a.items) == len(b.items) and all(same(x, y) for x, y in zip(a.items, b.items))  # type: ignore[attr-defined]
    if isinstance(a, FunctionT):
        return same(a.domain, b.domain) and same(a.range, b.range)  # type: ignore[attr-defined]
    if isinstance(a, VectorT):
        return same(a.element, b.element) and (a.size is None or b.size is None or a.size == b.size)  # type: ignore[attr-defined]
    if isinstance(a, MatrixT):
        return same(a.element, b.element)  # type: ignore[attr-defined]
    return False


def assignable(value: Type, target: Type) -> bool:
    """May a value of type ``value`` be stored where ``target`` is expected?

    Numbers widen (nat -> int -> real) and int narrows to nat (checked at run time, as
    RoboChart models write ``n = n - 1`` for a nat ``n``); real never narrows to an integer type.
    """
    if value in NUMERIC and target in NUMERIC:
        return not (value == REAL and target != REAL)
    if isinstance(value, VectorT) and isinstance(target, VectorT):
        return assignable(value.element, target.element) and (
            value.size is None or target.size is None or value.size == target.size
        )
    if isinstance(value, MatrixT) and isinstance(target, MatrixT):
        return assignable(value.element, target.element) and all(
            a is None or b is None or a == b for a, b in ((value.rows, target.rows), (value.columns, target.columns))
        )
    if isinstance(value, (SetT, SeqT)) and type(value) is type(target):
        return assignable(value.element, target.element)  # type: ignore[attr-defined]
    if isinstance(value, ProductT) and isinstance(target, ProductT):
        return len(value.items) == len(target.items) and all(assignable(v, t) for v, t in zip(value.items, target.items))
    return same(value, target)


def comparable(a: Type, b: Type) -> bool:
    """May ``a == b`` be asked?"""
    if a in NUMERIC and b in NUMERIC:
        return True
    return assignable(a, b) or assignable(b, a)


# ---------------------------------------------------------------------------- built-in library


@dataclass(frozen=True)
class Builtin:
    """A toolkit function: its package, arity, and a rule giving the result type."""

    package: str
    name: str
    arity: tuple[int, ...]
    result: Callable[[Sequence[Type]], Type | str]  # a Type, or an error message
    doc: str


def _collection_element(t: Type) -> Type | None:
    if isinstance(t, (SetT, SeqT)):
        return t.element
    if isinstance(t, (UnknownT, TypeVarT)):
        return UNKNOWN
    return None


def _same_sets(name: str):
    def rule(args: Sequence[Type]) -> Type | str:
        a, b = args
        for t in args:
            if not isinstance(t, (SetT, UnknownT, TypeVarT)):
                return f"'{name}' expects sets, not {t.show()}"
        if isinstance(a, SetT) and isinstance(b, SetT) and not same(a.element, b.element):
            if isinstance(a.element, (UnknownT, TypeVarT)):
                return b
            if not isinstance(b.element, (UnknownT, TypeVarT)):
                return f"'{name}' of sets of different types: {a.show()} and {b.show()}"
        return a if isinstance(a, SetT) and not isinstance(a.element, UnknownT) else b

    return rule


def _size(args: Sequence[Type]) -> Type | str:
    if _collection_element(args[0]) is None:
        return f"'size' expects a sequence or a set, not {args[0].show()}"
    return NAT


def _seq_element(name: str, whole: bool):
    def rule(args: Sequence[Type]) -> Type | str:
        t = args[0]
        if not isinstance(t, (SeqT, UnknownT, TypeVarT)):
            return f"'{name}' expects a sequence, not {t.show()}"
        if whole:
            return t
        return t.element if isinstance(t, SeqT) else UNKNOWN

    return rule


def _concat(args: Sequence[Type]) -> Type | str:
    a, b = args
    for t in args:
        if not isinstance(t, (SeqT, UnknownT, TypeVarT)):
            return f"'concat' expects sequences, not {t.show()}"
    return a if isinstance(a, SeqT) else b


def _elems(args: Sequence[Type]) -> Type | str:
    t = args[0]
    if not isinstance(t, (SeqT, UnknownT, TypeVarT)):
        return f"'elems' expects a sequence, not {t.show()}"
    return SetT(t.element if isinstance(t, SeqT) else UNKNOWN)


def _minmax(name: str):
    def rule(args: Sequence[Type]) -> Type | str:
        if len(args) == 1:
            element = _collection_element(args[0])
            if element is None or not is_numeric(element):
                return f"'{name}' of one argument expects a set or sequence of numbers, not {args[0].show()}"
            return element
        a, b = args
        if not (is_numeric(a) and is_numeric(b)):
            return f"'{name}' expects numbers, not {a.show()} and {b.show()}"
        return numeric_join(a, b) if not (a == NAT and b == NAT) else NAT

    return rule


def _abs(args: Sequence[Type]) -> Type | str:
    if not is_numeric(args[0]):
        return f"'abs' expects a number, not {args[0].show()}"
    return NAT if args[0] in (NAT, INT) else args[0]


def _relation_part(name: str, first: bool):
    def rule(args: Sequence[Type]) -> Type | str:
        t = args[0]
        if isinstance(t, FunctionT):
            return SetT(t.domain if first else t.range)
        if isinstance(t, SetT) and isinstance(t.element, ProductT) and len(t.element.items) == 2:
            return SetT(t.element.items[0 if first else 1])
        if isinstance(t, (UnknownT, TypeVarT)):
            return SetT(UNKNOWN)
        return f"'{name}' expects a function or relation, not {t.show()}"

    return rule


BUILTINS: dict[str, dict[str, Builtin]] = {}


def _add(b: Builtin) -> None:
    BUILTINS.setdefault(b.package, {})[b.name] = b


for _name in ("union", "inter", "diff"):
    _add(Builtin("set_toolkit", _name, (2,), _same_sets(_name), f"{_name}(Set(?X), Set(?X)): Set(?X)"))
_add(Builtin("set_toolkit", "card", (1,), _size, "card(Set(?X)): nat"))
_add(Builtin("sequence_toolkit", "size", (1,), _size, "size(Seq(?X)): nat (also accepts a set)"))
_add(Builtin("sequence_toolkit", "head", (1,), _seq_element("head", False), "head(Seq(?X)): ?X"))
_add(Builtin("sequence_toolkit", "last", (1,), _seq_element("last", False), "last(Seq(?X)): ?X"))
_add(Builtin("sequence_toolkit", "tail", (1,), _seq_element("tail", True), "tail(Seq(?X)): Seq(?X)"))
_add(Builtin("sequence_toolkit", "front", (1,), _seq_element("front", True), "front(Seq(?X)): Seq(?X)"))
_add(Builtin("sequence_toolkit", "reverse", (1,), _seq_element("reverse", True), "reverse(Seq(?X)): Seq(?X)"))
_add(Builtin("sequence_toolkit", "concat", (2,), _concat, "concat(Seq(?X), Seq(?X)): Seq(?X)"))
_add(Builtin("sequence_toolkit", "elems", (1,), _elems, "elems(Seq(?X)): Set(?X)"))
_add(Builtin("function_toolkit", "dom", (1,), _relation_part("dom", True), "dom(?X -> ?Y): Set(?X)"))
_add(Builtin("function_toolkit", "ran", (1,), _relation_part("ran", False), "ran(?X -> ?Y): Set(?Y)"))
_add(Builtin("relation_toolkit", "min", (1, 2), _minmax("min"), "min(?X, ?X): ?X, or min(Set(?X)): ?X"))
_add(Builtin("relation_toolkit", "max", (1, 2), _minmax("max"), "max(?X, ?X): ?X, or max(Set(?X)): ?X"))
_add(Builtin("relation_toolkit", "abs", (1,), _abs, "abs(?X): ?X"))

TOOLKIT_PACKAGES = frozenset(BUILTINS) | {"core"}


def builtin_named(name: str) -> list[Builtin]:
    return [pkg[name] for pkg in BUILTINS.values() if name in pkg]
