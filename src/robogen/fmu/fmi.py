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
import re

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


def _runtime_tolerance() -> float:
    header = (importlib.resources.files("robogen.runtime") / "robogen_runtime.h").read_text(encoding="utf-8")
    return float(re.search(r"^#define RG_TIME_RELATIVE_TOLERANCE (\S+)$", header, re.M).group(1))


#: Relative tolerance deciding that two times are the same (communication points, clock ticks,
#: the stop time): |a - b| <= TIME_TOLERANCE * max(1, |a|, |b|). The runtime header's value.
TIME_TOLERANCE = _runtime_tolerance()


def status_name(status: int) -> str:
    return STATUS_NAMES[status] if 0 <= status < len(STATUS_NAMES) else f"status {status}"


def tolerance(t: float) -> float:
    """How close to ``t`` counts as ``t``."""
    return TIME_TOLERANCE * max(1.0, abs(t))


def same_time(a: float, b: float) -> bool:
    return abs(a - b) <= TIME_TOLERANCE * max(1.0, abs(a), abs(b))


__all__ = ["OK", "WARNING", "DISCARD", "ERROR", "FATAL", "STATUS_NAMES", "INTERVAL_NOT_YET_KNOWN",
           "INTERVAL_UNCHANGED", "INTERVAL_CHANGED", "LOG_CATEGORIES", "PYTHON_FMU_LOG_CATEGORIES", "TIME_TOLERANCE",
           "status_name",
           "tolerance", "same_time"]
