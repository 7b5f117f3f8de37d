"""What code generation supports: the concrete types of IR values, and the located error for a
construct that has no code-generation meaning yet (reported, never silently dropped)."""

from __future__ import annotations

from robogen.diagnostics import RobogenError, Span
from robogen.semantics import types as T


def not_supported(what: str, span: Span | None) -> RobogenError:
    return RobogenError.at(f"{what} is not supported for code generation", span)


def normalise(t: T.Type, given: str = "int") -> T.Type:
    """Replace given types by their concrete scalar type, recursively."""
    if isinstance(t, T.Given):
        return T.PRIMITIVES[given]
    if isinstance(t, T.RecordT):
        return T.RecordT(t.qname, tuple((n, normalise(ft, given)) for n, ft in t.fields))
    if isinstance(t, T.VectorT):
        return T.VectorT(normalise(t.element, given), t.size)
    if isinstance(t, T.MatrixT):
        return T.MatrixT(normalise(t.element, given), t.rows, t.columns)
    return t


SCALARS = (T.NAT, T.INT, T.REAL, T.BOOLEAN)


def is_scalar(t: T.Type) -> bool:
    return t in SCALARS or isinstance(t, T.EnumT)


def check_codegen_type(t: T.Type, span: Span | None, what: str) -> None:
    """Raise the not-supported error unless values of ``t`` (already normalised) have a
    representation in generated code: scalars, records of them, sized vectors and matrices."""
    if is_scalar(t):
        return
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
    raise not_supported(f"{what} of type {t.show()}", span)


__all__ = ["not_supported", "normalise", "is_scalar", "check_codegen_type", "SCALARS"]
