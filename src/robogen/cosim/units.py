"""Units and the linear conversions between them, as FMI and SSP define them.

A unit is its SI base-unit exponents (kg, m, s, A, K, mol, cd, rad) with a factor and an offset:
a value ``x`` in the unit is ``factor * x + offset`` in SI units (FMI 3.0 section 2.4.3, SSP's
``<BaseUnit>``). A value crossing from unit ``a`` to unit ``b`` of the same exponents becomes
``a.factor / b.factor * x + (a.offset - b.offset) / b.factor``. Conversions are pairs
``(factor, offset)``; None is the identity, so that a value that needs no conversion is passed on
as it is, bit for bit.
"""

from __future__ import annotations

from dataclasses import dataclass

#: The SI base units a unit gives exponents of, in the order of FMI and SSP.
SI_BASE_UNITS = ("kg", "m", "s", "A", "K", "mol", "cd", "rad")

Scale = tuple[float, float]


@dataclass(frozen=True)
class UnitDef:
    """A unit: its name and, when known, its base unit (exponents in :data:`SI_BASE_UNITS`
    order, factor, offset). ``exponents`` None: a unit declared without a base unit, known by
    its name only."""

    name: str
    exponents: tuple[int, ...] | None = None
    factor: float = 1.0
    offset: float = 0.0

    def describe(self) -> str:
        if self.exponents is None:
            return f"'{self.name}' (no base unit)"
        dims = "*".join(f"{n}^{e}" if e != 1 else n for n, e in zip(SI_BASE_UNITS, self.exponents) if e) or "1"
        scale = f"{self.factor!r} * " if self.factor != 1.0 else ""
        shift = f" + {self.offset!r}" if self.offset != 0.0 else ""
        return f"'{self.name}' ({scale}{dims}{shift})"


class UnitMismatch(ValueError):
    """Two units between which no linear conversion exists."""


def conversion(source: UnitDef, target: UnitDef) -> Scale | None:
    """The conversion of a value in ``source`` to ``target`` (None: none needed); raises
    :class:`UnitMismatch` when they measure different things or one is known by name only."""
    if source.name == target.name and source.exponents == target.exponents \
            and (source.factor, source.offset) == (target.factor, target.offset):
        return None
    if source.exponents is None or target.exponents is None:
        raise UnitMismatch(f"cannot convert {source.describe()} to {target.describe()}: a unit without a base unit "
                           "converts only to itself")
    if source.exponents != target.exponents:
        raise UnitMismatch(f"cannot convert {source.describe()} to {target.describe()}: they measure different quantities")
    scale = (source.factor / target.factor, (source.offset - target.offset) / target.factor)
    return None if scale == (1.0, 0.0) else scale


def compose(first: Scale | None, then: Scale | None) -> Scale | None:
    """The conversion ``then`` applied after ``first``."""
    if first is None:
        return then
    if then is None:
        return first
    scale = (then[0] * first[0], then[0] * first[1] + then[1])
    return None if scale == (1.0, 0.0) else scale


def apply(scale: Scale | None, value: float) -> float:
    return value if scale is None else scale[0] * value + scale[1]
