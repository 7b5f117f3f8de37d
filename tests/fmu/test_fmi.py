"""One home each: the time tolerance (the runtime header's, read by Python, handed to the engine
in its plan) and the log categories (robogen.fmu.fmi, which the C tables naming them follow)."""

from __future__ import annotations

import math
import re
from importlib.resources import files

from robogen.fmu import fmi


def _text(package: str, name: str) -> str:
    return (files(package) / name).read_text(encoding="utf-8")


def test_the_time_tolerance_is_the_runtime_headers_and_nowhere_else_a_number():
    header = _text("robogen.runtime", "robogen_runtime.h")
    assert [float(v) for v in re.findall(r"#define RG_TIME_RELATIVE_TOLERANCE (\S+)", header)] == [fmi.TIME_TOLERANCE]
    assert fmi.same_time(1.0, 1.0 + 0.5 * fmi.TIME_TOLERANCE) and not fmi.same_time(1.0, 1.0 + 2 * fmi.TIME_TOLERANCE)
    # the engine gets it in its plan: its C files compute no tolerance of their own
    for name in ("engine_values.c", "engine_run.c", "engine_events.c"):
        text = re.sub(r"1e-9 \* \(double\)now\.tv_nsec", "", _text("robogen.cosim", name))  # nanoseconds
        assert not re.search(r"\b1e-9\b|TOLERANCE", text), name
    assert "time_tolerance;" in _text("robogen.cosim", "engine.h")


def test_the_c_tables_of_log_categories_follow_fmi_py():
    runtime = _text("robogen.runtime", "robogen_runtime.c")
    names = re.search(r"rg_category_names\[RG_LOG_NUM_CATEGORIES\] = \{(.*?)\};", runtime, re.S).group(1)
    assert re.findall(r'"(\w+)"', names) == list(fmi.LOG_CATEGORIES)  # generated FMUs: all four, in order
    shim = _text("robogen.pyfmu", "shim.c")
    table = re.search(r"\} categories\[\] = \{(.*?)\};", shim, re.S).group(1)
    assert re.findall(r'"(\w+)"', table) == list(fmi.PYTHON_FMU_LOG_CATEGORIES)  # Python FMUs: no transitions
    assert "logTransitions" not in fmi.PYTHON_FMU_LOG_CATEGORIES and len(fmi.LOG_CATEGORIES) == 4


def test_same_time_is_relative_past_one_second_and_capped_by_the_resolution():
    # worked from the rule: |a - b| <= TIME_TOLERANCE * max(1, |a|, |b|), but below a quarter of
    # the resolution; a gap that is not a number (inf - inf, NaN) is never one time
    tol = fmi.TIME_TOLERANCE
    assert fmi.same_time(0.25, 0.25 + tol / 2) and not fmi.same_time(0.25, 0.25 + 3 * tol)
    assert fmi.same_time(1e6, 1e6 + 1e6 * tol / 2) and not fmi.same_time(1e6, 1e6 + 3e6 * tol)
    t = 1e7
    assert fmi.same_time(t, t + t * tol / 2)                               # no resolution: t * tol
    assert not fmi.same_time(t, t + t * tol / 2, resolution=t * tol)       # capped at t * tol / 4
    assert fmi.same_time(t, t + t * tol / 8, resolution=t * tol)
    assert not fmi.same_time(math.inf, math.inf) and not fmi.same_time(math.nan, 0.0)
