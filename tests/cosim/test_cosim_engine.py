"""The engine (robogen.cosim.engine, in C) does what the master's Python loop, its executable
reference, does on the same plan (ROBOGEN_REFERENCE_LOOP=1): the same rows byte for byte, kept,
written by Python or written as CSV lines by C, the same events log, the same statistics, the same
located errors and kept rows, on every scenario of this folder: quiet stretches over several
chunks, connected chains, reals of every form, every FMI type, periodic clocks, nextEventTime,
early return, FMUs that roll back, termination, Zeno behaviour, a failing FMU, decimation,
instances traced or in a worker process (adapters), paced runs."""

from __future__ import annotations

import json
import math
import random
import struct

import pytest

from robogen.cosim import engine, schema, simulate_system
from robogen.cosim.recorder import FLUSH_SECONDS, Recorder
from robogen.diagnostics import RobogenError

STATS = ("steps", "event_iterations", "instants", "early_returns", "rollbacks", "end_time", "terminated_by")

#: a ticker's output clock and count through three relays (r3 records what r2 sent)
RELAYS = ('connections = ["k.out -> r1.u", "k.count -> r1.x_in", "r1.y -> r2.u", "r1.x_out -> r2.x_in", '
          '"r2.y -> r3.u", "r2.x_out -> r3.x_in"]\n[experiment]\nstop = 2.0\nstep = 0.1\n[instances.k]\nfmu = "{{ticker}}"\n'
          + "".join(f'[instances.r{i}]\nfmu = "{{{{relay}}}}"\nstart = {{{{ stepwise = {{stepwise}} }}}}\n' for i in (1, 2, 3))
          + '[record]\nvariables = ["k.out", "k.count", "r1.y", "r2.y", "r3.y", "r3.x_out", "r3.n", "r3.x_in"]\n')

SYSTEMS = {
    # a time event announced by nextEventTime every 0.25 s, half of them between the 0.1 s grid
    # points: the master steps to them (the stair, which may return early, first)
    "stair": '[experiment]\nstop = 3.0\nstep = 0.1\n[instances.s]\nfmu = "{stair}"\nstart = { period = 0.25 }\n'
             '[instances.t]\nfmu = "{trivial}"\n',
    # the events fall on grid points: one event iteration at every step
    "stair-every-step": '[experiment]\nstop = 2.0\nstep = 0.1\n[instances.s]\nfmu = "{stair}"\nstart = { period = 0.1 }\n',
    # a terminate request from fmi3UpdateDiscreteStates (the 4th event, t = 1.0)
    "stair-terminate": '[experiment]\nstop = 3.0\nstep = 0.1\n[instances.s]\nfmu = "{stair}"\n'
                       'start = { period = 0.25, last = 4 }\n',
    # a periodic input clock every 0.25 s, its output clock and clocked count recorded, quiet
    # stretches in between with a second FMU
    "ticker": '[experiment]\nstop = 3.0\nstep = 0.1\n[instances.k]\nfmu = "{ticker}"\n[instances.t]\nfmu = "{trivial}"\n'
              '[record]\nvariables = ["k.tick", "k.out", "k.count", "k.ticks", "k.phase", "t.y"]\n',
    # a terminate request from fmi3DoStep in a quiet stretch between ticks
    "ticker-terminate": '[experiment]\nstop = 3.0\nstep = 0.01\n[instances.k]\nfmu = "{ticker}"\n'
                        '[instances.t]\nfmu = "{trivial}"\nstart = { stop_at = 1.105 }\n',
    # early returns at each bounce
    "ball": '[experiment]\nstop = 3.0\nstep = 0.1\n[instances.b]\nfmu = "{ball}"\n',
    # clocks and clocked values forwarded along a chain of relays in one instant ...
    "relay-chain": RELAYS.format(stepwise="false"),
    # ... and each relay answering in the instant after it was activated (after an update)
    "relay-chain-stepwise": RELAYS.format(stepwise="true"),
    # connected values in Event Mode: the ticker's tick count into a chain of set counters (each
    # y follows its u at once), set only when it changed; and the quiet stretches in between
    "ticker-setcount": 'connections = ["k.ticks -> a.u", "a.y -> b.u", "b.y -> c.u"]\n'
                       '[experiment]\nstop = 2.0\nstep = 0.1\n[instances.k]\nfmu = "{ticker}"\n'
                       + "".join(f'[instances.{n}]\nfmu = "{{setcount}}"\n' for n in "abc"),
    # two FMUs that may return early: those ahead of an early return roll back (the master's
    # step, called from the engine)
    "rollback": '[experiment]\nstop = 1.0\nstep = 0.5\norder = ["b", "a"]\n[instances.a]\nfmu = "{ball}"\n'
                f'start = {{ h0 = {0.5 * 9.81 * 0.731**2!r} }}\n[instances.b]\nfmu = "{{ball}}"\n'
                f'start = {{ h0 = {0.5 * 9.81 * 0.9**2!r} }}\n',
    # instances in worker processes and traced: called through adapters
    "isolated": '[experiment]\nstop = 1.0\nstep = 0.1\n[instances.k]\nfmu = "{ticker}"\nisolate = true\n'
                '[instances.s]\nfmu = "{stair}"\nisolate = true\nstart = { period = 0.25 }\n',
    # the adapters (robogen.cosim.interfaces): a Model Exchange ball integrated by CVode returning
    # early at its bounces, beside a co-simulation FMU ...
    "me-bounce": '[experiment]\nstop = 2.0\nstep = 0.1\ntolerance = 1e-6\n[instances.b]\nfmu = "{bounce3}"\n'
                 'interface = "model-exchange"\n[instances.t]\nfmu = "{trivial}"\n',
    # ... by explicit Euler, with a time event, a step event and a terminate request (FMI 2.0)
    "me-euler": '[experiment]\nstop = 3.0\nstep = 0.1\n[instances.b]\nfmu = "{bounce2}"\nsolver = "euler"\n'
                'solver_step = 0.01\nstart = { kick_time = 0.25, kick = 1.0, step_event_at = 0.5, max_bounces = 3 }\n',
    # FMI 2.0 co-simulation connected to FMI 3.0 (an Integer into an Int64 input), with a ticker's events
    "fmi2-cs": 'connections = ["l.x -> t.u", "l.crossings -> s.u"]\n[experiment]\nstop = 2.0\nstep = 0.1\n'
               '[instances.l]\nfmu = "{lag2}"\n[instances.t]\nfmu = "{trivial}"\n[instances.s]\nfmu = "{setcount}"\n'
               '[instances.k]\nfmu = "{ticker}"\n',
    # scheduled execution: two partitions at their clocks' ticks, in priority order
    "scheduled": '[experiment]\nstop = 1.0\nstep = 0.1\n[instances.s]\nfmu = "{sched3}"\n',
    # clock domains: sampled into a clocked input, held from a clocked output (the supervisory-control example)
    "supervisory": 'connections = ["controller.ur -> plant.u", "plant.x -> controller.xr", "plant.x -> supervisor.x", '
                   '"supervisor.s -> controller.s", "supervisor.as -> controller.as"]\n[experiment]\nstop = 0.8\n'
                   'step = 0.025\n[instances.controller]\nfmu = "{controller3}"\n[instances.plant]\nfmu = "{plant2}"\n'
                   '[instances.supervisor]\nfmu = "{supervisor3}"\n',
    # decimation: the plain rows thinned, every event row kept
    "ticker-every": '[experiment]\nstop = 3.0\nstep = 0.01\n[instances.k]\nfmu = "{ticker}"\n'
                    '[record]\nvariables = ["k.tick", "k.count", "k.phase"]\nevery = 0.3\n',
}


@pytest.fixture
def whole_runs(monkeypatch):
    """The number of runs made by the C loop since the test started."""
    runs = []
    original = engine.Engine.run
    monkeypatch.setattr(engine.Engine, "run", lambda self, progress: runs.append(1) or original(self, progress))
    return runs


def simulate(loop: str, monkeypatch, path, **kwargs):
    if loop == "Python":
        monkeypatch.setenv("ROBOGEN_REFERENCE_LOOP", "1")
    else:
        monkeypatch.delenv("ROBOGEN_REFERENCE_LOOP", raising=False)
    return simulate_system(path, **kwargs)


def outcome(loop: str, monkeypatch, path, tmp_path, csv: bool = True, events: bool | None = True, **kwargs):
    """(rows, CSV bytes, statistics or the error's message, events log bytes) of one run."""
    output = tmp_path / f"{path.stem}-{loop}-{csv}-{len(kwargs)}.csv"
    events = output.with_suffix(".jsonl") if events else None
    read = lambda f: f.read_bytes() if f is not None and f.exists() else None  # noqa: E731
    try:
        result = simulate(loop, monkeypatch, path, output=output if csv else None, events=events, **kwargs)
    except RobogenError as exc:
        return None, read(output), exc.diagnostics[0].message, read(events)
    return result.rows, read(output), tuple(getattr(result.stats, f) for f in STATS), read(events)


@pytest.mark.parametrize("name", sorted(SYSTEMS))
def test_the_c_run_gives_the_python_loops_results(monkeypatch, write_system, tmp_path, whole_runs, name):
    path = write_system(SYSTEMS[name], name=f"{name}.toml")
    python = outcome("Python", monkeypatch, path, tmp_path)
    assert not whole_runs
    c = outcome("C", monkeypatch, path, tmp_path)
    text = outcome("C", monkeypatch, path, tmp_path, keep_rows=False)  # C writes the CSV lines
    quiet = outcome("C", monkeypatch, path, tmp_path, csv=False, keep_rows=False)  # the rows go nowhere
    assert len(whole_runs) == 3
    assert c == python
    assert text[1:] == python[1:]
    assert quiet[2:] == python[2:]
    if name not in ("stair", "stair-every-step", "stair-terminate", "ball", "rollback", "me-bounce", "me-euler"):  # no clocks
        assert python[3].count(b"\n") >= 10 and b'"clock": ' in python[3]
    assert python[2][1] > 0  # event iterations happened
    stats = dict(zip(STATS, python[2]))
    if name == "stair":  # the stair's events at 0.25 k: six extra points between grid points (0.25, 0.75, ..., 2.75)
        assert (stats["steps"], stats["event_iterations"], stats["early_returns"]) == (30 + 6, 1 + 12, 0)
        assert [r[0] for r in c[0] if r[1] == 1] == [0.0] + [0.25 * k for k in range(1, 13)]
    if name == "rollback":  # b steps first to 1.0, returns early at 0.9; a then at 0.731: b rolls back
        assert (stats["rollbacks"], stats["early_returns"]) == (1, 3)
        assert sorted({round(r[0], 9) for r in c[0] if r[1] == 1 and r[0] > 0}) == [0.731, 0.9]
    if name == "ball":  # the bounces fall between grid points: the ball returns early at each
        assert stats["early_returns"] > 0 and stats["steps"] == 30 + stats["early_returns"]
    if name == "stair-every-step":  # one instant, two rows per event iteration; 20 steps
        assert (stats["steps"], stats["event_iterations"], stats["instants"]) == (20, 21, 21)
        assert len(c[0]) == 2 * 21
    if name == "stair-terminate":
        assert stats["terminated_by"] == "instance 's' asked to terminate in fmi3UpdateDiscreteStates at t=1"
        assert c[0][-1][:3] == [1.0, 1, 4]
    if name == "ticker-terminate":
        assert stats["terminated_by"] == "instance 't' asked to terminate in fmi3DoStep at t=1.11"
    if name.startswith("relay-chain"):  # each tick reaches r3, its count + 1 per relay: in one instant, or one per relay
        fired = [(r[0], r[1], r[7]) for r in c[0] if r[6] == 1]
        later = 0 if name == "relay-chain" else 3
        assert fired == [(0.25 * k, later, k + 1 + 3) for k in range(9)]
        assert c[0][-1][8] == 9  # r3.n: nine activations
    if name == "ticker-setcount":  # ticks counts up in each tick's update; a, b, c follow it in the next instant
        assert c[0][-1] == [2.0, 2, 0, 0, None, 9, 2.0, 9, 10, 9, 10, 9, 10]  # 10 sets: the start's, and 9 changes
        assert [r[1] for r in c[0] if r[0] == 0.25] == [0, 1, 2]
    if name == "ticker":  # count ticks at 0, 0.25, ...: recorded (1 then empty) only while its clock is active
        rows = [r for r in c[0] if r[2] == 1]
        assert [(r[0], r[1], r[4]) for r in rows] == [(0.25 * k, 0, k + 1) for k in range(13)]
        assert all(r[4] is None for r in c[0] if r[2] == 0)


def test_a_paced_run_waits_in_python_at_every_point_and_gives_the_same_results(monkeypatch, write_system, tmp_path):
    path = write_system(SYSTEMS["ticker"].replace("stop = 3.0", "stop = 1.0"), name="paced.toml")
    waits = []
    original = engine.Engine._run
    python = simulate("Python", monkeypatch, path, realtime=100.0)
    from robogen.cosim.recorder import Pacer

    wait = Pacer.wait
    monkeypatch.setattr(Pacer, "wait", lambda self, t: waits.append(t) or wait(self, t))
    c = simulate("C", monkeypatch, path, realtime=100.0)
    assert original is engine.Engine._run and c.stats.loop == "C"
    assert c.rows == python.rows
    # one wait per communication point: the grid's ten and the ticks between grid points (0.25, 0.75)
    assert waits == sorted(waits) and len(waits) == c.stats.steps == python.stats.steps == 12
    assert c.stats.realtime["points"] == python.stats.realtime["points"] == 12


def test_zeno_behaviour_is_the_same_located_error_with_the_same_rows(monkeypatch, write_system, tmp_path, whole_runs):
    path = write_system('[experiment]\nstop = 3.0\nstep = 0.1\nmax_event_iterations = 50\n[instances.z]\nfmu = "{zeno}"\n',
                        name="zeno.toml")
    python = outcome("Python", monkeypatch, path, tmp_path)
    c = outcome("C", monkeypatch, path, tmp_path)
    text = outcome("C", monkeypatch, path, tmp_path, keep_rows=False)
    assert len(whole_runs) == 2
    assert c == python and text[1:] == python[1:]
    assert python[2].startswith("event iteration at t=0.5 did not settle after 50 super-dense instants")
    assert python[3].splitlines()[-1] == b'{"time": 0.5, "index": 49, "fmu": "z", "clock": "z", "values": {}}'
    lines = python[1].decode().splitlines()
    assert lines[-1].startswith("0.5,49,")  # the instants recorded before the error are kept


def test_zeno_notes_name_the_clocks_active_in_the_last_instant(monkeypatch, write_system):
    path = write_system('[experiment]\nstop = 3.0\nstep = 0.1\n[instances.z]\nfmu = "{zeno}"\n', name="zeno.toml")
    notes = []
    for loop in ("Python", "C"):
        with pytest.raises(RobogenError) as exc:
            simulate(loop, monkeypatch, path)
        notes.append([(n.message, n.span) for n in exc.value.diagnostics[0].notes])
    assert notes[0] == notes[1]
    assert ("clocks active in the last instant: z.z", None) in notes[1]


def test_a_failing_fmu_stops_the_c_run_with_the_same_error_and_rows(monkeypatch, write_system, tmp_path, whole_runs):
    path = write_system('[experiment]\nstop = 2.0\nstep = 0.1\n[instances.k]\nfmu = "{ticker}"\n'
                        '[instances.f]\nfmu = "{failer}"\n', name="fail.toml")
    python = outcome("Python", monkeypatch, path, tmp_path)
    c = outcome("C", monkeypatch, path, tmp_path)
    text = outcome("C", monkeypatch, path, tmp_path, keep_rows=False)
    assert len(whole_runs) == 2
    assert c == python and text[1:] == python[1:]
    assert python[2] == "instance 'f': fmi3DoStep returned fmi3Error at t=0.5; the results recorded so far are kept"
    assert python[1].decode().splitlines()[-1].startswith("0.5,1,")  # the event iteration at 0.5 (a tick) is kept


def test_a_failing_fmu_exits_non_zero_with_its_rows_on_disk(write_system, robogen_process, tmp_path):
    path = write_system('[experiment]\nstop = 2.0\nstep = 0.1\n[instances.k]\nfmu = "{ticker}"\n'
                        '[instances.f]\nfmu = "{failer}"\n', name="fail.toml")
    runs = {}
    for loop in ("Python", "C"):
        env = {"ROBOGEN_REFERENCE_LOOP": "1"} if loop == "Python" else {}
        runs[loop] = robogen_process("simulate", path, "-o", f"{loop}.csv", env=env)
    assert runs["C"].returncode == runs["Python"].returncode == 1
    assert runs["C"].stderr == runs["Python"].stderr.replace("Python.csv", "C.csv")
    assert (tmp_path / "C.csv").read_bytes() == (tmp_path / "Python.csv").read_bytes()



SUFFIXES = ("f32", "f64", "i8", "u8", "i16", "u16", "i32", "u32", "i64", "u64", "b", "s", "bin", "e")


def test_every_fmi_type_travels_through_clock_and_value_connections_alike(monkeypatch, write_system, tmp_path,
                                                                          whole_runs):
    # a's output clock (it ticks with a's periodic tick, every 0.3 s) drives b's input clock, and
    # carries a value of every type; every unclocked output of a feeds the same input of b
    links = ['"a.out -> b.tin"'] + [f'"a.c_{x} -> b.ci_{x}"' for x in SUFFIXES] + [f'"a.y_{x} -> b.u_{x}"' for x in SUFFIXES]
    path = write_system("connections = [" + ", ".join(links) + "]\n[experiment]\nstop = 1.2\nstep = 0.1\n"
                        '[instances.a]\nfmu = "{alltypes}"\n[instances.b]\nfmu = "{alltypes}"\n[record]\nvariables = ['
                        + ", ".join(['"a.out"', '"b.tin"', *(f'"a.c_{x}", "b.ci_{x}", "b.y_{x}"' for x in SUFFIXES)]) + "]\n",
                        name="types.toml")
    python = outcome("Python", monkeypatch, path, tmp_path, events=None)
    c = outcome("C", monkeypatch, path, tmp_path, events=None)
    text = outcome("C", monkeypatch, path, tmp_path, events=None, keep_rows=False)
    assert len(whole_runs) == 2  # the C runs (the CSV lines with Strings are Python's to write)
    assert c == python and text[1:] == python[1:]
    result = simulate("C", monkeypatch, path)
    rows = [dict(zip(result.columns, r)) for r in result.rows]
    ticks = [r for r in rows if r["a.out"] == 1]
    assert [r["time"] for r in ticks] == [0.0, 0.3, 0.6, 0.8999999999999999, 1.2]  # 3 * 0.3 is 0.8999999999999999
    for r in ticks:  # b received every clocked value in the instant a's clock ticked
        assert r["b.tin"] == 1 and all(r[f"b.ci_{x}"] == r[f"a.c_{x}"] for x in SUFFIXES)
    # the 5th tick, after 12 steps: c = derive(derive(u, 12), 5), each derive appending ',"m"' or the byte m
    assert ticks[-1]["b.ci_s"] == 'a b,"12","5"' and ticks[-1]["b.ci_bin"] == b"\x0c\x05"


# ----------------------------------------------------------------------------------------
# Quiet stretches, connections, every FMI type

STRETCH_SYSTEMS = {
    # quiet stretches only, over several chunks of the C loop (4,096 rows each)
    "trivial": '[experiment]\nstop = 1.0\nstep = 1e-4\n[instances.t]\nfmu = "{trivial}"\n',
    # a periodic clock every 0.25 s ends each stretch; two FMUs step side by side
    "ticker": '[experiment]\nstop = 3.0\nstep = 0.1\n[instances.k]\nfmu = "{ticker}"\n[instances.t]\nfmu = "{trivial}"\n',
    # a terminate request from fmi3DoStep in the middle of a stretch
    "terminate": '[experiment]\nstop = 10.0\nstep = 0.01\n[instances.t]\nfmu = "{trivial}"\nstart = { stop_at = 3.005 }\n',
    # connected: a chain of five over several chunks, each y forwarded to the next u after every step
    "chain": 'connections = ["a.y -> b.u", "b.y -> c.u", "c.y -> d.u", "d.y -> e.u"]\n'
             '[experiment]\nstop = 1.0\nstep = 1e-4\n' + "".join(f'[instances.{n}]\nfmu = "{{trivial}}"\n' for n in "abcde"),
    # connected across time events: the ticker's phase (changed only at its ticks, every 0.25 s, so
    # the inputs set by the C loop and by the event iterations alternate) into a chain
    "ticker-chain": 'connections = ["k.phase -> a.u", "a.y -> b.u"]\n'
                    '[experiment]\nstop = 3.0\nstep = 0.1\n[instances.k]\nfmu = "{ticker}"\n'
                    '[instances.a]\nfmu = "{trivial}"\n[instances.b]\nfmu = "{trivial}"\n',
    # connected, and the last instance asks to terminate in a stretch
    "chain-terminate": 'connections = ["a.y -> b.u"]\n[experiment]\nstop = 10.0\nstep = 0.01\n'
                       '[instances.a]\nfmu = "{trivial}"\n[instances.b]\nfmu = "{trivial}"\nstart = { stop_at = 3.005 }\n',
    # reals whose repr takes every form (the FMUs refuse nan and inf: rg_format_double's own test
    # has those): exponents, 17 digits, whole numbers
    "reals": 'connections = ["tiny.y -> small.u"]\n[experiment]\nstop = 0.3\nstep = 0.003\n'
             + "".join(f'[instances.{n}]\nfmu = "{{trivial}}"\nstart = {{ u = {u} }}\n' for n, u in (
                 ("big", "1e16"), ("huge", "1e300"), ("max", "1.7976931348623157e308"), ("tiny", "-1e-7"),
                 ("small", "0.0"), ("whole", "123456789012345.0"), ("neg", "-2.5e-5"))),
}


@pytest.fixture
def loops(monkeypatch):
    """run(system) in the reference and in the engine: (python, c) results."""

    def run(path, **kwargs):
        python = simulate("Python", monkeypatch, path, output=path.with_suffix(".py.csv"), **kwargs)
        c = simulate("C", monkeypatch, path, output=path.with_suffix(".c.csv"), **kwargs)
        assert (python.stats.loop, c.stats.loop) == ("Python", "C"), "the engine did not build here"
        # the rows only to the file: the C loop writes the CSV lines itself
        text = simulate("C", monkeypatch, path, output=path.with_suffix(".text.csv"), keep_rows=False, **kwargs)
        assert text.output.read_bytes() == python.output.read_bytes()
        assert (text.stats.steps, text.stats.end_time) == (python.stats.steps, python.stats.end_time)
        # the rows nowhere: the same run, nothing stored
        quiet = simulate("C", monkeypatch, path, keep_rows=False, **kwargs)
        assert (quiet.stats.steps, quiet.stats.event_iterations, quiet.stats.end_time, quiet.stats.terminated_by) == (
            python.stats.steps, python.stats.event_iterations, python.stats.end_time, python.stats.terminated_by)
        return python, c

    return run


@pytest.mark.parametrize("name", sorted(STRETCH_SYSTEMS))
def test_quiet_stretches_give_the_references_results(loops, write_system, name):
    python, c = loops(write_system(STRETCH_SYSTEMS[name], name=f"{name}.toml"))
    assert c.output.read_bytes() == python.output.read_bytes()
    assert c.rows == python.rows
    for field in ("steps", "event_iterations", "instants", "end_time", "terminated_by"):
        assert getattr(c.stats, field) == getattr(python.stats, field), field
    if name == "trivial":
        assert c.stats.steps == 10_000 and len(c.rows) == 10_002  # (0,0), (0,1) and one row per step
    if name in ("terminate", "chain-terminate"):  # the step reaching 3.005 is t = 3.01; its row is recorded
        who = "t" if name == "terminate" else "b"
        assert c.stats.terminated_by == f"instance '{who}' asked to terminate in fmi3DoStep at t=3.01"
        assert c.rows[-1][0] == 301 * 0.01  # the grid is n * h, not a running sum
    if name == "chain":  # e.y = sum of the chain's times: at t = n h, a.y = t, b.y = t + (t - h), ...
        row = c.rows[-1]
        assert row[0] == 1.0 and row[-1] == pytest.approx(5 * 1.0 - 10 * 1e-4)
    if name == "reals":
        lines = c.output.read_text().splitlines()
        cells = dict(zip(lines[0].split(","), lines[-1].split(",")))
        # 1e16 + 0.3 is 1e16 (the ulp is 2), 0.3 is nothing next to 1e300
        assert (cells["big.y"], cells["huge.y"], cells["max.y"]) == ("1e+16", "1e+300", "1.7976931348623157e+308")
        def y(u, n):  # trivial's y after the step to n h: u + t + h, as the FMU computes it
            return u + (n - 1) * 0.003 + (n * 0.003 - (n - 1) * 0.003)

        assert cells["tiny.y"] == repr(y(-1e-7, 100)) and cells["small.y"] == repr(y(y(-1e-7, 99), 100))
        assert cells["whole.y"] == "123456789012345.3" and cells["neg.y"] == repr(y(-2.5e-5, 100))
        assert [cells["tiny.y"][:9], cells["small.y"][:8], cells["neg.y"][:7]] == ["0.2999999", "0.596999", "0.29997"]


@pytest.mark.parametrize("connected", [False, True], ids=["alone", "connected"])
def test_a_failing_fmu_in_a_quiet_stretch_stops_the_engine_with_the_same_error_and_rows(monkeypatch, write_system, tmp_path, connected):
    links = 'connections = ["f.y -> t.u"]\n' if connected else ""
    other = '[instances.t]\nfmu = "{trivial}"\n' if connected else ""
    path = write_system(links + '[experiment]\nstop = 2.0\nstep = 0.1\n[instances.f]\nfmu = "{failer}"\n' + other,
                        name="fail.toml")
    c_runs = []  # the engine's runs (the failure leaves no statistics to tell)
    whole = engine.Engine.run
    monkeypatch.setattr(engine.Engine, "run", lambda self, progress: c_runs.append(0) or whole(self, progress))
    messages = []
    for loop, keep_rows in (("Python", True), ("C", True), ("C", False)):
        with pytest.raises(RobogenError) as exc:
            simulate(loop, monkeypatch, path, output=tmp_path / f"{loop}-{keep_rows}.csv", keep_rows=keep_rows)
        messages.append(exc.value.diagnostics[0].message)
    assert len(c_runs) == 2  # the C runs ran in the engine
    assert messages[0] == messages[1] == messages[2]
    assert "instance 'f': fmi3DoStep returned fmi3Error at t=0.5" in messages[0]
    python = (tmp_path / "Python-True.csv").read_bytes()
    assert python == (tmp_path / "C-True.csv").read_bytes() == (tmp_path / "C-False.csv").read_bytes()
    assert python.decode().splitlines()[-1].startswith("0.5,0,")  # the rows up to the failing step are kept


def test_reals_are_written_as_pythons_repr():
    """The C loop's float cells (rg_format_double) against repr, over every form repr takes:
    shortest digits of 1 to 17, exponents from -324 to 308, powers of two (where the double below
    is nearer than the one above), subnormals, Float32 values widened, grid points n * h."""
    lib = engine.load()
    assert lib is not None, "the engine did not build here"
    rng = random.Random(12)
    values = [0.0, -0.0, math.inf, -math.inf, math.nan, 1.0, 0.1, 1e16, 1e15, 9999999999999998.0, 1e-4, 1e-5, 5e-324,
              2.2250738585072014e-308, 1.7976931348623157e308, 123456789012345680.0, 1e22, 1e23, 2 / 3]
    values += [math.ldexp(1.0, e) * sign for e in range(-1074, 1024) for sign in (1, -1)]
    values += [struct.unpack("<d", rng.getrandbits(64).to_bytes(8, "little"))[0] for _ in range(50_000)]
    values += [rng.random() * 10.0 ** rng.randint(-12, 20) for _ in range(50_000)]
    values += [struct.unpack("<f", rng.getrandbits(32).to_bytes(4, "little"))[0] for _ in range(20_000)]
    values += [n * 1e-4 for n in range(20_000)] + [n * 0.003 for n in range(20_000)]
    out = schema.ffi.new("char[40]")
    wrong = [(x, text) for x in values if (text := schema.ffi.string(out, lib.rg_format_double(out, x)).decode()) != repr(x)]
    assert wrong == []


def test_a_connected_stretch_records_every_instance_after_the_exchange(write_system):
    # trivial: y = u + t at the end of each step; the chain forwards a.y -> b.u and b.y -> c.u after
    # every step. c has no outgoing connection, yet its y is recorded fresh at every point (the
    # quiet stretch once recorded the value c.y had at the start).
    path = write_system('connections = ["a.y -> b.u", "b.y -> c.u"]\n[experiment]\nstop = 0.005\nstep = 0.001\n'
                        + "".join(f'[instances.{n}]\nfmu = "{{trivial}}"\n' for n in "abc"), name="chain.toml")
    quiet = simulate_system(path)
    traced = simulate_system(path, trace=lambda line: None)  # a trace: every call through an adapter
    assert (quiet.stats.loop, traced.stats.loop) == ("C", "C")
    general = traced
    assert quiet.rows == general.rows
    # t = 0.001: a.y = 0 + 0.001, b.y = b.u + 0.001 = 0.001, c.y = 0.001 (then b.u = c.u = 0.001)
    # t = 0.002: a.y = 0.002, b.y = 0.001 + 0.002, c.y = 0.001 + 0.002
    assert [r[:2] for r in quiet.rows[2:4]] == [[0.001, 0], [0.002, 0]]
    assert [r[2:] for r in quiet.rows[2:4]] == [pytest.approx([0.001, 0.001, 0.001]), pytest.approx([0.002, 0.003, 0.003])]


# ----------------------------------------------------------------------------------------
# Every FMI 3.0 type (tests/cosim/fmus/alltypes.c): y = derive(u, n) after the n-th step; the
# clocked c = derive(y, k) at the k-th tick of `tick` (every 0.3 s, from t = 0).

TYPES = ("f32", "f64", "i8", "u8", "i16", "u16", "i32", "u32", "i64", "u64", "b", "s", "bin", "e")


def alltypes(step: float, connected: bool) -> str:
    """One all-types instance, or two with every output of a connected to the input of b of the
    same type (values, the clock out -> tin and the clocked values), b's clocked inputs recorded."""
    if not connected:
        return f'[experiment]\nstop = 1.2\nstep = {step}\n[instances.a]\nfmu = "{{alltypes}}"\n'
    links = [f"a.y_{t} -> b.u_{t}" for t in TYPES] + ["a.out -> b.tin"] + [f"a.c_{t} -> b.ci_{t}" for t in TYPES]
    record = ["a.*", "b.*"] + [f"b.ci_{t}" for t in TYPES]
    return (f"connections = {links!r}\n[experiment]\nstop = 1.2\nstep = {step}\n"
            '[instances.a]\nfmu = "{alltypes}"\n[instances.b]\nfmu = "{alltypes}"\n'
            f"[record]\nvariables = {record!r}\n").replace("'", '"')


@pytest.mark.parametrize("step", [0.1, 0.7], ids=["step-shorter-than-the-clock", "step-longer-than-the-clock"])
def test_every_fmi_type_is_recorded_byte_for_byte_alike_by_the_c_and_the_python_loop(loops, write_system, step):
    python, c = loops(write_system(alltypes(step, connected=False), name="alltypes.toml"))
    assert c.output.read_bytes() == python.output.read_bytes()
    assert c.rows == python.rows
    row = dict(zip(python.columns, python.rows[2]))  # the first step's point (a grid point or the tick at 0.3): n = 1
    assert row["time"] == min(step, 0.3)
    assert [row[f"a.y_{t}"] for t in TYPES] == [
        0.5, 1.85, -4, 37, -300, 1000, -100000, 3_000_000_000, -1_000_000_007, 7 + 0x8000000000000001, True,
        'a b,"1"', b"\x01", 3]
    tick = dict(zip(python.columns, python.rows[0]))  # (0, 0): the first tick, k = 1, c = derive(derive(u, 0), 1)
    assert (tick["a.tick"], tick["a.out"], tick["a.c_f64"], tick["a.c_s"], tick["a.c_bin"], tick["a.c_e"]) == (
        1, 1, 1.6 + 0.25 + 0.1, 'a b,"0","1"', b"\x01", 3)
    lines = c.output.read_text().splitlines()
    assert lines[1].endswith(',True,"a b,""0"",""1""",0x01,3')  # a String in quotes, a Binary in hex
    assert ',False,"a b,""0""",0x,2,' in lines[1]  # the empty Binary is 0x, not an empty cell
    assert lines[2].endswith(",,,,,,,,,,,,,,")  # (0, 1): the clocked values are gone with their clock


def test_the_integers_at_the_ends_of_their_types_are_written_alike_by_the_c_and_the_python_loop(loops, write_system):
    # After the first step y = derive(u, 1): i8 = u - 1, u8 = u + 37, i16 = u - 300, u16 = u + 1000,
    # i32 = u - 100000, u32 = u + 3e9, i64 = u - 1000000007, u64 = u + 2^63 + 1: these starts put
    # every y at the end of its type (the C loop writes integers without printf)
    starts = {"u_i8": -127, "u_u8": 218, "u_i16": -32468, "u_u16": 64535, "u_i32": -2147383648, "u_u32": 1294967295,
              "u_i64": -9223372036854775808 + 1000000007, "u_u64": 2**63 - 2}
    text = alltypes(0.1, connected=False) + "start = { " + ", ".join(f"{k} = {v}" for k, v in starts.items()) + " }\n"
    python, c = loops(write_system(text, name="ends.toml"))
    assert c.output.read_bytes() == python.output.read_bytes()
    row = dict(zip(python.columns, python.rows[2]))
    assert [row[f"a.y_{t}"] for t in ("i8", "u8", "i16", "u16", "i32", "u32", "i64", "u64")] == [
        -128, 255, -32768, 65535, -2147483648, 4294967295, -9223372036854775808, 18446744073709551615]
    line = c.output.read_text().splitlines()[3]
    assert ",-128,255,-32768,65535,-2147483648,4294967295,-9223372036854775808,18446744073709551615," in line


@pytest.mark.parametrize("step", [0.1, 0.7], ids=["step-shorter-than-the-clock", "step-longer-than-the-clock"])
def test_every_fmi_type_travels_through_connections(monkeypatch, write_system, tmp_path, step):
    path = write_system(alltypes(step, connected=True), name="connected.toml")
    python = simulate("Python", monkeypatch, path, output=tmp_path / "python.csv", events=tmp_path / "events.jsonl")
    c = simulate("C", monkeypatch, path, output=tmp_path / "c.csv")
    text = simulate("C", monkeypatch, path, output=tmp_path / "text.csv", keep_rows=False)
    general = simulate_system(path, output=tmp_path / "general.csv", trace=lambda line: None)
    assert (python.stats.loop, c.stats.loop, text.stats.loop, general.stats.loop) == ("Python", "C", "C", "C")
    assert python.output.read_bytes() == c.output.read_bytes() == general.output.read_bytes()
    assert text.output.read_bytes() == python.output.read_bytes()
    row = dict(zip(python.columns, python.rows[2]))  # after the first step: b.u = a.y = derive(u, 1), then
    # b.y = derive(b.u, 1): the Binary grows by a byte, the String by ',"1"', the UInt64 wraps, the Enumeration cycles
    assert (row["b.y_bin"], row["b.y_s"], row["b.y_u64"], row["b.y_e"]) == (b"\x01\x01", 'a b,"1","1"', 9, 1)
    first = dict(zip(python.columns, python.rows[0]))  # (0, 0): a's first tick forwarded to b with its values
    assert first["b.tin"] == 1
    assert [first[f"b.ci_{t}"] for t in TYPES] == [first[f"a.c_{t}"] for t in TYPES]
    assert first["b.ci_bin"] == b"\x01"
    events = [json.loads(line) for line in (tmp_path / "events.jsonl").read_text().splitlines()]
    out = next(e for e in events if e["fmu"] == "a" and e["clock"] == "out")
    assert out["values"]["c_bin"] == "0x01" and out["values"]["c_s"] == 'a b,"0","1"'


def test_a_chunk_waits_for_the_flush_of_a_results_file_only(tmp_path, monkeypatch):
    # The C loop's chunk ends by the recorder's next flush: never where no file is written (a
    # deadline that passed once would otherwise cut every later chunk to one row).
    kept = Recorder(["a"], None, None, keep_rows=True)
    assert kept.flush_due == math.inf
    now = [100.0]
    monkeypatch.setattr("robogen.cosim.recorder._time.monotonic", lambda: now[0])
    written = Recorder(["a"], tmp_path / "out.csv", None, keep_rows=False)
    assert written.flush_due == 100.0 + FLUSH_SECONDS
    now[0] = 101.0
    written.append_text("0.0,0,1.5\n", 1)  # overdue: flushed, and the next flush is due from now
    assert written.flush_due == 101.0 + FLUSH_SECONDS and written.recorded == 1
    written.close()
    assert (tmp_path / "out.csv").read_text() == "time,superdense,a\n0.0,0,1.5\n"


def test_an_input_is_set_only_when_its_value_changed_whichever_loop_set_it_last(loops, write_system):
    # The ticker's `ticks` changes only in its event iterations (every 0.25 s); between them the
    # quiet stretches read the same value after every step. Each loop hands the values it last set
    # to the other (robogen.cosim.wiring.ValueExchange.last_set), so s sees one Set call per change:
    # a loop that forgot what the other set would set it again at the start of each stretch.
    path = write_system('connections = ["k.ticks -> s.u"]\n[experiment]\nstop = 3.0\nstep = 0.1\n'
                        '[instances.k]\nfmu = "{ticker}"\n[instances.s]\nfmu = "{setcount}"\n'
                        '[record]\nvariables = ["k.ticks", "s.y", "s.sets"]\n', name="sets.toml")
    python, c = loops(path)
    assert c.rows == python.rows
    changes = len({row[2] for row in c.rows})  # every value `ticks` took, the first (0) set in Initialization Mode
    last = dict(zip(c.columns, c.rows[-1]))
    assert last["k.ticks"] == last["s.y"] == 13 and last["s.sets"] == changes == 14  # ticks at 0, 0.25, ..., 3.0
    assert c.stats.steps == python.stats.steps > 20  # many steps in the C loop, without a Set
