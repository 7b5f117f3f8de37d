"""When an FMU crashes the master's own process: say which instance, in which call, at which time.

An FMU in the master's process (the default) that dies of a fatal signal takes the process with
it: no Python runs afterwards to report or clean up. The design here is a watcher, chosen for
being correct in every case and nearly free per call:

- Before each FMI call, the binding stores one 32-bit code (instance and function) into a few
  bytes of shared memory (:class:`robogen.cosim.fmi3.CallNotes`); the master stores the time at
  each step and event iteration; the C stretch does the same in C. That store is the whole cost
  per call (a few nanoseconds; ``bench/bench_master.py`` measures it).
- A small watching process (:mod:`robogen.cosim.watch`, plain Python without robogen, started in
  a few milliseconds) blocks on a pipe. Python's ``faulthandler`` writes the fatal signal's name
  to that pipe when the master dies; the pipe closing wakes the watcher. If the master did not
  mark its run as finished, the watcher reads the notes, renames the results files to their
  names (rows up to the last flush: every event iteration and at least every 0.2 s), removes the
  extracted FMUs and prints ``instance 'd' crashed (SIGSEGV) in fmi3DoStep at t=30``. The
  master's exit status is the signal's (139 for SIGSEGV).

The alternatives cost more or do less: a signal handler inside the dying process can print but
not safely remove folders or rename files (its heap may be what broke); running the master in a
supervised child would also work, but the child's output and exit status, Ctrl-C and the
Python API (which returns rows in memory) would all have to cross a process boundary. True
isolation, with a clean exit 1 and every row kept, is :mod:`robogen.cosim.proxy`.

``robogen simulate`` watches every run; :func:`robogen.cosim.simulate_system` does so with
``watch=True``. Without a watcher (or off Linux, without ``memfd_create``) the notes live in the
process's own memory and a crash leaves the rows in the results' temporary file.
"""

from __future__ import annotations

import faulthandler
import json
import mmap
import os
import subprocess
import sys
from pathlib import Path

from robogen.cosim import watch
from robogen.cosim.fmi3 import FUNCTIONS, CallNotes, ffi


class Watch:
    """The watcher of one run and the shared notes it reads (see the module docstring)."""

    def __init__(self) -> None:
        fd = os.memfd_create("robogen-call-notes")
        try:
            os.ftruncate(fd, watch.SIZE)
            self._memory = mmap.mmap(fd, watch.SIZE)
            read_end, write_end = os.pipe()
            try:
                self._process = subprocess.Popen(
                    [sys.executable, "-I", "-S", str(Path(watch.__file__).resolve()), str(fd), str(read_end)],
                    pass_fds=(fd, read_end), stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL)
            finally:
                os.close(read_end)
        finally:
            os.close(fd)
        self._pipe = os.fdopen(write_end, "wb", buffering=0)
        self._buffer = ffi.from_buffer("char[]", self._memory)
        self.notes = CallNotes(self._buffer)
        self._faulthandler_was_on = faulthandler.is_enabled()
        faulthandler.enable(file=self._pipe, all_threads=False)

    def publish(self, *, temp: Path | None = None, shared: Path | None = None, files=(),
                output: Path | None = None) -> None:
        """What the watcher needs after a crash: the instances the notes number, the folders to
        remove (the run's extracted FMUs, the process's shared ones: robogen.cosim.shared), the
        (temporary, final) names of the results files."""
        info = {"instances": self.notes.instances, "functions": list(FUNCTIONS),
                "temp": str(temp) if temp else None, "shared": str(shared) if shared else None,
                "files": [[str(a), str(b)] for a, b in files],
                "output": str(output) if output else None}
        data = json.dumps(info).encode("utf-8")[:watch.SIZE - watch.INFO_OFFSET]
        self._memory[watch.INFO_OFFSET:watch.INFO_OFFSET + len(data)] = data
        watch.LENGTH.pack_into(self._memory, watch.NOTES.size, len(data))

    def close(self) -> None:
        """The run is over (however it ended, short of a crash): the watcher exits quietly."""
        ffi.cast("int32_t *", self._buffer)[1] = watch.DONE
        faulthandler.disable()
        if self._faulthandler_was_on and sys.__stderr__ is not None:
            faulthandler.enable(file=sys.__stderr__)
        self._pipe.close()
        self._process.wait()
        # The memory stays mapped while a binding holds the notes (their pointers point into it).


class NoWatch:
    """A run without a watcher: notes in the process's own memory, nothing to publish."""

    def __init__(self) -> None:
        self.notes = CallNotes()

    def publish(self, **_info) -> None:
        pass

    def close(self) -> None:
        pass


def watch_run(enabled: bool) -> Watch | NoWatch:
    """The watcher of a run (when ``enabled`` and the platform has memfd_create)."""
    return Watch() if enabled and hasattr(os, "memfd_create") else NoWatch()
