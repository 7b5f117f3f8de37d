"""One process per run: results come back, crashes and hangs become the run's failure."""

from __future__ import annotations

import ctypes
import operator
import os
import signal
import time

from robogen.campaign.isolate import Zygote, run_forked


def _segfault():
    print("about to read address 0")
    ctypes.string_at(0)


def test_a_forked_run_returns_its_result():
    outcome = run_forked(lambda a, b: {"sum": a + b, "pid": os.getpid()}, (2, 3), timeout=30)
    assert outcome.failure is None
    assert outcome.result["sum"] == 5 and outcome.result["pid"] != os.getpid()


def test_a_large_result_comes_back_whole():
    outcome = run_forked(lambda n: list(range(n)), (300_000,), timeout=30)
    assert outcome.result == list(range(300_000))


def test_a_segfault_is_a_failure_with_the_last_lines_printed():
    outcome = run_forked(_segfault, (), timeout=30)
    assert outcome.result is None
    assert outcome.failure == ("crashed: the run's process was killed by SIGSEGV (Segmentation fault)"
                               "\n  | about to read address 0")


def test_a_hang_is_killed_at_the_timeout():
    started = time.monotonic()
    outcome = run_forked(time.sleep, (60,), timeout=0.5)
    assert 0.5 <= time.monotonic() - started < 10
    assert outcome.failure == "timed out: still running after 0.5 s of wall time; killed"


def test_an_exception_is_a_failure_with_its_traceback():
    outcome = run_forked(operator.truediv, (1, 0), timeout=30)
    assert outcome.failure.startswith("the run's process exited with status 70 and no result")
    assert "ZeroDivisionError: division by zero" in outcome.failure


def test_the_zygote_survives_its_childrens_crashes():
    zygote = Zygote()
    try:
        assert zygote.run((), 30, operator.add, (1, 2)).result == 3
        pid = zygote.process.pid
        assert zygote.run((), 30, os.abort, ()).failure == "crashed: the run's process was killed by SIGABRT (Aborted)"
        assert zygote.run((), 0.3, time.sleep, (60,)).failure.startswith("timed out")
        assert zygote.run((), 30, operator.mul, (6, 7)).result == 42
        assert zygote.process.pid == pid  # the same zygote throughout
        assert zygote.run(("no_such_module_anywhere",), 30, operator.add, (1, 2)).failure.startswith(
            "cannot preload module no_such_module_anywhere: ModuleNotFoundError")
    finally:
        zygote.close()
    assert zygote.process is None


def test_the_zygote_and_its_child_end_when_the_worker_goes():
    zygote = Zygote()
    zygote.run((), 30, operator.add, (1, 2))
    process = zygote.process
    from robogen.campaign.isolate import send

    send(process.stdin.fileno(), ((), 60, time.sleep, (60,), False))  # a run under way ...
    time.sleep(0.3)
    process.stdin.close()  # ... when its worker dies
    assert process.wait(timeout=10) == 0
    process.stdout.close()
    assert not _children_of(process.pid)


def _children_of(pid: int) -> list[int]:
    found = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as f:
                    if int(f.read().rsplit(")", 1)[1].split()[1]) == pid:
                        found.append(int(entry))
            except OSError:
                continue
    return found


def test_signals_from_the_terminal_do_not_reach_the_zygote():
    zygote = Zygote()
    try:
        zygote.run((), 30, operator.add, (1, 2))
        assert os.getpgid(zygote.process.pid) != os.getpgid(0)
        os.kill(zygote.process.pid, signal.SIGINT)  # ignored: only the campaign's client handles Ctrl-C
        assert zygote.run((), 30, operator.add, (2, 2)).result == 4
    finally:
        zygote.close()


def test_a_warming_call_runs_in_the_zygote_and_later_children_start_from_it(tmp_path):
    zygote = Zygote()
    try:
        start = zygote.run((), 30, os.getcwd, ()).result
        assert zygote.run((), 30, os.chdir, (str(tmp_path),)).failure is None
        assert zygote.run((), 30, os.getcwd, ()).result == start  # a child's chdir stays in the child
        assert zygote.warm((), os.chdir, (str(tmp_path),)).failure is None
        assert zygote.run((), 30, os.getcwd, ()).result == str(tmp_path)  # later children start from it
        assert zygote.warm((), os.chdir, (str(tmp_path / "missing"),)).failure is None  # its exception is ignored
        assert zygote.run((), 30, os.getcwd, ()).result == str(tmp_path)
    finally:
        zygote.close()
