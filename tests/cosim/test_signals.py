"""SIGINT, SIGTERM and SIGHUP stop a run the same way: every instance terminated and freed, the
rows recorded so far kept, the extracted FMUs removed, exit 128 + n; a Python FMU interrupted
inside its do_step is interrupted, not failing with fmi3Error."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest

SLOW = """[experiment]
stop = 100.0
step = 0.01
[instances.p]
fmu = "MISBEHAVING"
start = { delay = 0.01 }
"""


def started(tmp_path, *args) -> subprocess.Popen:
    """``robogen simulate`` under way: returns once its first rows reached the results' temporary file."""
    (tmp_path / "tmp").mkdir(exist_ok=True)
    proc = subprocess.Popen([sys.executable, "-m", "robogen", "simulate", *map(str, args)], cwd=tmp_path, text=True,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, env={**os.environ, "TMPDIR": str(tmp_path / "tmp")})
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        temporary = list(tmp_path.glob(".r.csv.*.tmp"))
        if temporary and temporary[0].read_text().count("\n") >= 2:  # the header and the start row
            return proc
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.05)
    proc.kill()
    raise AssertionError("the run did not start")


@pytest.mark.parametrize("isolate", [False, True], ids=["in-process", "isolated"])
@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM, signal.SIGHUP], ids=lambda s: signal.Signals(s).name)
def test_a_signal_stops_the_run_cleanly(write_system, misbehaving, tmp_path, signum, isolate):
    path = write_system(SLOW.replace("MISBEHAVING", str(misbehaving)))
    proc = started(tmp_path, path, "-o", "r.csv", *(["--isolate"] if isolate else []))
    time.sleep(0.3)  # well inside the Python FMU's do_step (it sleeps 10 ms of each step's 10.1 ms)
    proc.send_signal(signum)
    _, err = proc.communicate(timeout=60)
    name = signal.Signals(signum).name
    assert proc.returncode == 128 + signum, err
    assert err.strip().splitlines()[-1] == f"robogen simulate: interrupted ({name}); results recorded so far are in r.csv"
    assert "fmi3Error" not in err and "Traceback" not in err
    lines = (tmp_path / "r.csv").read_text().splitlines()
    times = [float(line.split(",")[0]) for line in lines[1:]]
    assert len(times) > 2 and times == sorted(times)
    assert list((tmp_path / "tmp").iterdir()) == [] and list(tmp_path.glob(".*.tmp")) == []


def test_a_signal_during_the_clean_up_is_raised_once_it_is_done():
    from robogen.cosim.signals import Interrupted, deferred, interruptible

    done = []
    with pytest.raises(Interrupted) as stopped:
        with interruptible([signal.SIGTERM]):
            with deferred():
                signal.raise_signal(signal.SIGTERM)
                done.append("flushed and removed")  # the clean-up goes on
    assert done == ["flushed and removed"]
    assert (stopped.value.name, stopped.value.exit_status) == ("SIGTERM", 143)


def test_ctrl_c_in_a_python_fmus_step_interrupts_simulate_system(write_system, misbehaving, tmp_path):
    import threading

    from robogen.cosim import simulate_system
    from robogen.cosim.signals import Interrupted

    path = write_system(SLOW.replace("MISBEHAVING", str(misbehaving)))
    timer = threading.Timer(1.0, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(Interrupted) as stopped:
            simulate_system(path, output=tmp_path / "r.csv")  # the master handles SIGINT itself here
    finally:
        timer.cancel()
    assert stopped.value.signum == signal.SIGINT and stopped.value.results == tmp_path / "r.csv"
    assert (tmp_path / "r.csv").read_text().count("\n") > 2


def test_a_signal_inside_a_callback_of_the_master_is_delivered_once_back_in_python():
    # cffi prints and drops an exception that escapes a callback: a signal handled inside the
    # FMUs' logger would be lost, and the run would go on. It comes again after the callback.
    import cffi

    from robogen.cosim.signals import Interrupted, callback, interruptible

    ffi = cffi.FFI()
    calls = []

    @ffi.callback("void(int)")
    @callback
    def logger(n):
        calls.append(n)
        if n == 1:
            signal.raise_signal(signal.SIGTERM)  # the handler runs here, inside the callback
        calls.append(-n)  # the callback finishes

    with pytest.raises(Interrupted) as stopped:
        with interruptible([signal.SIGTERM]):
            logger(1)  # through C, as an FMU calls it
            calls.append("after")
            for _ in range(100):  # the master goes on, and the signal comes again in a moment
                time.sleep(0.05)
                calls.append("still running")
    assert calls[:3] == [1, -1, "after"] and len(calls) < 10 and stopped.value.name == "SIGTERM"
