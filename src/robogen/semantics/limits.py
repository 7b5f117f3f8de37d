"""Comparisons whose value the operands' types decide: a ``nat`` is never negative, so
``k >= 0`` is always true and ``k < 0`` always false, whatever ``k`` is.

The checker warns about such a comparison (it is usually a slip: ``k`` was meant to be an ``int``,
or the bound is wrong) and records its value in the model's tables
(:meth:`robogen.semantics.model.SemanticModel.constant_comparison`), so that code generation
can use the value instead of a comparison a C compiler would flag (``-Wtype-limits``: an
unsigned value compared with 0).

Decided here: a comparison (``<``, ``<=``, ``>``, ``>=``, ``==``, ``!=``) of an expression of type
``nat`` with a number literal (``0``, ``-1``, ``0.0``, ``-0.5``, in parentheses or not), on either
side, when every ``nat`` gives it the same value. A constant's name is not a literal: its value
may be given when the model is compiled.
"""

from __future__ import annotations

from fractions import Fraction

from robogen.semantics import types as T
from robogen.syntax import ast

def _literal(e: ast.Expr) -> int | Fraction | None:
    """The value of a number literal, possibly negated (``-1``, ``-(0.5)``): exact, an int for an
    integer literal (no Fraction made for the common ``x > 3``)."""
    sign = 1
    while isinstance(e, ast.Unary) and e.op == "-":
        sign, e = -sign, e.operand
    if isinstance(e, ast.IntLit):
        return sign * e.value
    if isinstance(e, ast.RealLit):
        return sign * Fraction(e.text)
    return None


# A comparison with the literal on the left is the mirrored comparison with it on the right.
_MIRROR = {"<": ">", "<=": ">=", ">": "<", ">=": "<=", "==": "==", "!=": "!="}


def _nat_against(op: str, c: int | Fraction) -> bool | None:
    """The value of ``n op c`` for every nat ``n`` (n >= 0), if one value holds for all."""
    if op == ">=" and c <= 0 or op == ">" and c < 0 or op == "!=" and c < 0:
        return True
    if op == "<" and c <= 0 or op == "<=" and c < 0 or op == "==" and c < 0:
        return False
    return None


def constant_comparison(e: ast.Binary, left: T.Type, right: T.Type) -> bool | None:
    """The value of comparison ``e`` when its operands' types decide it (``left`` and ``right``
    are their types), else None."""
    if e.op not in _MIRROR:
        return None
    if left == T.NAT:
        c = _literal(e.right)
        if c is not None and _literal(e.left) is None:
            return _nat_against(e.op, c)
    if right == T.NAT:
        c = _literal(e.left)
        if c is not None and _literal(e.right) is None:
            return _nat_against(_MIRROR[e.op], c)
    return None


def message(e: ast.Binary, value: bool, text) -> str:
    """The warning for a comparison whose value is ``value``; ``text`` prints an expression."""
    nat_side = e.left if _literal(e.left) is None else e.right
    shown, side = text(e), text(nat_side)
    if len(shown) > 60:
        return f"this comparison is always {str(value).lower()}: one side is a nat, and a nat is never negative"
    return f"'{shown}' is always {str(value).lower()} for nat {side}: a nat is never negative"


__all__ = ["constant_comparison", "message"]
