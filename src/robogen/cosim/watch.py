"""The watching process of a robogen run: it reports the run's crash, since the run cannot.

Started by :class:`robogen.cosim.crash.Watch` as ``python -I -S watch.py MEMORY PIPE`` (a plain
script: the standard library only, nothing of robogen, so it starts in milliseconds and needs no
import path). ``MEMORY`` is a shared memory file the master writes its call notes into (the
layout below, :class:`robogen.cosim.fmi3.CallNotes` at its start); ``PIPE`` is the read end of a
pipe whose write end the master holds, and to which Python's ``faulthandler`` writes when a
fatal signal kills the master.

The watcher ignores SIGINT, SIGTERM and SIGHUP (a Ctrl-C reaches every process of the terminal's
group; the master decides how the run ends) and blocks reading the pipe. When the pipe closes, the master has either finished (it
marked ``state`` done first: the watcher exits silently) or died. Then it names the instance,
the FMI call and the time from the notes, and the signal from faulthandler's first line; renames
the results files from their temporary names to the names asked for (their rows up to the last
flush); removes the folder of extracted FMUs; and prints the report on stderr.
"""

from __future__ import annotations

import json
import mmap
import os
import shutil
import signal
import struct
import sys

#: The shared memory: call (int32), state (int32), time (double), then the length (uint32) and
#: the UTF-8 JSON text of what the master published (instances, functions, temp, files, output).
NOTES = struct.Struct("<iid")
LENGTH = struct.Struct("<I")
INFO_OFFSET = NOTES.size + LENGTH.size
SIZE = 1 << 18
RUNNING, DONE = 0, 1
#: faulthandler's words for the fatal signals it catches.
SIGNALS = {"Segmentation fault": "SIGSEGV", "Bus error": "SIGBUS", "Floating point exception": "SIGFPE",
           "Illegal instruction": "SIGILL", "Aborted": "SIGABRT"}


def _read_all(fd: int) -> bytes:
    chunks = []
    while chunk := os.read(fd, 65536):
        chunks.append(chunk)
    return b"".join(chunks)


def _signal(fault: str) -> str:
    first = fault.strip().splitlines()[0] if fault.strip() else ""
    for words, name in SIGNALS.items():
        if words in first:
            return name
    return "killed"  # by a signal faulthandler does not catch (SIGKILL: out of memory, kill -9)


def _python_frames(fault: str) -> list[str]:
    """The frames of faulthandler's traceback in a Python FMU's own code (its resources/python
    folder, robogen's runtime there left out), innermost first as faulthandler lists them."""
    return [line.strip() for line in fault.splitlines()
            if line.strip().startswith("File ") and "/resources/python/" in line and "/robogen/" not in line]


def report(memory: bytes, fault: str) -> tuple[str, dict]:
    """The message for a crash, and the published information."""
    call, _state, time = NOTES.unpack_from(memory, 0)
    (length,) = LENGTH.unpack_from(memory, NOTES.size)
    info = json.loads(memory[INFO_OFFSET:INFO_OFFSET + length].decode("utf-8")) if length else {}
    instances, functions = info.get("instances", []), info.get("functions", [])
    instance = instances[call >> 8] if 0 <= call >> 8 < len(instances) else None
    function = functions[call & 255] if 0 <= call & 255 < len(functions) else None
    how = _signal(fault)
    where = f"in {function} of instance '{instance}' at t={time:.12g}" if instance and function else "before its first FMI call"
    if how == "killed":  # no fatal signal of its own: killed from outside (kill -9, out of memory)
        text = f"robogen simulate: the run was killed (SIGKILL, or for want of memory) {where}"
    elif instance is None or function is None:
        text = f"robogen simulate: the simulation crashed ({how}) {where}"
    else:
        text = f"robogen simulate: instance '{instance}' crashed ({how}) in {function} at t={time:.12g}"
    lines = [text]
    lines += [f"  {frame}" for frame in _python_frames(fault)]
    if info.get("output"):
        lines.append(f"robogen simulate: the results recorded up to the last flush are in {info['output']}")
    lines.append("(run the instance in a process of its own, with isolate = true or --isolate, "
                 "to keep every row and stop cleanly)")
    return "\n".join(lines) + "\n", info


def clean_up(info: dict) -> None:
    """Rename the results files to their names, remove the extracted FMUs (the run's, and the
    Python FMUs the dead process kept for its later runs)."""
    for temporary, target in info.get("files", []):
        if os.path.exists(temporary):
            os.replace(temporary, target)
    for folder in (info.get("temp"), info.get("shared")):
        if folder:
            shutil.rmtree(folder, ignore_errors=True)


def main(argv: list[str]) -> int:
    for stop in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):  # a Ctrl-C reaches the whole group:
        signal.signal(stop, signal.SIG_IGN)                     # the master ends the run, we watch it end
    memory_fd, pipe_fd = int(argv[0]), int(argv[1])
    fault = _read_all(pipe_fd).decode("utf-8", "replace")
    with mmap.mmap(memory_fd, SIZE) as memory:
        snapshot = bytes(memory)
    if NOTES.unpack_from(snapshot, 0)[1] == DONE:
        return 0
    message, info = report(snapshot, fault)
    clean_up(info)
    sys.stderr.write(message)
    sys.stderr.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
