"""Stopping a run on a signal: SIGINT (Ctrl-C), SIGTERM and SIGHUP end a run the same way.

Inside :func:`interruptible`, the first of the given signals raises :class:`Interrupted` (a
``KeyboardInterrupt``) wherever the main thread is, so the run unwinds as after any failure: every
FMU instance is terminated and freed, the rows recorded so far are flushed and kept, the
extracted FMUs are removed. Further signals are ignored while that happens. ``robogen simulate``
then exits with 128 + the signal's number (130, 143, 129).

A signal that arrives while a Python FMU runs its own code (its ``do_step``, say) raises inside
that code, in the same interpreter; the FMU turns every exception into ``fmi3Error``. The master
therefore asks :func:`caught` when a call fails: if a signal came in, the failure is the
interruption, not the FMU's error. One that arrives in a callback of the master's own (an FMU's
log message) is delivered again once the callback has returned (:func:`callback`).

Handlers are Python's: they run in the main thread only, between two bytecodes, so a call into
C (an FMU's step, the C stretch) finishes first (the C stretch hands control back at least
every 0.2 s). A signal that arrives during the clean-up itself (:func:`deferred`) is raised when
the clean-up is done, so the rows are always flushed and the folders always removed.
"""

from __future__ import annotations

import _thread
import signal
import threading
from contextlib import contextmanager
from typing import Callable, Iterable, Iterator, TypeVar

F = TypeVar("F", bound=Callable)


class Interrupted(KeyboardInterrupt):
    """The run was stopped by a signal; ``results`` is the CSV with the rows recorded so far."""

    results = None

    def __init__(self, signum: int):
        self.signum = signum
        self.name = signal.Signals(signum).name
        super().__init__(self.name)

    @property
    def exit_status(self) -> int:
        return 128 + self.signum


_caught: int | None = None
_deferring = 0  # depth of deferred() blocks: a signal then waits for the clean-up to finish
_pending = False  # a signal came in a deferred() block and is yet to be raised
_again = False  # a signal came in a callback (see callback()): the handler is to run again
_callbacks: set = set()  # the code of the master's C callbacks
_AGAIN_AFTER = 0.02  # s: a callback (a log message) is far shorter


def caught() -> int | None:
    """The signal that interrupted the current run, if one did."""
    return _caught


def _handler(signum: int, frame) -> None:
    global _caught, _pending, _again
    if _caught is not None and not _again:
        return  # already winding down
    _caught, _again = signum, False
    if _in_callback(frame):  # not here: again in a moment, once the callback has returned
        _again = True
        timer = threading.Timer(_AGAIN_AFTER, _thread.interrupt_main, (signum,))
        timer.daemon = True
        timer.start()
        return
    if _deferring:
        _pending = True
        return
    raise Interrupted(signum)


def callback(function: F) -> F:
    """Mark ``function`` as one of the master's C callbacks (cffi's, such as the FMUs' logger).
    The handler runs wherever Python runs, so also inside such a callback, where an exception
    would be printed and dropped by cffi while the FMU's call went on. Inside one, the handler
    raises nothing: the signal is delivered again a moment later (and again while control is
    still in a callback), so that the run stops all the same, from the master's own code."""
    _callbacks.add(function.__code__)
    return function


def _in_callback(frame) -> bool:
    while frame is not None:
        if frame.f_code in _callbacks:
            return True
        frame = frame.f_back
    return False


@contextmanager
def deferred() -> Iterator[None]:
    """Clean-up that must finish (flush, free, remove): a signal that comes meanwhile is raised
    on leaving the block, not inside it."""
    global _deferring, _pending
    _deferring += 1
    try:
        yield
    finally:
        _deferring -= 1
        if not _deferring and _pending:
            _pending = False
            raise Interrupted(_caught)


@contextmanager
def interruptible(signums: Iterable[int], *, only_if_default: bool = False) -> Iterator[None]:
    """Within: the first of ``signums`` raises :class:`Interrupted`; the previous handlers come
    back afterwards. ``only_if_default``: leave a signal alone whose handler someone else chose
    (a host application, or an outer :func:`interruptible`). Outside the main thread (where
    Python cannot handle signals) it does nothing."""
    global _caught, _pending, _again
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    defaults = (signal.SIG_DFL, signal.default_int_handler)
    previous = {s: signal.getsignal(s) for s in signums}
    mine = [s for s, h in previous.items() if not only_if_default or h in defaults]
    if mine:
        _caught, _pending, _again = None, False, False
    for s in mine:
        signal.signal(s, _handler)
    try:
        yield
    finally:
        for s in mine:
            signal.signal(s, previous[s])
        if mine:
            _caught, _pending, _again = None, False, False


__all__ = ["Interrupted", "callback", "caught", "deferred", "interruptible"]
