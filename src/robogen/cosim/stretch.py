"""Quiet stretches: the master's fast path between time events.

Between two time events (a clock tick, a nextEventTime, the stop time), in a system where no FMU
can return early, every communication point is the same work: step every FMU to the next point
of the grid start + n * step, exchange the connected values, record the row (t, 0). A
:class:`Stretch` does that from t up to a horizon::

    end = stretch.run(t, horizon)      # StretchEnd(t, steps, event, terminating)

It stops before the first grid point within the tolerance of the horizon (the master's general
step goes there: it is a time event or the stop time), or after the first step at which an FMU
asks for Event Mode (``end.event``; that point is not recorded, the event iteration records it) or
to terminate (``end.terminating``, the first instance that asked; that point is recorded). A
failing call raises its :class:`~robogen.cosim.fmi3.FMI3Error`; the rows before it are recorded
and every instance's ``time`` is the last point reached, as after a normal end. Before each FMI
call a stretch notes it, and the time, in the plan's :class:`~robogen.cosim.fmi3.CallNotes`, as the
bindings do (the report of a crash, :mod:`robogen.cosim.crash`, reads them).

The master picks the implementation once per run (:meth:`robogen.cosim.master.Master._choose_stretch`); both give the same results byte for
byte: the C loop (:class:`robogen.cosim.stepper.CStretch`) where it can run, else
:class:`PythonStretch`; none when the system has no quiet stretch (an FMU that may return early,
or an instance without raw C access: a trace, or a binding outside this process).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple, Protocol

from robogen.cosim.clocks import grid_index
from robogen.cosim.fmi3 import CallNotes
from robogen.cosim.instances import FmuInstance, Reader
from robogen.cosim.recorder import Pacer, Progress, Recorder
from robogen.cosim.wiring import CLOCK, VALUE, Column, ValueExchange, plain
from robogen.fmu.fmi import WARNING, tolerance


class StretchEnd(NamedTuple):
    t: float  # the last communication point reached (every instance's time)
    steps: int  # communication steps taken
    event: bool  # the last step asks for Event Mode; its point is not recorded
    terminating: FmuInstance | None  # the first instance that asked to terminate in the last step


@dataclass
class StretchPlan:
    """What a quiet stretch works with: the grid, the instances, how to exchange connected values
    and read recorded ones, where rows go."""

    start: float
    step: float
    instances: list[FmuInstance]  # in dependency order
    values: ValueExchange  # connected non-clocked values (it reads their sources' outputs)
    reads: list[Reader]  # then these, for the recorded values the exchange did not read
    columns: list[Column]
    recorder: Recorder
    progress: Progress
    pacer: Pacer | None
    notes: CallNotes  # where each call is noted before it is made (the instances' bindings' notes)

    def index(self, t: float) -> int:
        """n of the grid point start + n * step at or just before t."""
        return grid_index(t - self.start, self.step)

    def limit(self, horizon: float) -> float:
        """Grid points from here on belong to the horizon's general step."""
        return horizon - tolerance(horizon)


class Stretch(Protocol):
    """A quiet stretch's loop, bound to one run's plan (see the module's docstring)."""

    name: str  # "C" or "Python" (Stats.stretch)

    def run(self, t: float, horizon: float) -> StretchEnd: ...


class _Step(NamedTuple):
    """fmi3DoStep of one instance, called without the binding's layer."""

    instance: FmuInstance
    note: int  # the call's code in the notes
    function: object
    handle: object
    event: object  # the output arguments' pointers
    terminate: object
    early_return: object
    last_time: object
    event_mode: bool  # an event of an FMU without Event Mode is no event for the master


class _Read(NamedTuple):
    """One Reader's fmi3Get<Type>, called without the binding's layer."""

    note: int
    function: object
    handle: object
    vrs: object
    count: int
    buffer: object
    reader: Reader


class PythonStretch:
    """The quiet stretch in Python: the FMUs' C functions called through cffi."""

    name = "Python"

    def __init__(self, plan: StretchPlan):
        self.plan = plan
        self.calls = plain([_Step(u, u.binding.note_code("fmi3DoStep"), u.binding.raw("fmi3DoStep"), u.binding.handle,
                                  *u.binding.step_outputs, u.event_mode) for u in plan.instances])
        self.raw_reads = plain([_Read(r.note_code, r.c_function, r.binding.handle, r.c_vrs, r.count, r.buffer, r)
                                for r in plan.reads if not r.decodes])
        self.decoded_reads = [r for r in plan.reads if r.decodes]  # Strings, Binaries: read, then decoded
        # where each column's value is after the reads: a reader's values, or a constant
        self.sources = [(c.reader.values, c.index) if c.kind == VALUE else ((0,) if c.kind == CLOCK else (None,), 0)
                        for c in plan.columns]

    def run(self, t: float, horizon: float) -> StretchEnd:
        # Everything the loop touches is a local: it runs millions of times.
        plan = self.plan
        start, h, limit, n = plan.start, plan.step, plan.limit(horizon), plan.index(t)
        calls, raw_reads, decoded_reads, sources = self.calls, self.raw_reads, self.decoded_reads, self.sources
        exchange = plan.values.exchange if plan.values.connected else None
        pacer, progress = plan.pacer, (plan.progress if plan.progress.enabled else None)
        append_row = plan.recorder.row_sink()
        note, note_time = plan.notes.call, plan.notes.time
        steps, terminating = 0, None
        try:
            while True:
                n += 1
                t_next = start + n * h
                if t_next >= limit or t_next <= t:
                    return StretchEnd(t, steps, False, None)
                event = False
                note_time[0] = t
                for u, code, do_step, handle, ev, term, er, lst, event_mode in calls:
                    note[0] = code
                    status = do_step(handle, t, t_next - t, True, ev, term, er, lst)
                    if status > WARNING:
                        raise u.binding.error("fmi3DoStep", status)
                    if ev[0] or term[0]:
                        event = event or (ev[0] and event_mode)
                        if term[0] and terminating is None:
                            terminating = u
                t = t_next
                steps += 1
                if pacer is not None:
                    pacer.wait(t)
                if event:
                    return StretchEnd(t, steps, True, terminating)
                note_time[0] = t
                if exchange is not None:
                    exchange(plan.instances)
                for code, get, handle, vrs, count, buffer, reader in raw_reads:
                    note[0] = code
                    status = get(handle, vrs, count, buffer, count)
                    if status > WARNING:
                        raise reader.binding.error(reader.function, status)
                for reader in decoded_reads:
                    reader.read()
                row = [t, 0]
                row += [values[i] for values, i in sources]
                append_row(row)
                if progress is not None:
                    progress.update(t)
                if terminating is not None:
                    return StretchEnd(t, steps, False, terminating)
        finally:
            for u in plan.instances:
                u.time = t
