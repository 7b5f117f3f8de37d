"""The worker process of an isolated FMU instance: ``python -m robogen.cosim.worker IN OUT``.

It loads one FMU binary and serves the calls of one :class:`robogen.cosim.proxy.ProxyBinding`,
read from the pipe ``IN`` and answered on the pipe ``OUT`` (file descriptors it inherits). Each
request is ``(method, args)``, a method of :class:`robogen.cosim.fmi3.Binding`; each answer is
``(outcome, value, logged, traced)``: ``("ok", result)`` or ``("failed", (function, status,
message))``, with the messages the FMU logged and the trace lines of the call. The first
request loads the binary: ``("load", (path, name, trace))``.

The worker ignores SIGINT and SIGHUP (a Ctrl-C or a closed terminal reaches every process of
the group; the master decides how its FMUs end) and exits when its request pipe closes, so it
never outlives the master. If the FMU crashes, the worker dies with it and the master reads
the signal from its exit status.
"""

from __future__ import annotations

import signal
import sys
from multiprocessing.connection import Connection

from robogen.cosim.fmi3 import Binding, FMI3Error, Library, LoadError, ffi, value_array, vr_array

#: The Binding methods a proxy may call.
METHODS = frozenset({
    "fmi3InstantiateCoSimulation", "fmi3FreeInstance", "fmi3EnterInitializationMode", "fmi3ExitInitializationMode",
    "fmi3EnterEventMode", "fmi3EnterStepMode", "fmi3Terminate", "fmi3Reset", "fmi3DoStep", "fmi3UpdateDiscreteStates",
    "fmi3GetIntervalDecimal", "fmi3GetShiftDecimal", "fmi3SetIntervalDecimal", "fmi3SetShiftDecimal",
    "fmi3GetFMUState", "fmi3SetFMUState", "fmi3FreeFMUState", "get_values", "set_values", "get_clocks", "set_clocks",
    "set_array",
})

_TAKE_VRS = frozenset({"fmi3GetIntervalDecimal", "fmi3GetShiftDecimal", "fmi3SetIntervalDecimal", "fmi3SetShiftDecimal"})


class _Served:
    """The worker's one instance: its binding, what it logged and traced during the current call."""

    def __init__(self, path: str, name: str, trace: bool):
        self.logged: list[tuple[int, str]] = []
        self.traced: list[str] = []
        self.saved = None  # the FMU state of the last fmi3GetFMUState (the proxy holds a token)
        self.binding = Binding(Library(path), name, trace=self.traced.append if trace else None,
                               log=lambda _name, status, text: self.logged.append((status, text)))

    def call(self, method: str, args: tuple):
        """The answer to one request."""
        self.logged.clear()
        self.traced.clear()
        if method not in METHODS:
            raise ValueError(f"the worker does not serve {method!r}")
        if method in _TAKE_VRS:  # value references travel as a list; the binding takes a C array
            args = (vr_array(args[0]), *args[1:])
        try:
            if method in ("get_clocks", "set_clocks", "fmi3GetFMUState", "fmi3SetFMUState"):
                result = getattr(self, method)(*args)
            else:
                result = getattr(self.binding, method)(*args)
        except FMI3Error as exc:
            return ("failed", (exc.function, exc.status, exc.message), list(self.logged), list(self.traced))
        return ("ok", result, list(self.logged), list(self.traced))

    def get_clocks(self, vrs: list[int]) -> list[bool]:
        values = value_array("Clock", len(vrs))
        self.binding.fmi3GetClock(vr_array(vrs), len(vrs), values)
        return [bool(v) for v in values[0:len(vrs)]]

    def set_clocks(self, vrs: list[int], values: list[bool]) -> None:
        self.binding.fmi3SetClock(vr_array(vrs), len(vrs), ffi.new("bool[]", values or 1))

    def fmi3GetFMUState(self) -> None:
        self.saved = self.binding.fmi3GetFMUState()  # stays here: the proxy hands out a token

    def fmi3SetFMUState(self, _token) -> int:
        return self.binding.fmi3SetFMUState(self.saved)


def serve(requests: Connection, answers: Connection) -> None:
    served: _Served | None = None
    while True:
        try:
            method, args = requests.recv()
        except EOFError:
            return
        if method == "quit":
            return
        if method == "load":
            try:
                served = _Served(*args)
                answers.send(("ok", None, [], []))
            except LoadError as exc:
                answers.send(("load-failed", str(exc), [], []))
            continue
        answers.send(served.call(method, args))


def main(argv: list[str]) -> int:
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGHUP, signal.SIG_IGN)
    requests = Connection(int(argv[0]), writable=False)
    answers = Connection(int(argv[1]), readable=False)
    serve(requests, answers)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
