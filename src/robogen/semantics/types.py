"""Semantic types of RoboChart/RoboSim and the built-in library (core types and toolkits).

Types are frozen values. ``UNKNOWN`` stands for the type of an expression that already failed
to check: it is compatible with everything, so one mistake gives one message.

Compatibility is structural where RoboTool's translations rely on it: two enumerations with the
same literals, two records with the same fields, or two given types of the same simple name are
the same type (the RoboChart-to-RoboSim translation re-declares types in other packages).

Where two types have different forms, they are compared as RoboTool's type provider compares
them, through their *general* form (:func:`general`): a relation or function is a set of pairs,
a sequence a set of (index, element) pairs, a vector of known size a product. The type of a
named function used as a value has a product domain even for one parameter (RoboTool's, so
that ``f(x: nat, y: nat)`` and ``f(p: nat * nat)`` differ); a product of one component is
therefore taken to be that component. Generic toolkit functions are typed by :func:`unify`
and :func:`instantiate` over their type variables ``?X``.
"""

from __future__ import annotations

from dataclasses import dataclass


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
    items: tuple[Type, ...]  # none: the type of the empty tuple (||)

    def show(self) -> str:
        return " * ".join(_paren(t) for t in self.items) if self.items else "empty product"


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
    a, b = single(a), single(b)
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


def assignable(value: Type, target: Type, narrow: bool = True) -> bool:
    """May a value of type ``value`` be stored where ``target`` is expected?

    Numbers widen (nat -> int -> real) and int narrows to nat (checked at run time, as
    RoboChart models write ``n = n - 1`` for a nat ``n``; not with ``narrow`` False, which is
    RoboTool's ``typeCompatible``: numbers only widen); real never narrows to an integer type.
    Types of different forms are compared through their general forms.
    """
    value, target = single(value), single(target)
    if value is target:  # every rule below holds for a type and itself (the common case: one symbol's type)
        return True
    if value in NUMERIC and target in NUMERIC:
        return not (value == REAL and target != REAL) and (narrow or not (value == INT and target == NAT))
    if isinstance(value, VectorT) and isinstance(target, VectorT):
        return assignable(value.element, target.element, narrow) and (
            value.size is None or target.size is None or value.size == target.size
        )
    if isinstance(value, MatrixT) and isinstance(target, MatrixT):
        return assignable(value.element, target.element, narrow) and all(
            a is None or b is None or a == b for a, b in ((value.rows, target.rows), (value.columns, target.columns))
        )
    if isinstance(value, (SetT, SeqT)) and type(value) is type(target):
        return assignable(value.element, target.element, narrow)  # type: ignore[attr-defined]
    if isinstance(value, ProductT) and isinstance(target, ProductT):
        return len(value.items) == len(target.items) and all(assignable(v, t, narrow) for v, t in zip(value.items, target.items))
    if isinstance(value, FunctionT) and isinstance(target, FunctionT):
        return assignable(value.domain, target.domain, narrow) and assignable(value.range, target.range, narrow)
    if same(value, target):
        return True
    general_value, general_target = general(value), general(target)
    if (general_value, general_target) != (value, target) and type(general_value) is type(general_target):
        return assignable(general_value, general_target, narrow)
    return False


def _holds_unknown(t: Type) -> bool:
    """Does ``t`` hold the element type of ``{}`` or ``<>`` (``Seq(Seq(?))`` of ``<<>>``)?"""
    t = single(t)
    if isinstance(t, UnknownT):
        return True
    if isinstance(t, (SetT, SeqT)):
        return _holds_unknown(t.element)
    if isinstance(t, ProductT):
        return any(_holds_unknown(x) for x in t.items)
    return False


def element_join(t: Type, it: Type) -> Type | None:
    """The type of the elements of an enumeration (``{a, b}``, ``<a, b>``) whose elements so far
    have type ``t`` and whose next one has type ``it``, or None if they have none: numbers join
    (``<0, -1>`` is a Seq(int), not a Seq(nat) that would wrap -1); other types as RoboTool's type
    provider (``typeFor(SetExp)``): the next element's type where the type so far widens to it
    (``{ {1}, {-1} }`` is a Set(Set(int))), else the type so far where the next fits in it."""
    if t in NUMERIC and it in NUMERIC:
        return numeric_join(t, it)
    if _holds_unknown(it) and assignable(it, t):  # <q, <<>>>: an empty collection takes the typed one's type
        return t
    if _holds_unknown(t) and assignable(t, it):
        return it
    if assignable(t, it, narrow=False):
        return it
    if assignable(it, t):
        return t
    if assignable(t, it):
        return it
    return None


def widens(a: Type, b: Type) -> bool:
    """Is number type ``a`` a part of number type ``b`` (nat of int, nat and int of real)?"""
    return a in NUMERIC and b in NUMERIC and a != b and (b == REAL or (a == NAT and b == INT))


def receivable(event: Type, variable: Type) -> bool:
    """May ``e?x`` receive a value of ``event``'s type into a variable of type ``variable``? If
    it may be stored there, and also (RoboChartValidator, InputCommunicationTypeError:
    ``typeCompatible(parameter.type, event.type)``) if the variable's type fits the event's: a
    real event into an int variable (the value converted, an out-of-range one a run-time error)."""
    return assignable(event, variable) or assignable(variable, event)


def comparable(a: Type, b: Type) -> bool:
    """May ``a == b`` be asked?"""
    if a in NUMERIC and b in NUMERIC:
        return True
    return assignable(a, b) or assignable(b, a)


# ---------------------------------------------------------------------------- general forms


def single(t: Type) -> Type:
    """A product of one component is that component (see the module docstring)."""
    while isinstance(t, ProductT) and len(t.items) == 1:
        t = t.items[0]
    return t


def same_form(a: Type, b: Type) -> bool:
    """Are two types of one form (two sets, two primitive types, ...)? A type that failed to
    check, or a type variable, is of every form."""
    a, b = single(a), single(b)
    return isinstance(a, (UnknownT, TypeVarT)) or isinstance(b, (UnknownT, TypeVarT)) or type(a) is type(b)


def general(t: Type) -> Type:
    """The general form of a type (RoboTool's ``getGeneralType``): a relation or function
    ``X <-> Y`` is the set of pairs ``Set(X * Y)``; a sequence ``Seq(X)`` the set of its
    (index, element) pairs ``Set(nat * X)`` (RoboTool writes ``X * nat``; the order here is the
    one ``dom`` and ``ran`` of a sequence need); a vector of known size n the product of n
    elements. Other types are their own general form."""
    if isinstance(t, FunctionT):
        return SetT(ProductT((t.domain, t.range)))
    if isinstance(t, SeqT):
        return SetT(ProductT((NAT, t.element)))
    if isinstance(t, VectorT) and t.size is not None:
        return ProductT((t.element,) * t.size)
    return t


# ---------------------------------------------------------------------------- type variables


def unify(param: Type, arg: Type, bindings: dict[str, Type]) -> bool:
    """Can a value of type ``arg`` be passed where ``param`` (with type variables ``?X``) is
    expected? Binds the variables in ``bindings`` as it goes, so that the parameters of one call
    agree: a variable bound to ``nat`` widens to ``int`` or ``real`` if a later argument needs it.
    Values that failed to check (``UNKNOWN``) fit anything."""
    param, arg = single(param), single(arg)
    if isinstance(param, TypeVarT):
        bound = bindings.get(param.name)
        if bound is None or isinstance(bound, (UnknownT, TypeVarT)):
            bindings[param.name] = arg
            return True
        if bound in NUMERIC and arg in NUMERIC:
            bindings[param.name] = numeric_join(bound, arg)
            return True
        if assignable(arg, bound):
            if _holds_unknown(bound) and not _holds_unknown(arg):
                bindings[param.name] = arg  # concat(<<>>, q): the typed argument decides what <<>> left open
            return True
        if assignable(bound, arg):
            bindings[param.name] = arg
            return True
        return False
    if isinstance(arg, (UnknownT, TypeVarT)):
        return True
    if type(param) is type(arg):
        if isinstance(param, (SetT, SeqT, VectorT, MatrixT)):
            return unify(param.element, arg.element, bindings) and assignable(arg, instantiate(param, bindings))  # type: ignore[attr-defined]
        if isinstance(param, ProductT):
            return len(param.items) == len(arg.items) and all(unify(p, a, bindings) for p, a in zip(param.items, arg.items))  # type: ignore[attr-defined]
        if isinstance(param, FunctionT):
            return unify(param.domain, arg.domain, bindings) and unify(param.range, arg.range, bindings)  # type: ignore[attr-defined]
        return assignable(arg, param)
    general_param, general_arg = general(param), general(arg)
    if (general_param, general_arg) != (param, arg) and type(general_param) is type(general_arg):
        return unify(general_param, general_arg, bindings)
    return False


def instantiate(t: Type, bindings: dict[str, Type]) -> Type:
    """``t`` with its bound type variables replaced (unbound ones stay: they fit anything)."""
    if isinstance(t, TypeVarT):
        return bindings.get(t.name, t)
    if isinstance(t, SetT):
        return SetT(instantiate(t.element, bindings))
    if isinstance(t, SeqT):
        return SeqT(instantiate(t.element, bindings))
    if isinstance(t, ProductT):
        return ProductT(tuple(instantiate(x, bindings) for x in t.items))
    if isinstance(t, FunctionT):
        return FunctionT(instantiate(t.domain, bindings), instantiate(t.range, bindings), t.relation)
    if isinstance(t, VectorT):
        return VectorT(instantiate(t.element, bindings), t.size)
    if isinstance(t, MatrixT):
        return MatrixT(instantiate(t.element, bindings), t.rows, t.columns)
    return t


def form(t: Type, plural: bool = False) -> str:
    """How messages name the form of a type: "a set", "sequences", "a relation", "a number"."""
    if isinstance(t, FunctionT):
        word = "relation" if t.relation else "function"
    elif isinstance(t, (SetT, SeqT, ProductT, VectorT, MatrixT)):
        word = {SetT: "set", SeqT: "sequence", ProductT: "tuple", VectorT: "vector", MatrixT: "matrix"}[type(t)]
    elif t in NUMERIC:
        word = "number"
    else:
        return t.show()
    if plural:
        return "matrices" if word == "matrix" else word + "s"
    return f"a {word}"
