"""One home each: the time tolerance (the runtime header's, read by Python, handed to the engine
in its plan) and the log categories (robogen.fmu.fmi, which the C tables naming them follow)."""

from __future__ import annotations

import math
import random
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


def test_same_time_is_the_tolerance_of_the_larger_time():
    # same_time computes tolerance() inline: it must answer |a - b| <= tolerance(max(|a|, |b|), r)
    # everywhere, at the edges of the tolerance, past 1 s, with a resolution, and for inf and NaN
    rng = random.Random(5)
    edge = [0.0, 1.0, -1.0, 0.5, 1e7, 1e7 + 0.01, 1e-12, 1e300, math.inf, -math.inf, math.nan, 5e-324]
    cases = [(a, b) for a in edge for b in edge]
    for _ in range(2000):
        a = rng.choice([rng.uniform(-2, 2), rng.uniform(-1e8, 1e8), rng.choice(edge)])
        gap = rng.choice([0.0, fmi.TIME_TOLERANCE, fmi.TIME_TOLERANCE * abs(a), math.ulp(a) * fmi.TIME_ULPS,
                          rng.uniform(-1e-6, 1e-6)]) * rng.choice([0.5, 1.0, 1.0000001, 2.0, -1.0])
        cases.append((a, a + gap))
    for a, b in cases:
        for resolution in (None, 0.5, 1e-12, 0.01):
            expected = abs(a - b) <= fmi.tolerance(max(abs(a), abs(b)), resolution)
            assert fmi.same_time(a, b, resolution) is expected, (a, b, resolution)
    assert fmi.same_time(1.0, 1.0 + fmi.TIME_TOLERANCE / 2) and not fmi.same_time(1.0, 1.0 + 3 * fmi.TIME_TOLERANCE)
