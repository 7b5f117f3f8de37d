"""FMI 3.0 constants robogen's Python side needs, the one time tolerance and the log categories.

The status codes and interval qualifiers are the values of the standard's C enumerations
(``fmi3Status``, ``fmi3IntervalQualifier``); the master, the Python-FMU slave and the tests take
them from here. The time tolerance is the C runtime's ``RG_TIME_RELATIVE_TOLERANCE``
(``robogen_runtime.h``), read from that header: generated FMUs, the master's engine (which gets
it in its plan) and the Python side use that one value. The log categories are defined here; the
C tables that name them (the runtime's, the Python-FMU shim's) are checked against this one by
tests/fmu/test_fmi.py.
"""

from __future__ import annotations

import importlib.resources
import math
import re
from fractions import Fraction
from typing import Iterable

#: fmi3Status
OK, WARNING, DISCARD, ERROR, FATAL = range(5)
STATUS_NAMES = ("fmi3OK", "fmi3Warning", "fmi3Discard", "fmi3Error", "fmi3Fatal")

#: fmi3IntervalQualifier
INTERVAL_NOT_YET_KNOWN, INTERVAL_UNCHANGED, INTERVAL_CHANGED = range(3)

#: The log categories of robogen's FMUs, in the order of <LogCategories>, with what each logs.
#: A generated FMU declares all four (the runtime's RG_LOG_* categories); a Python FMU all but
#: logTransitions (:data:`PYTHON_FMU_LOG_CATEGORIES`: it has no state machine).
LOG_CATEGORIES = {
    "logEvents": "clock activations, event iterations, mode changes",
    "logTransitions": "transitions taken by the state machines",
    "logStatusWarning": "warnings",
    "logStatusError": "errors: every fmi3Error explains itself here",
}
PYTHON_FMU_LOG_CATEGORIES = tuple(c for c in LOG_CATEGORIES if c != "logTransitions")


def _runtime_define(name: str) -> str:
    header = (importlib.resources.files("robogen.runtime") / "robogen_runtime.h").read_text(encoding="utf-8")
    return re.search(rf"^#define {name} (\S+)$", header, re.M).group(1)


#: Relative tolerance deciding that two times are the same (communication points, clock ticks,
#: the stop time): |a - b| <= TIME_TOLERANCE * max(1, |a|, |b|). The runtime header's value.
TIME_TOLERANCE = float(_runtime_define("RG_TIME_RELATIVE_TOLERANCE"))


def status_name(status: int) -> str:
    return STATUS_NAMES[status] if 0 <= status < len(STATUS_NAMES) else f"status {status}"


#: Times are told apart down to this many units in the last place (the runtime header's RG_TIME_ULPS).
TIME_ULPS = int(_runtime_define("RG_TIME_ULPS"))


def decimal_fraction(x: float) -> Fraction:
    """The number a time was written as: the shortest decimal that reads back as ``x`` (0.1 is
    1/10, not the binary fraction nearest to it)."""
    return Fraction(repr(float(x)))


def time_resolution(values: Iterable[float]) -> float | None:
    """The time resolution of a run (or of an FMU): the greatest common divisor of the given
    positive times (the communication step, the periodic clocks' intervals and shifts), each read
    as the decimal it was written as; every grid point and clock tick is an integer number of
    resolutions from the start. None without any."""
    fractions = [decimal_fraction(v) for v in values if v and math.isfinite(v) and v > 0]
    if not fractions:
        return None
    denominator = math.lcm(*(f.denominator for f in fractions))
    numerator = math.gcd(*(f.numerator * (denominator // f.denominator) for f in fractions))
    return numerator / denominator


def tolerance(t: float, resolution: float | None = None) -> float:
    """How close to ``t`` counts as ``t``: TIME_TOLERANCE relative to ``t`` (absolute below 1 s),
    but never a quarter of the ``resolution`` or more (so that on a long horizon two grid points or
    ticks are never taken for one: 1e7 + 0.01 is not 1e7), and never less than TIME_ULPS units in
    the last place of ``t`` (what doubles can tell apart there)."""
    scale = max(1.0, abs(t))
    close = TIME_TOLERANCE * scale
    if resolution is not None:
        close = min(close, resolution / 4)
    return max(close, TIME_ULPS * math.ulp(scale))


def same_time(a: float, b: float, resolution: float | None = None) -> bool:
    return abs(a - b) <= tolerance(max(abs(a), abs(b)), resolution)


def resolvable(step: float, t: float) -> bool:
    """Whether doubles tell ``t`` and ``t + step`` apart with room to spare: the step is more than
    4 TIME_ULPS units in the last place of ``t`` (a quarter of it, the tolerance, is then above them)."""
    return step > 4 * TIME_ULPS * math.ulp(max(1.0, abs(t)))


__all__ = ["OK", "WARNING", "DISCARD", "ERROR", "FATAL", "STATUS_NAMES", "INTERVAL_NOT_YET_KNOWN",
           "INTERVAL_UNCHANGED", "INTERVAL_CHANGED", "LOG_CATEGORIES", "PYTHON_FMU_LOG_CATEGORIES", "TIME_TOLERANCE",
           "status_name", "tolerance", "same_time", "TIME_ULPS", "decimal_fraction", "time_resolution", "resolvable"]
