"""FMI 3.0 constants robogen's Python side needs, and the one time tolerance.

The status codes and interval qualifiers are the values of the standard's C enumerations
(``fmi3Status``, ``fmi3IntervalQualifier``); the master, the Python-FMU slave and the tests take
them from here. The C runtime has its own copy of the tolerance (``RG_TIME_RELATIVE_TOLERANCE``
in ``robogen_runtime.h``), which the runtime's tests check against :data:`TIME_TOLERANCE`.
"""

from __future__ import annotations

#: fmi3Status
OK, WARNING, DISCARD, ERROR, FATAL = range(5)
STATUS_NAMES = ("fmi3OK", "fmi3Warning", "fmi3Discard", "fmi3Error", "fmi3Fatal")

#: fmi3IntervalQualifier
INTERVAL_NOT_YET_KNOWN, INTERVAL_UNCHANGED, INTERVAL_CHANGED = range(3)

#: The log categories every robogen FMU declares (Python and generated alike).
LOG_CATEGORIES = ("logEvents", "logStatusWarning", "logStatusError")

#: Relative tolerance deciding that two times are the same (communication points, clock ticks,
#: the stop time): |a - b| <= TIME_TOLERANCE * max(1, |a|, |b|).
TIME_TOLERANCE = 1e-9


def status_name(status: int) -> str:
    return STATUS_NAMES[status] if 0 <= status < len(STATUS_NAMES) else f"status {status}"


def tolerance(t: float) -> float:
    """How close to ``t`` counts as ``t``."""
    return TIME_TOLERANCE * max(1.0, abs(t))


def same_time(a: float, b: float) -> bool:
    return abs(a - b) <= TIME_TOLERANCE * max(1.0, abs(a), abs(b))


__all__ = ["OK", "WARNING", "DISCARD", "ERROR", "FATAL", "STATUS_NAMES", "INTERVAL_NOT_YET_KNOWN",
           "INTERVAL_UNCHANGED", "INTERVAL_CHANGED", "LOG_CATEGORIES", "TIME_TOLERANCE", "status_name",
           "tolerance", "same_time"]
