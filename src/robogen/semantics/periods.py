"""Cycle periods (RoboSim reference manual, cycleDef): the value of ``cycleDef cycle == p`` and the
robogen rule that every machine, controller and module of one model has the same period."""

from __future__ import annotations

from fractions import Fraction
from typing import Iterable

from robogen.diagnostics import DiagnosticSink, Note, Span
from robogen.syntax import ast, printer


def cycle_period(c: ast.CycleDef, previous: Fraction | None, owner: str, sink: DiagnosticSink) -> Fraction | None:
    """The period p of ``cycleDef cycle == p`` (a positive number literal); ``previous`` if the
    definition is malformed. Two different periods of one owner are an error. The obsolete forms
    ``cycleDef p`` and ``cycleDef { cycle == p }`` are read as ``cycle == p``, with a warning
    (RoboTool gives none: it no longer checks cycle definitions)."""
    value = _period_expression(c.expr, sink)
    if value is None:
        sink.error("a cycle definition has the form 'cycleDef cycle == p' with p a positive number", c.expr.span)
        return previous
    if isinstance(value, ast.IntLit):
        period = Fraction(value.value)
    elif isinstance(value, ast.RealLit):
        period = Fraction(value.text)
    else:
        sink.error("the period in 'cycleDef cycle == p' must be a number literal", value.span)
        return previous
    if period <= 0:
        sink.error(f"the cycle period must be positive, not {value.text if isinstance(value, ast.RealLit) else value.value}", value.span)
        return previous
    if previous is not None and previous != period:
        sink.error(f"{owner} declares two different cycle periods", c.span)
    return period


def _period_expression(e: ast.Expr, sink: DiagnosticSink) -> ast.Expr | None:
    """The p of ``cycle == p``, of the obsolete ``p`` (a number) or ``{ cycle == p }``; None
    for any other expression."""
    if _is_cycle_equation(e):
        return e.right  # type: ignore[attr-defined]
    obsolete = None
    if isinstance(e, (ast.IntLit, ast.RealLit)):
        obsolete = e
    elif isinstance(e, ast.SetLit) and len(e.items) == 1 and _is_cycle_equation(e.items[0]):
        obsolete = e.items[0].right  # type: ignore[attr-defined]
    if obsolete is not None:
        sink.warning(f"obsolete cycle definition: read as 'cycleDef cycle == {printer.expr(obsolete)}'", e.span,
                     Note("write 'cycleDef cycle == p'"))
    return obsolete


def _is_cycle_equation(e: ast.Expr) -> bool:
    return isinstance(e, ast.Binary) and e.op == "==" and isinstance(e.left, ast.Keyword) and e.left.word == "cycle"


def declared_period(defs: Iterable[ast.CycleDef], owner: str, sink: DiagnosticSink) -> Fraction | None:
    """The period the cycle definitions of one owner declare, if any."""
    period = None
    for c in defs:
        period = cycle_period(c, period, owner, sink)
    return period


def one_period(periods: list[tuple[Fraction, str, Span | None]], sink: DiagnosticSink) -> Fraction | None:
    """robogen: the parts of one model (module, controllers, machines: ``(period, owner, span)``,
    the module first) share one period; it is the first one given."""
    if not periods:
        return None
    first, first_owner, _ = periods[0]
    for p, owner, span in periods[1:]:
        if p != first:
            sink.error(
                f"{owner} has cycle period {frac(p)}, but {first_owner} has {frac(first)}",
                span,
                Note("robogen requires one period for every machine, controller and module of a model"),
            )
    return first


def frac(f: Fraction) -> str:
    return str(f.numerator) if f.denominator == 1 else str(float(f))


__all__ = ["cycle_period", "declared_period", "one_period", "frac"]
