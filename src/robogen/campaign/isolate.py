"""Each run in a process of its own, forked from a warm one: crashes and hangs stay in that run.

An FMU is native code: a segmentation fault or an endless loop in it would take down whatever
process runs it. So a run never executes in the Dask worker itself. Each worker starts one
helper process, the *zygote* (``python -m robogen.campaign.isolate``), which imports robogen's
master and the campaign's ``preload`` modules once and then, for every run, ``fork()``s a child
that executes the run and sends back its result. The zygote is single-threaded, so forking it is
safe (forking the multi-threaded worker is not), and a child starts with everything imported: a
fork costs milliseconds where a fresh Python costs a second.

:func:`run_forked` is the primitive (fork, collect the pickled result through a pipe, kill at
the deadline, read the exit status); :class:`Zygote` is the worker's handle on its helper, and
:func:`serve` is the helper's loop. A child that dies by a signal, exits without a result or
outlives its timeout becomes an :class:`Outcome` with ``failure`` set, the last lines it printed
appended; the zygote and the worker carry on. The zygote reads its requests from a pipe: when
the worker dies, the pipe closes, and the zygote kills its running child and exits.
"""

from __future__ import annotations

import faulthandler
import os
import pickle
import select
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

_LENGTH = struct.Struct("!Q")
_TAIL_LINES = 8
#: Native libraries must not start thread pools in the child: a campaign runs one simulation per core.
SINGLE_THREADED = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}


@dataclass(frozen=True)
class Outcome:
    result: Any = None
    failure: str | None = None  # why there is no result


class Abandoned(Exception):
    """The process that asked for the run is gone."""


def _write_all(fd: int, data: bytes) -> None:
    view = memoryview(data)
    while view:
        view = view[os.write(fd, view):]


def _read_exactly(fd: int, n: int) -> bytes | None:
    chunks, left = [], n
    while left:
        chunk = os.read(fd, left)
        if not chunk:
            return None
        chunks.append(chunk)
        left -= len(chunk)
    return b"".join(chunks)


def send(fd: int, message: Any) -> None:
    data = pickle.dumps(message, protocol=pickle.HIGHEST_PROTOCOL)
    _write_all(fd, _LENGTH.pack(len(data)) + data)


def receive(fd: int) -> Any:
    """The next message, or None at end of file."""
    header = _read_exactly(fd, _LENGTH.size)
    if header is None:
        return None
    data = _read_exactly(fd, _LENGTH.unpack(header)[0])
    return None if data is None else pickle.loads(data)


def _child(function: Callable, args: tuple, result_fd: int, log_fd: int) -> None:
    """In the forked child: run, send the pickled result, exit without cleanup handlers."""
    code = 70
    try:
        os.dup2(log_fd, 1)
        os.dup2(log_fd, 2)
        sys.stdout = sys.stderr = open(2, "w", buffering=1, encoding="utf-8", errors="replace", closefd=False)
        signal.signal(signal.SIGINT, signal.SIG_DFL)
        faulthandler.disable()  # a crash is reported by its signal, the same wherever the run executed
        result = function(*args)
        _write_all(result_fd, pickle.dumps(result, protocol=pickle.HIGHEST_PROTOCOL))
        os.close(result_fd)  # the parent has the result now, before the kernel takes this process apart
        code = 0
    except BaseException:  # the child reports whatever happened through its log
        import traceback

        traceback.print_exc()
    finally:
        sys.stderr.flush()
        os._exit(code)


def run_forked(function: Callable, args: tuple, timeout: float, abort_fd: int | None = None) -> Outcome:
    """``function(*args)`` in a forked child; its pickled return value or why there is none.

    The child is killed when ``timeout`` seconds of wall time have passed, or when ``abort_fd``
    becomes readable (the requester closed it): then :class:`Abandoned` is raised.
    """
    _reap()
    with tempfile.TemporaryFile() as log:
        read_fd, write_fd = os.pipe()
        sys.stdout.flush()  # or the child would print what the parent had buffered again
        sys.stderr.flush()
        pid = os.fork()
        if pid == 0:
            os.close(read_fd)
            _child(function, args, write_fd, log.fileno())
        os.close(write_fd)
        try:
            data, timed_out = _collect(read_fd, pid, time.monotonic() + timeout, abort_fd)
        finally:
            os.close(read_fd)
        if data and not timed_out:
            try:
                result = pickle.loads(data)
            except Exception:  # cut short: the exit status below says why
                pass
            else:
                _exiting.append(pid)  # a whole result: the child is exiting, collect it later
                return Outcome(result=result)
        _, status = os.waitpid(pid, 0)
        if timed_out:
            return Outcome(failure=f"timed out: still running after {timeout:g} s of wall time; killed" + _tail(log))
        if os.WIFSIGNALED(status):
            number = os.WTERMSIG(status)
            name = signal.Signals(number).name if number in signal.Signals._value2member_map_ else f"signal {number}"
            return Outcome(failure=f"crashed: the run's process was killed by {name} ({signal.strsignal(number)})" + _tail(log))
        return Outcome(failure=f"the run's process exited with status {os.WEXITSTATUS(status)} and no result" + _tail(log))


#: Children that sent their whole result and are exiting; waited for before the next fork.
_exiting: list[int] = []


def _reap() -> None:
    while _exiting:
        os.waitpid(_exiting.pop(), 0)


def _collect(read_fd: int, pid: int, deadline: float, abort_fd: int | None) -> tuple[bytes, bool]:
    """Read the child's result until end of file; kill the child at the deadline or on abort."""
    chunks = []
    watched = [read_fd] + ([abort_fd] if abort_fd is not None else [])
    while True:
        left = deadline - time.monotonic()
        if left <= 0:
            os.kill(pid, signal.SIGKILL)
            return b"", True
        ready, _, _ = select.select(watched, [], [], left)
        if abort_fd is not None and abort_fd in ready:
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
            raise Abandoned()
        if read_fd in ready:
            chunk = os.read(read_fd, 1 << 20)
            if not chunk:
                return b"".join(chunks), False
            chunks.append(chunk)


def _tail(log) -> str:
    log.seek(0, os.SEEK_END)
    size = log.tell()
    log.seek(max(0, size - 4096))
    lines = log.read().decode("utf-8", "replace").strip().splitlines()[-_TAIL_LINES:]
    return "".join(f"\n  | {line}" for line in lines)


# ---------------------------------------------------------------------------------------------
# The zygote: one per worker process


def warm_up(preload: tuple[str, ...] = ()) -> None:
    """Import what a simulation needs, so that forked children start warm: every module of the
    master (some it imports only at their first use, such as the engine, whose C declarations
    take 20 ms to parse) and the ``preload`` modules."""
    import importlib
    import pkgutil

    import robogen.cosim
    from robogen.campaign import child  # noqa: F401 (imported for the children)

    for module in pkgutil.iter_modules(robogen.cosim.__path__, "robogen.cosim."):
        importlib.import_module(module.name)
    saved = os.dup(2)  # modules may print banners on import (pybullet does); failures raise
    os.dup2(os.open(os.devnull, os.O_WRONLY), 2)
    try:
        for module in preload:
            importlib.import_module(module)
    finally:
        os.dup2(saved, 2)
        os.close(saved)


def serve(requests: int, replies: int) -> None:
    """The zygote's loop: one request at a time, ``(preload, timeout, function, args, here)``
    -> :class:`Outcome` of ``function(*args)`` in a forked child (``function`` is pickled by
    name; None only imports the ``preload`` modules). With ``here``, the call is made in the
    zygote itself, to warm it: what a first simulation sets up and keeps (C declarations parsed
    on first use, type caches, the embedded FMUs' modules) is then there for every later child.
    Only :meth:`Zygote.warm` asks for that, with a call that already succeeded in a child."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    warm_up()
    loaded: set[str] = set()
    while True:
        message = receive(requests)
        if message is None:
            return
        preload, timeout, function, args, here = message
        try:
            for module in preload:
                if module not in loaded:
                    warm_up((module,))
                    loaded.add(module)
        except Exception as exc:  # a module the campaign named: the run fails, saying why
            send(replies, Outcome(failure=f"cannot preload module {module}: {type(exc).__name__}: {exc}"))
            continue
        if function is None:  # only warm up
            send(replies, Outcome())
            continue
        if here:
            _rehearse(function, args)
            send(replies, Outcome())
            continue
        try:
            outcome = run_forked(function, args, timeout, abort_fd=requests)
        except Abandoned:
            return
        send(replies, outcome)


def _rehearse(function: Callable, args: tuple) -> None:
    saved = tempfile.tempdir
    try:
        function(*args)
    except Exception:  # it succeeded in a child; here it only warms caches
        pass
    finally:
        tempfile.tempdir = saved


class Zygote:
    """A worker's handle on its zygote, started at the first run. ``owned``: a folder the zygote
    removes when it exits, which it does when its worker goes, however the worker went."""

    def __init__(self, owned: Path | None = None) -> None:
        self.process: subprocess.Popen | None = None
        self.lock = threading.Lock()
        self.owned = owned

    def _start(self) -> subprocess.Popen:
        env = {**os.environ, **SINGLE_THREADED}
        owned = [str(self.owned)] if self.owned is not None else []
        return subprocess.Popen([sys.executable, "-m", "robogen.campaign.isolate", *owned], stdin=subprocess.PIPE,
                                stdout=subprocess.PIPE, env=env, start_new_session=True)

    def run(self, preload: tuple[str, ...], timeout: float, function: Callable | None, args: tuple) -> Outcome:
        """``function(*args)`` in a child of the zygote (started now if it is not running);
        ``function`` None starts the zygote and imports ``preload`` only."""
        return self._request((preload, timeout, function, args, False))

    def warm(self, preload: tuple[str, ...], function: Callable, args: tuple) -> Outcome:
        """``function(*args)`` in the zygote itself, so that every later child starts warm (see
        :func:`serve`). Only for a call whose run just succeeded in a child: a call that could
        crash or hang would take the zygote with it."""
        return self._request((preload, 0.0, function, args, True))

    def _request(self, message: tuple) -> Outcome:
        with self.lock:
            if self.process is None or self.process.poll() is not None:
                self.process = self._start()
            try:
                send(self.process.stdin.fileno(), message)
                outcome = receive(self.process.stdout.fileno())
            except (BrokenPipeError, OSError):
                outcome = None
            if outcome is None:  # the zygote itself died (a preload module crashed it)
                self.process.kill()
                self.process.wait()
                return Outcome(failure=f"the isolation process died (exit status {self.process.returncode})")
            return outcome

    def close(self) -> None:
        with self.lock:
            if self.process is not None:
                self.process.stdin.close()
                try:
                    self.process.wait(timeout=10)
                except subprocess.TimeoutExpired:
                    self.process.kill()
                    self.process.wait()
                self.process.stdout.close()
                self.process = None


def main(argv: list[str]) -> None:
    """Entry point of the zygote (``python -m robogen.campaign.isolate [OWNED_FOLDER]``): requests
    on stdin, replies on stdout; what libraries print on standard output (pybullet's banner) is
    discarded so that it cannot corrupt the replies."""
    requests, replies = os.dup(0), os.dup(1)
    os.dup2(os.open(os.devnull, os.O_RDONLY), 0)
    os.dup2(os.open(os.devnull, os.O_WRONLY), 1)
    try:
        serve(requests, replies)
    finally:
        _reap()
        for folder in argv:
            shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    from robogen.campaign import isolate  # the package's module, so that replies unpickle anywhere

    isolate.main(sys.argv[1:])
