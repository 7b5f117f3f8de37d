"""Stopping a run on a signal: SIGINT (Ctrl-C), SIGTERM and SIGHUP end a run the same way.

Inside :func:`interruptible`, the first of the given signals raises :class:`Interrupted` (a
``KeyboardInterrupt``) wherever the main thread is, so the run unwinds as after any failure: every
FMU instance is terminated and freed, the rows recorded so far are flushed and kept, the
extracted FMUs are removed. Further signals are ignored while that happens. ``robogen simulate``
then exits with 128 + the signal's number (130, 143, 129).

A signal that arrives while a Python FMU runs its own code (its ``do_step``, say) raises inside
that code, in the same interpreter; the FMU turns every exception into ``fmi3Error``. The master
therefore asks :func:`caught` when a call fails: if a signal came in, the failure is the
interruption, not the FMU's error.

Handlers are Python's: they run in the main thread only, between two bytecodes, so a call into
C (an FMU's step, the C stretch) finishes first (the C stretch hands control back at least
every 0.2 s). A signal that arrives during the clean-up itself (:func:`deferred`) is raised when
the clean-up is done, so the rows are always flushed and the folders always removed.
"""

from __future__ import annotations

import signal
import threading
from contextlib import contextmanager
from typing import Iterable, Iterator


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


def caught() -> int | None:
    """The signal that interrupted the current run, if one did."""
    return _caught


def _handler(signum: int, frame) -> None:
    global _caught, _pending
    if _caught is not None:
        return  # already winding down
    _caught = signum
    if _deferring:
        _pending = True
        return
    raise Interrupted(signum)


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
    global _caught, _pending
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    defaults = (signal.SIG_DFL, signal.default_int_handler)
    previous = {s: signal.getsignal(s) for s in signums}
    mine = [s for s, h in previous.items() if not only_if_default or h in defaults]
    if mine:
        _caught, _pending = None, False
    for s in mine:
        signal.signal(s, _handler)
    try:
        yield
    finally:
        for s in mine:
            signal.signal(s, previous[s])
        if mine:
            _caught, _pending = None, False


__all__ = ["Interrupted", "caught", "deferred", "interruptible"]
