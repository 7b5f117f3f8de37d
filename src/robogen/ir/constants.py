"""Values of model constants at generation time: a ``--set NAME=VALUE`` text, or the constant's
initialiser evaluated over literals, enumeration literals and other constants, or, for a constant
the model leaves without a value, the default value of its type (the start value of the FMU
parameter it becomes, which an importer sets in Initialization Mode)."""

from __future__ import annotations

from fractions import Fraction

from robogen.diagnostics import RobogenError, Span
from robogen.ir import model as ir
from robogen.ir.supported import ArrayT, is_scalar, not_supported
from robogen.semantics import types as T
from robogen.semantics.model import EnumLitSym, SemanticModel, VarSym
from robogen.syntax import ast


def parse_setting(text: str, t: T.Type, span: Span | None, name: str) -> object:
    """The value of ``--set name=text`` for a constant of type ``t`` (a located error if the text
    is not a value of that type)."""
    if t == T.STRING:  # the text as it is, or written as a RoboChart literal "..."
        return text[1:-1] if len(text) >= 2 and text[0] == text[-1] == '"' else text
    text = text.strip()
    try:
        if t == T.BOOLEAN:
            if text not in ("true", "false"):
                raise ValueError
            return text == "true"
        if t == T.REAL:
            return Fraction(text)
        if t in (T.INT, T.NAT):
            v = int(text)
            if t == T.NAT and v < 0:
                raise ValueError
            return v
        if isinstance(t, T.EnumT):
            lit = text.rsplit("::", 1)[-1]
            return t.literals.index(lit)
    except (ValueError, ArithmeticError):
        pass
    raise RobogenError.at(f"--set {name}={text}: not a value of type {t.show()}", span)


def default_value(t: T.Type, real_zero: object = Fraction(0)) -> object:
    """The default value of type ``t``, which a constant without a value starts with (and the
    interpreter's memory, with ``real_zero`` 0.0): 0, 0.0, false, the first enumeration literal,
    and for records, vectors and matrices that of each part (a record is a dict, a vector or
    matrix a row-major list)."""
    if t == T.REAL:
        return real_zero
    if t == T.BOOLEAN:
        return False
    if t == T.STRING:
        return ""  # a string is one of the model's literals; "" is the first of them in C
    if isinstance(t, T.RecordT):
        return {n: default_value(ft, real_zero) for n, ft in t.fields}
    if isinstance(t, (T.VectorT, T.MatrixT)):
        size = t.size if isinstance(t, T.VectorT) else (t.rows or 0) * (t.columns or 0)
        return [default_value(t.element, real_zero) for _ in range(size or 0)]
    if isinstance(t, (T.SetT, T.SeqT)):
        return []  # the empty set or sequence
    if isinstance(t, ArrayT):  # an FMI array variable
        return [default_value(t.element, real_zero) for _ in range(t.size)]
    return 0  # nat, int, and the first literal of an enumeration


def default_expr(t: T.Type, span: Span | None = None) -> ir.Expr:
    """The default value of type ``t`` as an IR expression (a record literal's omitted fields):
    :func:`default_value` as a literal, the empty set or sequence, and that of each part of a
    record, vector or matrix."""
    if isinstance(t, T.RecordT):
        return ir.RecordLit(t, tuple((n, default_expr(ft, span)) for n, ft in t.fields))
    if isinstance(t, (T.VectorT, T.MatrixT)):
        size = t.size if isinstance(t, T.VectorT) else (t.rows or 0) * (t.columns or 0)
        return ir.VectorLit(t, tuple(default_expr(t.element, span) for _ in range(size or 0)))
    if isinstance(t, (T.SetT, T.SeqT)):
        return ir.Coll(t, "set" if isinstance(t, T.SetT) else "seq", (), "{}" if isinstance(t, T.SetT) else "<>", span)
    if is_scalar(t) or t in (T.REAL, T.BOOLEAN, T.STRING):
        return ir.Lit(t, default_value(t))
    raise not_supported(f"a record literal that leaves out a field of type {t.show()}", span)


def shown(value: object, t: T.Type) -> str:
    """A start value as the model would write it (for messages)."""
    if t == T.REAL:
        return repr(float(value))  # type: ignore[arg-type]
    if t == T.BOOLEAN:
        return "true" if value else "false"
    if isinstance(t, T.EnumT):
        return f"{t.qname}::{t.literals[value]}" if t.literals else "?"  # type: ignore[index]
    if isinstance(t, (T.RecordT, T.VectorT, T.MatrixT)):
        return "zero"
    if t == T.STRING:
        return '""' if not value else f'"{value}"'
    return str(value)


def constant_value(e: ast.Expr, t: T.Type, model: SemanticModel, known: dict[str, object]) -> object:
    """Evaluate a constant's initialiser (None if it is not computable at generation time).
    ``known`` holds the values of the constants declared before it."""
    try:
        v = _evaluate(e, model, known)
        return _typed(v, t)
    except (KeyError, ZeroDivisionError, TypeError):
        return None


def _arith(op: str, a, b):
    """``a op b`` of numbers, or elementwise of vectors and matrices (row-major lists) of one size
    and of a number and a vector or matrix (a product of two vectors or matrices is not a
    constant: TypeError)."""
    if isinstance(a, list) or isinstance(b, list):
        if isinstance(a, list) and isinstance(b, list):
            if op not in ("+", "-") or len(a) != len(b):
                raise TypeError("not an elementwise operation")
            return [_arith(op, x, y) for x, y in zip(a, b)]
        if op != "*":
            raise TypeError("a number and a vector")
        return [_arith(op, x, b) for x in a] if isinstance(a, list) else [_arith(op, a, y) for y in b]
    if op == "/" and isinstance(a, int) and isinstance(b, int):
        q = abs(a) // abs(b)
        return q if (a >= 0) == (b >= 0) else -q
    if op == "/":
        return Fraction(a) / Fraction(b)
    return a + b if op == "+" else a - b if op == "-" else a * b


def _typed(v: object, t: T.Type) -> object:
    """A computed value as a value of ``t`` (numbers of a real type exact fractions, vectors and
    matrices row-major lists of their elements)."""
    if isinstance(t, (T.VectorT, T.MatrixT)):
        if not isinstance(v, list):
            raise TypeError("not a vector")
        return [_typed(x, t.element) for x in v]
    if t == T.REAL and isinstance(v, (int, Fraction)) and not isinstance(v, bool):
        return Fraction(v)
    if t in (T.INT, T.NAT) and isinstance(v, int) and not isinstance(v, bool):  # wrapping, as the C arithmetic
        v &= (1 << 64) - 1
        return v - (1 << 64) if t == T.INT and v >> 63 else v
    return v


def _evaluate(e: ast.Expr, model: SemanticModel, known: dict[str, object]):
    if isinstance(e, ast.IntLit):
        return e.value
    if isinstance(e, ast.RealLit):
        return Fraction(e.text)
    if isinstance(e, (ast.BoolLit, ast.StringLit)):
        return e.value
    if isinstance(e, ast.Name):
        sym = model.symbol(e)
        if isinstance(sym, EnumLitSym):
            return sym.enum.literals.index(sym.literal)  # type: ignore[attr-defined]
        if isinstance(sym, VarSym) and sym.kind == "const":
            return known[sym.name]
        raise KeyError(e.text)
    if isinstance(e, ast.VectorLit):  # row-major
        return [_evaluate(x, model, known) for row in e.rows for x in row]
    if isinstance(e, ast.Unary):
        v = _evaluate(e.operand, model, known)
        if e.op == "not":
            return not v
        return [-x for x in v] if isinstance(v, list) else -v
    if isinstance(e, ast.Binary) and e.op in ("+", "-", "*", "/"):
        return _arith(e.op, _evaluate(e.left, model, known), _evaluate(e.right, model, known))
    raise KeyError(type(e).__name__)


__all__ = ["parse_setting", "constant_value", "default_value", "default_expr", "shown"]
