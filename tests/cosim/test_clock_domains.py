"""Connections between clock domains: a clocked output into an input that is not clocked (sample
and hold), an output that is not clocked into a clocked input (sampled at the input's ticks), a
clocked output into an input of another clock (refused, naming both clocks); and the
supervisory-control example of the FMI 3.0 standard, built of robogen's own test FMUs, against a
trace derived by hand."""

from __future__ import annotations

import pytest

from robogen.cosim import simulate_system
from robogen.diagnostics import RobogenError

SUPERVISORY = """connections = [
  "plant.x -> controller.xr",
  "controller.ur -> plant.u",
  "plant.x -> supervisor.x",
  "supervisor.s -> controller.s",
  "supervisor.as -> controller.as",
]
[experiment]
stop = 0.8
step = 0.025
[instances.controller]
fmu = "{controller3}"
[instances.plant]
fmu = "{plant2}"
[instances.supervisor]
fmu = "{supervisor3}"
[record]
variables = ["controller.r", "controller.s", "controller.ur", "controller.ref", "plant.x", "plant.u"]
"""


@pytest.mark.parametrize("loop", ["Python", "C"])
def test_the_supervisory_control_example_follows_the_hand_derived_trace(write_system, monkeypatch, loop):
    # The controller (FMI 3.0 CS) ticks r every 0.1 s: it samples the plant's x into xr (clocked by
    # r) and puts out ur = 2 (ref - xr), held in the plant's u (FMI 2.0 ME, x' = u, integrated by
    # CVode) until the next tick. So x(0.1 k + 0.1) = x(0.1 k) + 0.1 ur_k, with ref = 1:
    #   x: 0 -> 0.2 -> 0.36 -> 0.488 (u: 2, 1.6, 1.28, 1.024).
    # The supervisor (FMI 3.0 CS) sees x after each communication step (0.025 s); at 0.325, x =
    # 0.488 + 0.025 1.024 = 0.5136 > 0.5: its next fmi3DoStep (to 0.35) finds the state event and
    # asks for Event Mode, where its output clock s ticks once with as = 0: the controller's ref
    # becomes 0 at 0.35. At 0.4, x = 0.488 + 0.1 1.024 = 0.5904 and u = -1.1808; at 0.5, x = 0.47232,
    # u = -0.94464; at 0.6, x = 0.377856, u = -0.755712; at 0.7, x = 0.3022848.
    if loop == "Python":
        monkeypatch.setenv("ROBOGEN_REFERENCE_LOOP", "1")
    result = simulate_system(write_system(SUPERVISORY))
    assert result.stats.loop == loop
    rows = [dict(zip(result.columns, r)) for r in result.rows]
    r_ticks = [round(r["time"], 9) for r in rows if r["controller.r"] == 1]
    s_ticks = [round(r["time"], 9) for r in rows if r["controller.s"] == 1]
    assert r_ticks == [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8] and s_ticks == [0.35]
    x = {round(r["time"], 9): r["plant.x"] for r in rows}
    expected = {0.1: 0.2, 0.2: 0.36, 0.3: 0.488, 0.325: 0.5136, 0.35: 0.5392, 0.4: 0.5904, 0.5: 0.47232, 0.6: 0.377856,
                0.7: 0.3022848}
    assert {t: x[t] for t in expected} == pytest.approx(expected, abs=1e-12)
    held = {round(r["time"], 9): r["plant.u"] for r in rows if r["superdense"] == 0}
    assert [held[t] for t in (0.0, 0.05, 0.1, 0.175, 0.3, 0.375, 0.4, 0.45, 0.5)] == pytest.approx(
        [2.0, 2.0, 1.6, 1.6, 1.024, 1.024, -1.1808, -1.1808, -0.94464], abs=1e-12)  # held between r's ticks
    refs = [(round(r["time"], 9), r["superdense"], r["controller.ref"]) for r in rows if 0.31 < r["time"] < 0.39]
    assert refs == [(0.325, 0, 1.0), (0.35, 0, 1.0), (0.35, 1, 0.0), (0.375, 0, 0.0)]


def test_a_clocked_value_into_an_input_of_another_clock_is_refused_naming_both_clocks(write_system):
    text = SUPERVISORY.replace('"supervisor.as -> controller.as"', '"supervisor.as -> controller.xr"').replace(
        '"plant.x -> controller.xr",', "")
    with pytest.raises(RobogenError) as exc:
        simulate_system(write_system(text))
    d = exc.value.diagnostics[0]
    assert d.message == ("'supervisor.as' is clocked by supervisor.s and 'controller.xr' by controller.r: a clocked value "
                         "crosses only to a clock it drives")
    assert d.span.line == 6  # the removed connection leaves its line empty
    assert [n.message for n in d.notes] == ['connect the clocks ("supervisor.s -> controller.r"), or connect the value to '
                                            'an input that is not clocked (sample and hold)']


@pytest.mark.parametrize("loop", ["Python", "C"])
def test_a_held_value_is_converted_and_one_out_of_range_stops_the_run_naming_the_connection(write_system, monkeypatch,
                                                                                          loop):
    # the all-types FMU's c_i64 (clocked by out, which ticks with tick every 0.3 s) is y_i64 - k
    # 1000000007 at its k-th tick (k = 1 at t = 0), y_i64 = -n 1000000007 after n steps: -1000000007
    # at t = 0 (held in g.X), then -3000000021 - 2000000014 at t = 0.3, out of an FMI 2.0 Integer's range
    if loop == "Python":
        monkeypatch.setenv("ROBOGEN_REFERENCE_LOOP", "1")
    path = write_system('connections = ["a.c_i64 -> g.X"]\n[experiment]\nstop = 1.0\nstep = 0.1\n'
                        '[instances.a]\nfmu = "{alltypes}"\n[instances.g]\nfmu = "{gantry2}"\n')
    with pytest.raises(RobogenError) as exc:
        simulate_system(path)
    d = exc.value.diagnostics[0]
    assert d.message == ("connection 'a.c_i64 -> g.X': the value -5000000035 of Int64 'a.c_i64' does not fit the input's "
                         "type Int32 at t=0.3; the results recorded so far are kept")
    assert d.span.line == 1
