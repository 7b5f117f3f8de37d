"""Time grids: the communication grid and the schedules of time-based input clocks.

A point of a grid ``origin + k * period`` is computed from its index, never by adding up
periods, so the thousandth tick is where it should be. :func:`grid_index` finds the index of
the last point at or before a time, a point within the time tolerance counting as reached: from
the integer index, checked against the points themselves, so that it is exact on any horizon
(elapsed / period may be off by more than the tolerance when elapsed / period is 1e9).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from robogen.fmu.modeldesc import Variable

#: intervalVariability of the input clocks the master ticks on a fixed grid ...
PERIODIC = ("constant", "fixed", "tunable")
#: ... and of those whose next tick the FMU announces through fmi3GetIntervalDecimal.
APERIODIC = ("changing", "countdown")


def grid_index(origin: float, period: float, t: float, close: float) -> int:
    """k of the last grid point origin + k * period at or before ``t``, a point within ``close``
    of it (the time tolerance at t) counting as reached (the engine's grid_index does the same)."""
    k = math.floor((t - origin) / period)
    while origin + (k + 1) * period <= t + close:
        k += 1
    while origin + k * period > t + close:
        k -= 1
    return k


@dataclass
class Periodic:
    """A time-based periodic input clock: tick k at start + shift + k * interval (no running sum)."""

    var: Variable
    start: float
    interval: float
    shift: float
    k: int = 0

    def next_time(self) -> float:
        return self.start + self.shift + self.k * self.interval

    def ticked(self, t: float, close: float) -> None:
        """It ticked at t: the next tick is the first grid point after t (``close``: the time tolerance at t)."""
        self.k = max(self.k + 1, grid_index(self.start + self.shift, self.interval, t, close) + 1)


@dataclass
class Aperiodic:
    """A changing or countdown input clock: next tick known from fmi3GetIntervalDecimal."""

    var: Variable
    next: float | None = None

    def next_time(self) -> float:
        return math.inf if self.next is None else self.next

    def ticked(self, t: float, close: float) -> None:
        """It ticked at t: unknown until the FMU announces the next interval."""
        self.next = None
