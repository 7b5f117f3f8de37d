"""What code generation supports: the concrete types of IR values, and the located error for a
construct that has no code-generation meaning yet (reported, never silently dropped)."""

from __future__ import annotations

from dataclasses import dataclass

from robogen.diagnostics import RobogenError, Span
from robogen.semantics import types as T


def not_supported(what: str, span: Span | None) -> RobogenError:
    return RobogenError.at(f"{what} is not supported for code generation", span)


@dataclass(frozen=True, slots=True)
class TupleT(T.RecordT):
    """A product ``A * B`` as code generation represents it: a record whose fields ``_1``,
    ``_2``, ... are its components (``p[k]`` selects field ``_k``), so that tuples share the
    records' C structs, equality, FMI variables and interpreter values."""

    def show(self) -> str:
        return " * ".join(f"({t.show()})" if isinstance(t, TupleT) else t.show() for _, t in self.fields)


def tuple_type(items: tuple[T.Type, ...]) -> TupleT:
    """The code-generation type of a product of ``items`` (already normalised)."""
    return TupleT("tuple(" + ",".join(t.show() for t in items) + ")", tuple((f"_{i + 1}", t) for i, t in enumerate(items)))


@dataclass(frozen=True, slots=True)
class TaggedT(T.RecordT):
    """An enumeration some of whose literals carry arguments (``EM2(real)``), as code generation
    represents it: a record whose field ``tag`` is the literal (a plain enumeration of the same
    literals, so an FMI Enumeration variable) and, per argument ``k`` of literal ``L``, a field
    ``L_k``. A value sets the fields of its own literal's arguments and leaves the others at their
    type's default, so the records' equality is the literals': same literal and equal arguments;
    records give the C struct, FMI variables and interpreter values."""

    def show(self) -> str:
        return self.qname

    @property
    def tag(self) -> T.EnumT:
        t = self.fields[0][1]
        assert isinstance(t, T.EnumT)
        return t

    def arg_fields(self, literal: str) -> tuple[tuple[str, T.Type], ...]:
        """The fields of the arguments of ``literal``, in order."""
        return tuple((n, t) for n, t in self.fields[1:] if n.rsplit("_", 1)[0] == literal)


def literal_conditions(t: T.Type, path: tuple[str, ...]) -> tuple[tuple[tuple[str, ...], int], ...]:
    """When the part at ``path`` of a value of type ``t`` holds an argument of an enumeration
    literal: (path of the tag, literal index) for each tagged record on the way. An input
    assembled from FMI variables takes an argument only when its tag selects that literal, and
    the argument's default otherwise, so that equal literals are equal records (only for a
    scalar part)."""
    found = []
    for i, name in enumerate(path):
        if isinstance(t, TaggedT) and name != "tag":
            found.append((path[:i] + ("tag",), t.tag.literals.index(name.rsplit("_", 1)[0])))
        t = t.field(name) if isinstance(t, T.RecordT) else T.UNKNOWN  # type: ignore[assignment]
    return tuple(found) if is_scalar(t) else ()  # (an array argument is taken as it is)


def tagged_type(t: T.EnumT, given: str) -> TaggedT:
    tag = T.EnumT(t.qname, t.literals)
    fields = tuple((f"{lit}_{k + 1}", normalise(at, given))
                   for lit, args in zip(t.literals, t.literal_args) for k, at in enumerate(args))
    return TaggedT(t.qname, (("tag", tag),) + fields)


def normalise(t: T.Type, given: str = "int") -> T.Type:
    """Replace given types by their concrete scalar type, and products by :class:`TupleT`,
    recursively."""
    t = T.single(t)
    if isinstance(t, T.Given):
        return T.PRIMITIVES[given]
    if isinstance(t, T.UnknownT):  # the elements of a set or sequence nothing gives a type: it is empty
        return T.INT
    if isinstance(t, T.ProductT):
        return tuple_type(tuple(normalise(x, given) for x in t.items))
    if isinstance(t, T.SetT):
        return T.SetT(normalise(t.element, given))
    if isinstance(t, T.SeqT):
        return T.SeqT(normalise(t.element, given))
    if isinstance(t, T.FunctionT) and t.relation:  # a relation is the set of its pairs
        return T.SetT(tuple_type((normalise(t.domain, given), normalise(t.range, given))))
    if isinstance(t, T.FunctionT):
        return T.FunctionT(normalise(t.domain, given), normalise(t.range, given), t.relation)
    if isinstance(t, T.RecordT):  # (a tuple or a tagged enumeration keeps its class)
        return type(t)(t.qname, tuple((n, normalise(ft, given)) for n, ft in t.fields))
    if isinstance(t, T.VectorT):
        return T.VectorT(normalise(t.element, given), t.size)
    if isinstance(t, T.MatrixT):
        return T.MatrixT(normalise(t.element, given), t.rows, t.columns)
    if isinstance(t, T.EnumT) and any(t.literal_args):
        return tagged_type(t, given)
    if isinstance(t, T.EnumT) and t.literal_args:
        return T.EnumT(t.qname, t.literals)
    return t


def _holds_enum(t: T.Type, qname: str, skip_tag: bool = False) -> bool:
    """Whether a value of ``t`` contains one of enumeration ``qname`` (not counting the tag)."""
    if isinstance(t, T.EnumT):
        return t.qname == qname
    if isinstance(t, T.RecordT):
        return any(_holds_enum(ft, qname) for _, ft in (t.fields[1:] if skip_tag else t.fields))
    inner = getattr(t, "element", None)
    return inner is not None and _holds_enum(inner, qname)


SCALARS = (T.NAT, T.INT, T.REAL, T.BOOLEAN)


def is_scalar(t: T.Type) -> bool:
    return t in SCALARS or isinstance(t, T.EnumT)


def check_codegen_type(t: T.Type, span: Span | None, what: str) -> None:
    """Raise the not-supported error unless values of ``t`` (already normalised) have a
    representation in generated code: scalars, records of them, sized vectors and matrices."""
    if is_scalar(t) or t == T.STRING:  # a string: one of the model's string literals
        return
    if isinstance(t, TaggedT) and _holds_enum(t, t.qname, skip_tag=True):
        raise not_supported(f"{what}: enumeration {t.qname} whose literal's argument holds a {t.qname} "
                            "(a recursive enumeration)", span)
    if isinstance(t, T.RecordT):
        for n, ft in t.fields:
            check_codegen_type(ft, span, f"field '{n}' of {what}")
        return
    if isinstance(t, T.VectorT) and is_scalar(t.element):
        if t.size is None:
            raise not_supported(f"{what}: a vector whose size is not an integer literal", span)
        return
    if isinstance(t, T.MatrixT) and is_scalar(t.element):
        if t.rows is None or t.columns is None:
            raise not_supported(f"{what}: a matrix whose size is not given by integer literals", span)
        return
    if isinstance(t, T.FunctionT) and not t.relation:  # stored as the number of a function value
        check_codegen_type(t.domain, span, f"the domain of {what}")
        check_codegen_type(t.range, span, f"the range of {what}")
        return
    if isinstance(t, (T.SetT, T.SeqT)):
        if not (is_scalar(t.element) or isinstance(t.element, T.RecordT)):
            raise not_supported(f"{what}: a {T.form(t)[2:]} of {t.element.show()} (elements of collections are "
                                "numbers, booleans, enumerations, records or tuples)", span)
        check_codegen_type(t.element, span, f"the elements of {what}")
        return
    raise not_supported(f"{what} of type {t.show()}", span)


def is_collection(t: T.Type) -> bool:
    return isinstance(t, (T.SetT, T.SeqT))


__all__ = ["not_supported", "normalise", "is_scalar", "is_collection", "check_codegen_type", "SCALARS", "TupleT",
           "tuple_type"]
