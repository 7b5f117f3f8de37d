"""Time grids: the communication grid and the schedules of time-based input clocks.

A point of a grid ``origin + k * period`` is computed from its index, never by adding up
periods, so the thousandth tick is where it should be. :func:`grid_index` finds the index of
the last point at or before a time, a point within the time tolerance counting as reached.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from robogen.fmu.fmi import TIME_TOLERANCE
from robogen.fmu.modeldesc import Variable

#: intervalVariability of the input clocks the master ticks on a fixed grid ...
PERIODIC = ("constant", "fixed", "tunable")
#: ... and of those whose next tick the FMU announces through fmi3GetIntervalDecimal.
APERIODIC = ("changing", "countdown")


def grid_index(elapsed: float, period: float) -> int:
    """k of the last grid point k * period at or before ``elapsed`` (time since the grid's
    origin), a point within the tolerance counting as reached."""
    return math.floor(elapsed / period + TIME_TOLERANCE)


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

    def ticked(self, t: float) -> None:
        """It ticked at t: the next tick is the first grid point after t."""
        self.k = max(self.k + 1, grid_index(t - self.start - self.shift, self.interval) + 1)


@dataclass
class Aperiodic:
    """A changing or countdown input clock: next tick known from fmi3GetIntervalDecimal."""

    var: Variable
    next: float | None = None

    def next_time(self) -> float:
        return math.inf if self.next is None else self.next

    def ticked(self, t: float) -> None:
        """It ticked at t: unknown until the FMU announces the next interval."""
        self.next = None
