"""A crash inside an FMU: reported by the watcher (robogen.cosim.crash) when the FMU runs in the
master's process, an ordinary located error with every row kept when it runs isolated
(robogen.cosim.proxy). Both with a C FMU and a Python FMU that die of SIGSEGV mid-run."""

from __future__ import annotations

import csv
import os
import signal
import subprocess
import sys
import time

import pytest

#: the failer dies in the step that reaches t = 30 (from 29.99); the ticker's clock ticks every 0.25 s,
#: so an event iteration (and its flush) comes at 29.75.
C_SYSTEM = """[experiment]
stop = 50.0
step = 0.01
[instances.d]
fmu = "{failer}"
start = { crash_time = CRASH, fail_time = 1e9 }
[instances.k]
fmu = "{ticker}"
"""
PY_SYSTEM = """[experiment]
stop = 5.0
step = 0.01
[instances.p]
fmu = "MISBEHAVING"
start = { crash_time = CRASH }
"""


def rows(path) -> list[list[str]]:
    with open(path, newline="") as f:
        return list(csv.reader(f))


def leftovers(tmp_path) -> list[str]:
    """What a run left behind: extracted FMUs in its TMPDIR, temporary results files."""
    return sorted([p.name for p in (tmp_path / "tmp").iterdir()] + [p.name for p in tmp_path.glob(".*.tmp")])


@pytest.fixture
def systems(write_system, misbehaving):
    def write(kind: str, crash: float):
        text = (C_SYSTEM if kind == "C" else PY_SYSTEM.replace("MISBEHAVING", str(misbehaving))).replace("CRASH", repr(crash))
        return write_system(text, name=f"{kind}-{crash}.toml")
    return write


@pytest.mark.parametrize("kind, instance, when, last_flush", [("C", "d", "29.99", 29.75), ("Python", "p", "1.99", 0.0)])
def test_a_crash_in_the_masters_process_is_named_and_the_flushed_rows_are_kept(systems, robogen_process, tmp_path,
                                                                                kind, instance, when, last_flush):
    crash = 30.0 if kind == "C" else 2.0
    complete = robogen_process("simulate", systems(kind, -1.0), "-o", "complete.csv")
    assert complete.returncode == 0, complete.stderr
    proc = robogen_process("simulate", systems(kind, crash), "-o", "r.csv")
    assert proc.returncode == -11  # the process died of SIGSEGV
    assert f"robogen simulate: instance '{instance}' crashed (SIGSEGV) in fmi3DoStep at t={when}\n" in proc.stderr
    assert "robogen simulate: the results recorded up to the last flush are in r.csv" in proc.stderr
    if kind == "Python":  # the model's own frame, from faulthandler's traceback
        assert "misbehaving_models.py\", line 27 in do_step" in proc.stderr
    kept = rows(tmp_path / "r.csv")
    assert kept == rows(tmp_path / "complete.csv")[:len(kept)]  # every row written is the run's own
    assert last_flush <= float(kept[-1][0]) <= float(when)  # at least up to the last flush
    assert leftovers(tmp_path) == []  # the watcher removed the extracted FMUs and renamed the results


@pytest.mark.parametrize("kind, instance, when", [("C", "d", "29.99"), ("Python", "p", "1.99")])
def test_an_isolated_crash_is_a_located_error_with_every_row_kept(systems, robogen_process, tmp_path, kind, instance, when):
    crash = 30.0 if kind == "C" else 2.0
    path = systems(kind, crash)
    assert robogen_process("simulate", systems(kind, -1.0), "-o", "complete.csv").returncode == 0
    proc = robogen_process("simulate", path, "-o", "r.csv", "--isolate")
    assert proc.returncode == 1, proc.stderr
    assert f"error: instance '{instance}' crashed (SIGSEGV) in fmi3DoStep at t={when}; the results recorded so far are kept" in proc.stderr
    assert f"{path.name}:4:1: error" in proc.stderr  # at [instances.d] / [instances.p]
    assert "robogen simulate: stopped; results recorded so far are in r.csv" in proc.stderr
    assert "Traceback" not in proc.stderr and "internal error" not in proc.stderr
    kept = rows(tmp_path / "r.csv")
    full = rows(tmp_path / "complete.csv")
    last = max(i for i, r in enumerate(full[1:], start=1) if round(float(r[0]), 9) == float(when))  # 2999 * 0.01 = 29.990000000000002
    assert kept == full[:last + 1]  # every row up to the crash
    assert leftovers(tmp_path) == []


def test_a_crash_while_loading_is_reported_too(fmus, write_system, robogen_process, tmp_path):
    # an isolated instance is fine; the other one, in process, crashes in its first step
    path = write_system('[experiment]\nstop = 1.0\nstep = 0.1\n[instances.d]\nfmu = "{failer}"\n'
                        'start = { crash_time = 0.0 }\n[instances.t]\nfmu = "{trivial}"\nisolate = true\n')
    proc = robogen_process("simulate", path, "-o", "r.csv")
    assert proc.returncode == -11
    assert "instance 'd' crashed (SIGSEGV) in fmi3DoStep at t=0" in proc.stderr
    assert leftovers(tmp_path) == []


def test_a_run_killed_from_outside_is_reported_as_killed(write_system, misbehaving, tmp_path):
    path = write_system(f'[experiment]\nstop = 100.0\nstep = 0.01\n[instances.p]\nfmu = "{misbehaving}"\n'
                        "start = { delay = 0.01 }\n")
    (tmp_path / "tmp").mkdir()
    proc = subprocess.Popen([sys.executable, "-m", "robogen", "simulate", str(path), "-o", "r.csv"], cwd=tmp_path,
                            text=True, stderr=subprocess.PIPE, env={**os.environ, "TMPDIR": str(tmp_path / "tmp")})
    deadline = time.monotonic() + 60
    def stepping() -> bool:  # a row after the header: the run is in its steps (each 10 ms in fmi3DoStep)
        return any(f.read_text().count("\n") >= 2 for f in tmp_path.glob(".r.csv.*.tmp"))

    while not stepping():
        assert proc.poll() is None and time.monotonic() < deadline, "the run did not start stepping"
        time.sleep(0.05)
    time.sleep(0.2)
    proc.send_signal(signal.SIGKILL)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == -signal.SIGKILL
    assert "robogen simulate: the run was killed (SIGKILL, or for want of memory) in fmi3DoStep of instance 'p' at t=" in err
    assert leftovers(tmp_path) == [] and (tmp_path / "r.csv").read_text().startswith("time,superdense,p.y\n")
