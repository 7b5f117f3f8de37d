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


#: one conversion step per connection: the factor and offset, then the input's type (issue 19's
#: conversions between real types, and between clock domains)
ONE_STEP = """connections = [
  { from = "a.y_f64", to = "b.u_f32", factor = FACTOR },
  { from = "a.c_f64", to = "t.u", factor = 2.0, offset = 1.0 },
]
[experiment]
stop = 1.0
step = 0.1
[instances.a]
fmu = "{alltypes}"
[instances.b]
fmu = "{alltypes}"
[instances.t]
fmu = "{trivial}"
[record]
variables = ["a.y_f64", "b.u_f32", "a.c_f64", "t.y"]
"""


def test_a_connection_converts_in_one_step_in_both_loops(write_system, monkeypatch):
    """A Float64 scaled into a Float32 input (the product rounded once), and a clocked value scaled
    into an input that is not clocked (held between a's ticks): the same rows in both loops; a
    product past the largest Float32 stops both runs alike, at the connection, with that product."""
    path = write_system(ONE_STEP.replace("FACTOR", "-0.5"))
    python, c = run(path, "Python", monkeypatch), run(path, "C", monkeypatch)
    assert c.rows == python.rows
    rows = [dict(zip(c.columns, r)) for r in c.rows]
    for r in rows:
        assert r["b.u_f32"] == f32(-0.5 * r["a.y_f64"])
    held, plain = None, [r for r in rows if r["superdense"] == 0]
    for before, now in zip(plain, plain[1:]):
        held = next((r["a.c_f64"] for r in reversed(rows) if r["a.c_f64"] is not None and r["time"] <= before["time"]), held)
        assert now["t.y"] == pytest.approx(2.0 * held + 1.0 + now["time"])  # trivial: y = u + t
    overflow = write_system(ONE_STEP.replace("FACTOR", "1e39"), name="overflow.toml")
    errors = []
    for loop in ("Python", "C"):
        with pytest.raises(RobogenError) as exc:
            run(overflow, loop, monkeypatch)
        d = exc.value.diagnostics[0]
        errors.append((d.span.line, d.message))
    assert errors[0] == errors[1]
    assert errors[0] == (2, "connection 'a.y_f64 -> b.u_f32': the value 1.6e+39 of Float64 'a.y_f64' does not fit the "
                            "input's type Float32 at t=0; the results recorded so far are kept")  # y_f64 = u_f64 + 0.1 = 1.6
