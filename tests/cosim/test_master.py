"""The master's behaviour on robogen's own test FMUs; expected values come from the models' semantics."""

from __future__ import annotations

import csv
import json
import math
import re
import subprocess
import sys
from pathlib import Path

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


def test_a_next_event_time_within_the_tolerance_of_the_stop_time_is_handled_at_the_stop_time(write_system):
    # the stair's first step up is due at 0.99999999999, 1e-11 before the stop time: the run ends
    # at the stop time itself, where the event is handled
    path = write_system('[experiment]\nstop = 1.0\nstep = 0.25\n[instances.s]\nfmu = "{stair}"\n'
                        'start = { period = 0.99999999999 }\n')
    res = simulate_system(path)
    assert [r[:2] for r in res.rows[-2:]] == [[1.0, 0], [1.0, 1]] and res.rows[-1][2] == 1
    assert res.stats.end_time == 1.0


def test_a_system_without_event_mode_starts_with_one_row(fmu_builder, tmp_path):
    fmu = fmu_builder.build("trivial", tmp_path, spec={**fmu_builder.MODELS["trivial"], "event_mode": False})
    path = tmp_path / "plain.toml"
    path.write_text(f'[experiment]\nstop = 0.2\nstep = 0.1\n[instances.t]\nfmu = "{fmu}"\nstart = {{ u = 2.0 }}\n')
    res = simulate_system(path)
    # trivial: y = u + t; no Event Mode, so no event iteration and no (0, 1) row
    assert res.rows == [[0.0, 0, 2.0], [0.1, 0, 2.1], [0.2, 0, 2.2]]
    assert res.stats.event_iterations == 0


# ----------------------------------------------------------------------------------------
# Feedback through the master


def test_an_instance_may_drive_its_own_input_clock(write_system):
    path = write_system("""connections = ["a.out -> a.tin", "a.c_bin -> a.ci_bin", "a.c_s -> a.ci_s"]
[experiment]
stop = 0.3
step = 0.1
[instances.a]
fmu = "{alltypes}"
[record]
variables = ["a.out", "a.tin", "a.c_bin", "a.ci_bin", "a.ci_s"]
""")
    rows = rows_as_dicts(simulate_system(path))
    ticks = [r for r in rows if r["a.out"] == 1]
    assert [r["time"] for r in ticks] == [0.0, 0.3]  # a's own tick, forwarded to its own input clock
    assert all(r["a.tin"] == 1 and r["a.ci_bin"] == r["a.c_bin"] for r in ticks)
    assert ticks[1]["a.ci_bin"] == b"\x03\x02" and ticks[1]["a.ci_s"] == 'a b,"3","2"'


def test_a_clock_loop_through_one_instance_that_never_settles_is_named(write_system):
    # with echo, each tick of tin asks for an instant in which out ticks again: out -> tin forever
    path = write_system("""connections = ["a.out -> a.tin"]
[experiment]
stop = 1.0
step = 0.1
max_event_iterations = 20
[instances.a]
fmu = "{alltypes}"
start = { echo = true }
""")
    with pytest.raises(RobogenError) as exc:
        simulate_system(path)
    d = exc.value.diagnostics[0]
    assert "t=0 did not settle after 20 super-dense instants" in d.message and "'a'" in d.message
    [loop] = [n for n in d.notes if "loop" in n.message]
    assert loop.message == "the active clocks trigger each other around the loop 'a.out -> a.tin'"
    assert (loop.span.line, loop.span.column) == (1, 16)


def test_an_algebraic_loop_names_every_connection_of_its_cycle(write_system):
    # alltypes: y_f64 = u_f64 + 0.25 n + 0.1, so a value that goes round a -> b -> a grows by 0.2 each time
    path = write_system("""connections = ["a.y_f64 -> b.u_f64", "b.y_f64 -> a.u_f64"]
[experiment]
stop = 1.0
step = 0.1
[instances.a]
fmu = "{alltypes}"
[instances.b]
fmu = "{alltypes}"
[instances.c]
fmu = "{alltypes}"
""")
    with pytest.raises(RobogenError) as exc:
        simulate_system(path)
    d = exc.value.diagnostics[0]
    assert d.message.startswith("values did not settle at t=0: an algebraic loop a -> b -> a")
    assert (d.span.line, d.span.column) == (1, 16)  # "a.y_f64 -> b.u_f64"
    assert [(n.message, n.span.column) for n in d.notes] == [("'b.y_f64 -> a.u_f64' is part of the loop", 38)]


# ----------------------------------------------------------------------------------------
# Start values and steps


def test_a_start_value_the_fmu_refuses_is_reported_at_its_key(write_system):
    path = write_system('[experiment]\nstop = 1.0\nstep = 0.1\n[instances.a]\nfmu = "{alltypes}"\n'
                        'start = { u_i8 = 3, u_f64 = nan }\n')
    with pytest.raises(RobogenError) as exc:
        simulate_system(path)
    d = exc.value.diagnostics[0]
    assert d.message == "instance 'a' refused the start value nan of 'u_f64' (fmi3SetFloat64 returned fmi3Error)"
    assert (d.span.line, d.span.column) == (6, 21)
    assert [n.message for n in d.notes] == ["the FMU logged: fmi3SetFloat64: the value is not a finite number"]


@pytest.mark.parametrize("stop, step, message", [
    # doubles at 1 are 2**-52 apart; at 1e12, 2**-13 (1.22e-4): a step of 1e-4 is less than one of those
    (1.0, 1e-300, "at t=1, doubles are 2.22e-16 apart, and a step must be more than 16 of those (3.55e-15)"),
    (1e12, 1e-4, "at t=1e+12, doubles are 0.000122 apart, and a step must be more than 16 of those (0.00195)"),
])
def test_a_step_that_cannot_advance_time_is_refused(write_system, stop, step, message):
    path = write_system(f'[experiment]\nstop = {stop!r}\nstep = {step!r}\n[instances.t]\nfmu = "{{trivial}}"\n')
    with pytest.raises(RobogenError) as exc:
        simulate_system(path)
    d = exc.value.diagnostics[0]
    assert d.message == f"the communication step {step!r} cannot advance time exactly: {message}"
    assert (d.span.line, d.span.column) == (3, 1)


def test_a_run_of_more_than_1e8_rows_is_warned_about_before_it_starts(write_system):
    from robogen.cosim.assemble import build_master

    path = write_system('[experiment]\nstop = 1000.0\nstep = 5e-6\n[instances.t]\nfmu = "{trivial}"\n')
    warnings = []
    _master, cache = build_master(path, warn=warnings.append)
    cache.close()
    [w] = warnings
    assert w.message.startswith("this run records about 2e+08 rows") and w.span.line == 3


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


def test_a_python_fmus_exception_is_shown_with_its_type_message_and_place(write_system, misbehaving, tmp_path, capsys):
    path = write_system(f'[experiment]\nstop = 5.0\nstep = 0.5\n[instances.p]\nfmu = "{misbehaving}"\n'
                        'start = { fail_time = 2.0 }\n')
    assert main(["simulate", str(path), "-o", str(tmp_path / "r.csv")]) == 1  # logging off, as the master instantiates
    err = capsys.readouterr().err
    assert "error: instance 'p': fmi3DoStep returned fmi3Error at t=1.5" in err
    source = (Path(__file__).parent / "misbehaving_models.py").read_text().splitlines()
    line = 1 + next(i for i, text in enumerate(source) if "1.0 / (self.fail_time" in text)
    # (the model's module: the FMU's copy, or the test's own where this process imported it first)
    assert re.search(rf"ZeroDivisionError: float division by zero \(at (\S+/)?misbehaving_models\.py:{line} in do_step\)", err)


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
