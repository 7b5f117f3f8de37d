"""Isolation: an FMU instance in a worker process of its own, behind the binding's API.

An FMU is native code; a crash in it kills the process that runs it. An instance marked
``isolate = true`` in the system file (or every instance, with ``robogen simulate --isolate``)
therefore runs in a worker process (:mod:`robogen.cosim.worker`, one per instance, as libcosim
and ECOS do with their proxy processes). The master holds a :class:`ProxyBinding`: the methods
of :class:`robogen.cosim.fmi3.Binding` it uses, each sent through a pipe and answered by the
worker's real binding, with the FMU's log messages and trace lines passed back. It has no raw C
functions (:meth:`ProxyBinding.raw` is None), so the master runs such a system in its general
loop.

If the worker dies during a call, the call raises :class:`~robogen.cosim.fmi3.FMUCrashed` naming
the signal (``instance 'd' crashed (SIGSEGV) in fmi3DoStep at t=30``): the master stops as after
``fmi3Fatal``, terminates and frees the other instances, keeps every row recorded, and
``robogen simulate`` exits with 1. A call interrupted in the master (Ctrl-C) leaves the pipe in
the middle of an exchange: the worker is then killed rather than asked again.

Each call costs a round trip between two processes (two pipe writes, two reads, pickling);
``bench/bench_master.py`` measures it against the same call in process.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from multiprocessing.connection import Connection
from pathlib import Path
from typing import Callable, Sequence

import robogen
from robogen.cosim.fmi3 import (
    FUNCTION_CODE, UNLISTED, CallNotes, DiscreteStates, FMI3Error, FMUCrashed, LoadError, LogMemory, StepResult, ffi,
)

#: How long a worker may take to exit when asked (then it is killed).
EXIT_SECONDS = 5.0


def _how(returncode: int | None) -> str:
    if returncode is None:
        return "no answer"
    if returncode < 0:
        try:
            return signal.Signals(-returncode).name
        except ValueError:
            return f"signal {-returncode}"
    return f"exit status {returncode}"


class ProxyBinding:
    """The binding of an instance that lives in a worker process (see the module docstring)."""

    def __init__(self, path: str, name: str, trace: Callable[[str], None] | None = None,
                 log: Callable[[str, int, str], None] | None = None, notes: CallNotes | None = None):
        self.name, self.trace, self.log = name, trace, log
        self.notes = notes if notes is not None else CallNotes()
        self.note_base = self.notes.base(name)
        self.handle = None
        self.logged = LogMemory()
        self.dead = False  # the worker is gone (crashed, killed or stopped)
        self._busy = False  # a request was sent and its answer not read
        self._instantiated = False
        self._process, self._requests, self._answers = _spawn()
        outcome, value, _, _ = self._exchange("load", (path, name, trace is not None))
        if outcome == "load-failed":
            self.close()
            raise LoadError(value)

    # -- what the master asks of a binding -----------------------------------------------------
    @property
    def instantiated(self) -> bool:
        return self._instantiated and not self.dead

    def raw(self, function: str):
        return None  # no C function in this process: the engine calls through an adapter (robogen.cosim.adapters)

    def note_code(self, function: str) -> int:
        """What is noted before ``function`` is called on this instance (robogen.cosim.fmi3.CallNotes)."""
        return self.note_base | FUNCTION_CODE.get(function, UNLISTED)

    def error(self, function: str, status: int) -> FMI3Error:
        return FMI3Error(function, status, self.name, self.logged.message())

    # -- the exchange ----------------------------------------------------------------------------
    def _exchange(self, method: str, args: tuple):
        if self.dead:
            raise FMUCrashed(method, self.name, "it was stopped earlier")
        self._busy = True
        try:
            self._requests.send((method, args))
            answer = self._answers.recv()
        except (EOFError, OSError):
            raise FMUCrashed(method, self.name, self._ended()) from None
        self._busy = False
        return answer

    def _call(self, function: str, method: str, *args):
        """``method(*args)`` of the worker's binding; its log messages and trace lines here."""
        outcome, value, logged, traced = self._exchange(method, args)
        for status, text in logged:
            self.logged.note(status, text)
            if self.log is not None:
                self.log(self.name, status, text)
        if self.trace is not None:
            for line in traced:
                self.trace(line)
        if outcome == "failed":
            failed_function, status, message = value
            raise FMI3Error(failed_function, status, self.name, message)
        return value

    def _ended(self) -> str:
        """How the worker ended (it closed its pipe): waits for it, kills it if it lingers."""
        self.dead = True
        try:
            code = self._process.wait(timeout=EXIT_SECONDS)
        except subprocess.TimeoutExpired:
            self._process.kill()
            code = self._process.wait()
        return _how(code)

    def close(self) -> None:
        """Stop the worker: asked to quit, or killed when a call was interrupted midway."""
        if not self.dead:
            self.dead = True
            if self._busy:
                self._process.kill()
            else:
                try:
                    self._requests.send(("quit", ()))
                except OSError:
                    pass
        for connection in (self._requests, self._answers):
            connection.close()
        try:
            self._process.wait(timeout=EXIT_SECONDS)
        except subprocess.TimeoutExpired:
            self._process.kill()
            self._process.wait()

    # -- life cycle ------------------------------------------------------------------------------
    def fmi3InstantiateCoSimulation(self, instantiationToken: str, resourcePath: str | None, visible: bool = False,
                                    loggingOn: bool = False, eventModeUsed: bool = False,
                                    earlyReturnAllowed: bool = False) -> None:
        self._call("fmi3InstantiateCoSimulation", "fmi3InstantiateCoSimulation", instantiationToken, resourcePath,
                   visible, loggingOn, eventModeUsed, earlyReturnAllowed)
        self._instantiated = True

    def fmi3FreeInstance(self) -> None:
        if self.instantiated and not self._busy:
            self._call("fmi3FreeInstance", "fmi3FreeInstance")
        self._instantiated = False

    def fmi3EnterInitializationMode(self, tolerance: float | None, startTime: float, stopTime: float | None) -> int:
        return self._call("fmi3EnterInitializationMode", "fmi3EnterInitializationMode", tolerance, startTime, stopTime)

    def fmi3ExitInitializationMode(self) -> int:
        return self._call("fmi3ExitInitializationMode", "fmi3ExitInitializationMode")

    def fmi3EnterEventMode(self) -> int:
        return self._call("fmi3EnterEventMode", "fmi3EnterEventMode")

    def fmi3EnterStepMode(self) -> int:
        return self._call("fmi3EnterStepMode", "fmi3EnterStepMode")

    def fmi3Terminate(self) -> int:
        if self._busy:  # interrupted midway: the instance is in no state to be asked anything
            raise FMUCrashed("fmi3Terminate", self.name, "a call was interrupted")
        return self._call("fmi3Terminate", "fmi3Terminate")

    def fmi3Reset(self) -> int:
        return self._call("fmi3Reset", "fmi3Reset")

    # -- values ----------------------------------------------------------------------------------
    def get_values(self, fmi_type: str, vrs: Sequence[int], n_values: int | None = None) -> list:
        return self._call(f"fmi3Get{fmi_type}", "get_values", fmi_type, list(vrs), n_values)

    def set_values(self, fmi_type: str, vrs: Sequence[int], values: Sequence) -> None:
        self._call(f"fmi3Set{fmi_type}", "set_values", fmi_type, list(vrs), list(values))

    def set_array(self, fmi_type: str, vr: int, values: Sequence) -> None:
        self._call(f"fmi3Set{fmi_type}", "set_array", fmi_type, vr, list(values))

    def fmi3GetClock(self, vrs, n: int, values) -> int:
        active = self._call("fmi3GetClock", "get_clocks", ffi.unpack(vrs, n))
        values[0:n] = active
        return 0

    def fmi3SetClock(self, vrs, n: int, values) -> int:
        self._call("fmi3SetClock", "set_clocks", ffi.unpack(vrs, n), [bool(v) for v in values[0:n]])
        return 0

    def fmi3GetIntervalDecimal(self, vrs, n: int) -> tuple[list[float], list[int]]:
        return self._call("fmi3GetIntervalDecimal", "fmi3GetIntervalDecimal", ffi.unpack(vrs, n), n)

    def fmi3GetShiftDecimal(self, vrs, n: int) -> list[float]:
        return self._call("fmi3GetShiftDecimal", "fmi3GetShiftDecimal", ffi.unpack(vrs, n), n)

    def fmi3SetIntervalDecimal(self, vrs, n: int, intervals: Sequence[float]) -> int:
        return self._call("fmi3SetIntervalDecimal", "fmi3SetIntervalDecimal", ffi.unpack(vrs, n), n, list(intervals))

    def fmi3SetShiftDecimal(self, vrs, n: int, shifts: Sequence[float]) -> int:
        return self._call("fmi3SetShiftDecimal", "fmi3SetShiftDecimal", ffi.unpack(vrs, n), n, list(shifts))

    # -- FMU state (kept in the worker; the master holds a token) --------------------------------
    def fmi3GetFMUState(self):
        self._call("fmi3GetFMUState", "fmi3GetFMUState")
        return self.name

    def fmi3SetFMUState(self, state) -> int:
        return self._call("fmi3SetFMUState", "fmi3SetFMUState", state)

    def fmi3FreeFMUState(self) -> None:
        if self.instantiated and not self._busy:
            self._call("fmi3FreeFMUState", "fmi3FreeFMUState")

    # -- Event Mode and Step Mode ------------------------------------------------------------------
    def fmi3UpdateDiscreteStates(self) -> DiscreteStates:
        return self._call("fmi3UpdateDiscreteStates", "fmi3UpdateDiscreteStates")

    def fmi3DoStep(self, currentCommunicationPoint: float, communicationStepSize: float,
                   noSetFMUStatePriorToCurrentPoint: bool = True) -> StepResult:
        return self._call("fmi3DoStep", "fmi3DoStep", currentCommunicationPoint, communicationStepSize,
                          noSetFMUStatePriorToCurrentPoint)


def _spawn() -> tuple[subprocess.Popen, Connection, Connection]:
    """A fresh worker process (not a fork: the master may hold threads and loaded FMUs) and the
    two ends of its pipes the master keeps."""
    to_worker_r, to_worker_w = os.pipe()
    from_worker_r, from_worker_w = os.pipe()
    env = dict(os.environ)
    package_root = str(Path(robogen.__file__).resolve().parents[1])
    env["PYTHONPATH"] = os.pathsep.join([package_root, *filter(None, [env.get("PYTHONPATH")])])
    try:
        process = subprocess.Popen([sys.executable, "-m", "robogen.cosim.worker", str(to_worker_r), str(from_worker_w)],
                                   pass_fds=(to_worker_r, from_worker_w), env=env, stdin=subprocess.DEVNULL)
    finally:
        os.close(to_worker_r)
        os.close(from_worker_w)
    return process, Connection(to_worker_w, readable=False), Connection(from_worker_r, writable=False)


__all__ = ["ProxyBinding"]
