"""Connections that convert their value on the way (target = factor * source + offset): a system
file's connection tables, an SSP's units and linear transformations. Both loops convert alike,
values and clocked values, Float64 and Float32; a conversion of anything but a real is refused."""

from __future__ import annotations

import struct

import pytest

from robogen.cosim import simulate_system
from robogen.diagnostics import RobogenError

SCALED = """connections = [
  { from = "a.y", to = "b.u", factor = 1000.0, offset = 2.5 },
  { from = "c.y_f32", to = "d.u_f32", factor = -0.5, offset = 0.1 },
  "c.out -> d.tin",
  { from = "c.c_f32", to = "d.ci_f32", factor = 3.0 },
  { from = "c.c_f64", to = "d.ci_f64", factor = 3.0, offset = -1e-3 },
  "c.c_i64 -> d.ci_i64",
]
[experiment]
stop = 1.0
step = 0.1
[instances.a]
fmu = "{trivial}"
[instances.b]
fmu = "{trivial}"
[instances.c]
fmu = "{alltypes}"
[instances.d]
fmu = "{alltypes}"
[record]
variables = ["a.y", "b.y", "c.y_f32", "d.u_f32", "c.c_f32", "d.ci_f32", "c.c_f64", "d.ci_f64", "c.c_i64", "d.ci_i64"]
"""


def f32(x: float) -> float:
    return struct.unpack("f", struct.pack("f", x))[0]


def run(path, loop: str, monkeypatch):
    if loop == "Python":
        monkeypatch.setenv("ROBOGEN_REFERENCE_LOOP", "1")
    else:
        monkeypatch.delenv("ROBOGEN_REFERENCE_LOOP", raising=False)
    return simulate_system(path)


def test_both_loops_convert_values_and_clocked_values_alike(write_system, monkeypatch):
    path = write_system(SCALED)
    python, c = run(path, "Python", monkeypatch), run(path, "C", monkeypatch)
    assert (python.stats.loop, c.stats.loop) == ("Python", "C")
    assert c.rows == python.rows
    rows = [dict(zip(c.columns, r)) for r in c.rows]
    plain = [r for r in rows if r["superdense"] == 0]
    for before, now in zip(plain, plain[1:]):
        # trivial: y = u + t after a step; b.u was set from a.y at the previous point
        assert now["b.y"] == pytest.approx(1000 * before["a.y"] + 2.5 + now["time"])
    for r in rows:
        assert r["d.u_f32"] == f32(-0.5 * r["c.y_f32"] + 0.1)  # the Float32 input, set from the converted value
    ticks = [r for r in rows if r["c.c_f64"] is not None]
    assert len(ticks) == 4  # c's clock every 0.3 s
    for r in ticks:
        assert r["d.ci_f32"] == f32(3.0 * r["c.c_f32"])
        assert r["d.ci_f64"] == 3.0 * r["c.c_f64"] - 1e-3
        assert r["d.ci_i64"] == r["c.c_i64"]  # a connection without factor and offset is not converted


def test_a_conversion_of_anything_but_a_real_is_refused_at_its_table(write_system):
    path = write_system('connections = [{ from = "a.y_i64", to = "b.u_i64", factor = 2.0 }]\n'
                        '[experiment]\nstop = 1.0\nstep = 0.1\n[instances.a]\nfmu = "{alltypes}"\n[instances.b]\nfmu = "{alltypes}"\n')
    with pytest.raises(RobogenError) as exc:
        simulate_system(path)
    d = exc.value.diagnostics[0]
    assert (d.span.line, d.span.column) == (1, 16)
    assert "converts its value (factor and offset), which only a real (Float32, Float64) can be" in d.message


def test_a_connection_table_is_checked_like_a_table(write_system):
    path = write_system('connections = [\n  { from = "a.y", to = "b", factor = "two", scale = 1 },\n  "a.y -> b.u",\n]\n'
                        '[experiment]\nstop = 1.0\nstep = 0.1\n[instances.a]\nfmu = "{trivial}"\n[instances.b]\nfmu = "{trivial}"\n')
    with pytest.raises(RobogenError) as exc:
        simulate_system(path)
    got = sorted((d.span.line, d.span.column, d.message) for d in exc.value.diagnostics)
    assert got == [(2, 19, "'to' must be \"instance.variable\""),
                   (2, 29, "'factor' must be a finite number"),
                   (2, 45, "unknown key 'scale'")]


def test_factor_one_and_offset_zero_is_no_conversion(write_system):
    path = write_system('connections = [{ from = "a.y", to = "b.u", factor = 1.0, offset = 0.0 }]\n'
                        '[experiment]\nstop = 0.3\nstep = 0.1\n[instances.a]\nfmu = "{trivial}"\n[instances.b]\nfmu = "{trivial}"\n')
    from robogen.cosim.system import load_system

    assert load_system(path).connections[0].scale is None
    assert simulate_system(path).rows[-1] == [0.3, 0, pytest.approx(0.3), pytest.approx(0.5)]
