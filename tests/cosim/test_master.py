"""The master's behaviour on robogen's own test FMUs; expected values come from the models' semantics."""

from __future__ import annotations

import csv
import json
import math
import subprocess
import sys

import fmpy
import pytest

from robogen.cli import main
from robogen.cosim import simulate_system
from robogen.diagnostics import RobogenError

G = 9.81


def rows_as_dicts(result):
    return [dict(zip(result.columns, r)) for r in result.rows]


# ----------------------------------------------------------------------------------------
# Early return and time events


def test_early_return_event_is_recorded_at_its_own_time(write_system):
    t_hit = 0.731
    h0 = 0.5 * G * t_hit**2  # a ball dropped from rest hits the ground at t_hit
    path = write_system(f"""
[experiment]
stop = 1.5
step = 0.5
[instances.ball]
fmu = "{{ball}}"
start = {{ h0 = {h0!r} }}
""")
    res = simulate_system(path)
    rows = rows_as_dicts(res)
    times = [r["time"] for r in rows]
    # grid points 0.5, 1.0, 1.5 plus two rows at the impact: (t_hit, 0) before and (t_hit, 1) after the update
    assert times[2] == 0.5 and times[-2:] == [1.0, 1.5]
    impact = [r for r in rows if abs(r["time"] - t_hit) < 1e-9]
    assert [r["superdense"] for r in impact] == [0, 1]
    before, after = impact
    assert before["ball.h"] == pytest.approx(0.0, abs=1e-9)
    assert before["ball.v"] == pytest.approx(-G * t_hit) and before["ball.bounces"] == 0
    assert after["ball.v"] == pytest.approx(0.7 * G * t_hit) and after["ball.bounces"] == 1
    # at 1.0 the ball is in flight again, already bounced: nothing happened at 1.0
    at1 = [r for r in rows if r["time"] == 1.0]
    assert len(at1) == 1 and at1[0]["ball.bounces"] == 1
    v1 = 0.7 * G * t_hit
    assert at1[0]["ball.h"] == pytest.approx(v1 * (1 - t_hit) - 0.5 * G * (1 - t_hit) ** 2)
    assert res.stats.early_returns == 1


def test_next_event_time_is_hit_exactly(write_system):
    path = write_system("""
[experiment]
stop = 2.1
step = 0.3
[instances.stair]
fmu = "{stair}"
""")
    rows = rows_as_dicts(simulate_system(path))
    steps_up = [(r["time"], r["superdense"]) for prev, r in zip(rows, rows[1:]) if r["stair.counter"] != prev["stair.counter"]]
    assert steps_up == [(1.0, 1), (2.0, 1)]  # exactly at the announced times, after the instant's update
    assert [r["time"] for r in rows if r["superdense"] == 0][:6] == pytest.approx([0.0, 0.3, 0.6, 0.9, 1.0, 1.2])


def test_two_early_returners_roll_back_to_the_earliest_event(write_system):
    ta, tb = 0.731, 0.9
    path = write_system(f"""
[experiment]
stop = 1.0
step = 0.5
order = ["b", "a"]
[instances.a]
fmu = "{{ball}}"
start = {{ h0 = {0.5 * G * ta**2!r} }}
[instances.b]
fmu = "{{ball}}"
start = {{ h0 = {0.5 * G * tb**2!r} }}
""")
    res = simulate_system(path)
    rows = rows_as_dicts(res)
    # b is stepped first to 1.0, returns early at 0.9; a then returns at 0.731; b is rolled back to 0.731
    assert res.stats.rollbacks == 1
    event_times = sorted({round(r["time"], 9) for r in rows if r["superdense"] == 1 and r["time"] > 0})
    assert event_times == [0.731, 0.9]
    at_ta = next(r for r in rows if abs(r["time"] - ta) < 1e-9)
    assert at_ta["b.h"] == pytest.approx(0.5 * G * (tb**2 - ta**2))  # b is exactly where it must be at ta


# ----------------------------------------------------------------------------------------
# Clocks


def test_periodic_clock_ticks_at_start_plus_k_interval(write_system):
    path = write_system("""
[experiment]
stop = 10.0
step = 0.1
[instances.ticker]
fmu = "{ticker}"
[record]
variables = ["ticker.tick", "ticker.count"]
""")
    rows = rows_as_dicts(simulate_system(path))
    ticks = [(r["time"], r["ticker.count"]) for r in rows if r["ticker.tick"] == 1]
    assert ticks == [(k * 0.25, k + 1) for k in range(41)]  # 0, 0.25, ..., 10.0 exactly: no drift
    assert all(r["ticker.count"] is None for r in rows if r["ticker.tick"] == 0)  # clocked: read only while active


def _chain(n: int, stepwise: bool) -> str:
    text = """
[experiment]
stop = 0.5
step = 0.5
[instances.ticker]
fmu = "{ticker}"
"""
    conns = ['"ticker.out -> r1.u"', '"ticker.count -> r1.x_in"']
    for i in range(1, n + 1):
        text += f'[instances.r{i}]\nfmu = "{{relay}}"\nstart = {{ stepwise = {str(stepwise).lower()} }}\n'
        if i > 1:
            conns += [f'"r{i - 1}.y -> r{i}.u"', f'"r{i - 1}.x_out -> r{i}.x_in"']
    return "connections = [\n  " + ",\n  ".join(conns) + ",\n]\n" + text


def test_relay_chain_of_ten_forwards_a_tick_in_one_instant(write_system):
    res = simulate_system(write_system(_chain(10, stepwise=False)))
    rows = rows_as_dicts(res)
    for t, count in ((0.0, 1), (0.25, 2), (0.5, 3)):
        at = [r for r in rows if r["time"] == t]
        fired = [r for r in at if r["r10.y"] == 1]
        assert [r["superdense"] for r in fired] == [0]  # once, in the instant of the tick
        assert fired[0]["r10.x_out"] == count + 10  # payload incremented by every hop
        assert all(fired[0][f"r{i}.y"] == 1 for i in range(1, 11))


def test_stepwise_relay_chain_answers_at_successive_indices(write_system):
    res = simulate_system(write_system(_chain(10, stepwise=True)))
    rows = rows_as_dicts(res)
    for t, count in ((0.0, 1), (0.25, 2), (0.5, 3)):
        at = [r for r in rows if r["time"] == t]
        for i in range(1, 11):
            fired = [r["superdense"] for r in at if r[f"r{i}.y"] == 1]
            assert fired == [i]  # relay i answers one instant after it was activated
        last = next(r for r in at if r["r10.y"] == 1)
        assert last["r10.x_out"] == count + 10
        assert at[-1]["superdense"] == 11  # the settled row after ten forwarding instants
    # no step of latency: the tick at 0.25 reaches r10 at 0.25, never at the next step
    assert not any(r["r10.y"] == 1 and r["time"] not in (0.0, 0.25, 0.5) for r in rows)


def test_events_log_and_results_are_byte_identical_across_runs(write_system, tmp_path):
    path = write_system(_chain(3, stepwise=True))
    outs = []
    for i in range(2):
        out, ev = tmp_path / f"r{i}.csv", tmp_path / f"e{i}.jsonl"
        simulate_system(path, output=out, events=ev, keep_rows=False)
        outs.append((out.read_bytes(), ev.read_bytes()))
    assert outs[0] == outs[1]
    events = [json.loads(line) for line in outs[0][1].decode().splitlines()]
    first = [e for e in events if e["time"] == 0.0]
    assert [(e["fmu"], e["clock"], e["index"]) for e in first] == [
        ("ticker", "tick", 0), ("ticker", "out", 0), ("r1", "u", 0), ("r1", "y", 1), ("r2", "u", 1),
        ("r2", "y", 2), ("r3", "u", 2), ("r3", "y", 3)]
    assert first[-1]["values"] == {"x_out": 4}


# ----------------------------------------------------------------------------------------
# Failures


def test_zeno_fmu_gives_a_located_error(write_system):
    path = write_system("""
[experiment]
stop = 1.0
step = 0.1
max_event_iterations = 50
[instances.zeno]
fmu = "{zeno}"
""")
    with pytest.raises(RobogenError) as exc:
        simulate_system(path)
    d = exc.value.diagnostics[0]
    assert "t=0.5" in d.message and "50 super-dense instants" in d.message and "'zeno'" in d.message
    assert d.span.path == str(path) and d.span.line == 6  # [instances.zeno]
    assert any("zeno.z" in n.message for n in d.notes)


def test_failing_fmu_keeps_partial_results_and_exits_non_zero(write_system, tmp_path, capsys):
    path = write_system("""
[experiment]
stop = 2.0
step = 0.1
[instances.failer]
fmu = "{failer}"
""")
    out = tmp_path / "partial.csv"
    assert main(["simulate", str(path), "-o", str(out)]) == 1
    err = capsys.readouterr().err
    assert "instance 'failer': fmi3DoStep returned fmi3Error at t=0.5" in err and "Traceback" not in err
    lines = out.read_text().splitlines()
    assert lines[0] == "time,superdense,failer.y"
    assert [float(x.split(",")[0]) for x in lines[1:]] == pytest.approx([0.0, 0.0] + [k / 10 for k in range(1, 6)])


# ----------------------------------------------------------------------------------------
# Same results as fmpy.simulate_fmu with event mode, for the non-clocked outputs


def _collapse(rows):
    """Per time: the first and the last row (values before and after any event at that time)."""
    out, by_time = [], {}
    for r in rows:
        by_time.setdefault(r[0], []).append(r)
    for t, group in by_time.items():
        out.append(group[0])
        if group[-1] != group[0]:
            out.append(group[-1])
    return out


@pytest.mark.parametrize("name, outputs, start, stop, step, extra", [
    ("ball", ["h", "v", "bounces"], {"h0": 0.5 * G * 0.731**2}, 3.0, 0.5, []),
    ("stair", ["counter"], {}, 3.1, 0.3, []),
    # fmpy never activates clocks; robogen adds communication points at the ticks off the grid
    ("ticker", ["phase"], {}, 1.0, 0.1, [0.25, 0.75]),
    ("relay", ["n"], {}, 1.0, 0.1, []),
    ("failer", ["y"], {"fail_time": 5.0}, 1.0, 0.1, []),
    ("trivial", ["y"], {"u": 2.0}, 1.0, 0.25, []),
])
def test_same_results_as_fmpy(name, outputs, start, stop, step, extra, fmus, write_system):
    starts = ", ".join(f"{k} = {v!r}" for k, v in start.items())
    path = write_system(f"""
[experiment]
stop = {stop}
step = {step}
[instances.{name}]
fmu = "{{{name}}}"
start = {{ {starts} }}
[record]
variables = [{", ".join(f'"{name}.{o}"' for o in outputs)}]
""")
    ours = [tuple(r[:1] + r[2:]) for r in simulate_system(path).rows]
    theirs = fmpy.simulate_fmu(str(fmus[name]), stop_time=stop, output_interval=step, output=outputs,
                               start_values=start, use_event_mode=True, early_return_allowed=True)
    theirs = [tuple(r) for r in theirs.tolist()]
    a, b = _collapse(ours), _collapse(theirs)
    assert sorted({r[0] for r in a} - {r[0] for r in b}) == pytest.approx(extra)
    a = [r for r in a if not any(abs(r[0] - x) < 1e-12 for x in extra)]
    assert [r[0] for r in a] == pytest.approx([r[0] for r in b], abs=1e-12)
    for x, y in zip(a, b):
        assert x[1:] == pytest.approx(y[1:], rel=1e-12, abs=1e-12)


def test_realtime_pacing_reports_lag(write_system):
    path = write_system("""
[experiment]
stop = 0.2
step = 0.05
[instances.trivial]
fmu = "{trivial}"
""")
    res = simulate_system(path, realtime=20.0)
    r = res.stats.realtime
    assert r["factor"] == 20.0 and r["points"] == 4 and r["worst_lag"] >= r["mean_lag"] >= 0.0
    assert math.isfinite(r["worst_lag"]) and r["overruns"] >= 0


def test_terminate_request_ends_the_run_cleanly(write_system):
    # trivial never asks; the stop time ends the run and every instance is terminated and freed
    res = simulate_system(write_system("""
[experiment]
stop = 0.3
step = 0.1
[instances.trivial]
fmu = "{trivial}"
"""))
    assert res.stats.terminated_by is None and res.stats.end_time == pytest.approx(0.3)


def test_terminate_request_stops_the_run_with_its_results_and_exit_4(write_system, tmp_path):
    # The stair steps up at t = 1, 2, 3 and asks to terminate when its counter reaches 3: the run
    # ends at t = 3 (not at the stop time 10), with the rows up to then and a non-zero exit.
    system = write_system("""
[experiment]
stop = 10.0
step = 0.5
[instances.stair]
fmu = "{stair}"
start = { last = 3 }
""")
    out = tmp_path / "r.csv"
    proc = subprocess.run([sys.executable, "-m", "robogen", "simulate", str(system), "-o", str(out)],
                          capture_output=True, text=True)
    assert proc.returncode == 4, proc.stderr
    assert "instance 'stair' asked to terminate" in proc.stderr and "t=3.0" in proc.stderr
    assert "Traceback" not in proc.stderr
    rows = list(csv.reader(out.open()))
    times = [float(r[0]) for r in rows[1:]]
    assert times[-1] == 3.0
    assert rows[-1][rows[0].index("stair.counter")] == "3"
