"""The whole run in C (robogen.cosim.runloop) does what the master's Python loop does
(ROBOGEN_NO_C_STEPPER=1): the same rows byte for byte, kept, written by Python or written as CSV
lines by C, the same events log, the same statistics, the same located errors and kept rows, on
systems with events:
periodic clocks, nextEventTime, early return, termination, Zeno behaviour, a failing FMU."""

from __future__ import annotations

import pytest

from robogen.cosim import runloop, simulate_system
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
    # decimation: the plain rows thinned, every event row kept
    "ticker-every": '[experiment]\nstop = 3.0\nstep = 0.01\n[instances.k]\nfmu = "{ticker}"\n'
                    '[record]\nvariables = ["k.tick", "k.count", "k.phase"]\nevery = 0.3\n',
}


@pytest.fixture
def whole_runs(monkeypatch):
    """The number of runs made by the C loop since the test started."""
    runs = []
    original = runloop.CRun.run
    monkeypatch.setattr(runloop.CRun, "run", lambda self, progress: runs.append(1) or original(self, progress))
    return runs


def simulate(loop: str, monkeypatch, path, **kwargs):
    if loop == "Python":
        monkeypatch.setenv("ROBOGEN_NO_C_STEPPER", "1")
    else:
        monkeypatch.delenv("ROBOGEN_NO_C_STEPPER", raising=False)
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
    if name not in ("stair", "stair-every-step", "stair-terminate", "ball"):  # they have no clocks
        assert python[3].count(b"\n") >= 10 and b'"clock": ' in python[3]
    assert python[2][1] > 0  # event iterations happened
    stats = dict(zip(STATS, python[2]))
    if name == "stair":  # the stair's events at 0.25 k: six extra points between grid points (0.25, 0.75, ..., 2.75)
        assert (stats["steps"], stats["event_iterations"], stats["early_returns"]) == (30 + 6, 1 + 12, 0)
        assert [r[0] for r in c[0] if r[1] == 1] == [0.0] + [0.25 * k for k in range(1, 13)]
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
        env = {"ROBOGEN_NO_C_STEPPER": "1"} if loop == "Python" else {}
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
