"""The co-simulation algorithm: FMI 3.0 Co-Simulation with Event Mode, clocks and early return.

It follows the FMI 3.0 standard's Co-Simulation master algorithm with Event Mode step by step:

    setup       instantiate (eventModeUsed where hasEventMode, earlyReturnAllowed where the FMU
                might return early), Initialization Mode in dependency order, exit
    events      event iteration at (t_start, 0)
    loop        t_next = min(next grid point, next clock tick, nextEventTime, stop)
                step every FMU (early returners first); on an early return the others step only
                to lastSuccessfulTime, or are rolled back to it with FMU state
                on an event (eventHandlingNeeded, a tick, a reached nextEventTime): Event Mode on
                every FMU that uses it, event iteration at t, Step Mode
                else: exchange values, record (t, 0)

This module is the algorithm's executable reference: it runs the run's plan
(:mod:`robogen.cosim.plan`) point after point. Production runs go through the engine
(:mod:`robogen.cosim.engine`), the same algorithm in C on the same plan, which gives the same
results byte for byte (tests/cosim/test_cosim_engine.py runs every scenario through both) and returns
to this module for what only Python does: pacing, rolling FMUs back, reporting errors. The
reference runs only where no C compiler is at hand (or ``ROBOGEN_REFERENCE_LOOP=1``, for tests
and benchmarks).

An event iteration runs super-dense instants (t, 0), (t, 1), ... Each instant activates the due
time-based clocks (first instant only), then forwards clocks and values through a worklist in
dependency order (an FMU's outputs are read after its inputs for the instant were set), records
the instant, and closes it with fmi3UpdateDiscreteStates on every FMU. It continues while an FMU
asks for an update or a connected value changed, up to ``max_event_iterations`` instants. A
system without any FMU in Event Mode has no event iteration: its start is one row (t_start, 0).

A time event within the time tolerance of the stop time is handled at the stop time, so the last
row is always at the stop time. Before each FMI call the bindings note it, and the master notes
the time (:class:`~robogen.cosim.fmi3.CallNotes`); the rows are flushed to the results file at the
end of every event iteration. A run stopped by a signal (:mod:`robogen.cosim.signals`) ends as
any failure does: every instance terminated and freed, the rows recorded so far kept.
"""

from __future__ import annotations

import heapq
import math
import os
from dataclasses import dataclass

from signal import SIGINT

from robogen.cosim import engine, signals
from robogen.cosim.clocks import grid_index
from robogen.cosim.fmi3 import CallNotes, FMI3Error, FMUCrashed, StepResult
from robogen.cosim.instances import FmuInstance
from robogen.cosim.plan import Plan
from robogen.cosim.recorder import Pacer, Progress, Recorder
from robogen.cosim.system import Link, System, fits
from robogen.cosim.units import apply
from robogen.cosim.wiring import CLOCK, VALUE, Narrowing, find_cycle, plain
from robogen.diagnostics import Note, RobogenError
from robogen.fmu.fmi import DISCARD, status_name, tolerance


def _when(t: float) -> str:
    """A time for a message: 12 significant digits hide the grid's rounding (301 * 0.01 is 3.0100000000000002)."""
    return f"{t:.12g}"


@dataclass
class RunOptions:
    start: float
    stop: float
    step: float
    realtime: float | None = None
    progress: bool | None = None


@dataclass
class Stats:
    steps: int = 0
    event_iterations: int = 0
    instants: int = 0
    early_returns: int = 0
    rollbacks: int = 0
    end_time: float = 0.0
    terminated_by: str | None = None
    realtime: dict | None = None
    loop: str | None = None  # the loop that ran: "C" (the engine) or "Python" (the reference)


class Master:
    """One run of a system: its plan (instances in dependency order, their wiring), the results."""

    def __init__(self, system: System, plan: Plan, links: list[Link], options: RunOptions, recorder: Recorder,
                 notes: CallNotes):
        self.system, self.plan, self.options, self.recorder, self.notes = system, plan, options, recorder, notes
        self.links = links
        self.instances = list(plan.instances)
        self.by_name = plan.by_name
        self.stats = Stats()
        self.rank = {u.name: i for i, u in enumerate(self.instances)}
        self.values = plan.values
        self._columns = plain(plan.wiring.columns)
        self._stop_limit = plan.stop_limit
        self._next_event = math.inf
        self._pacer: Pacer | None = None
        self._timed: list[FmuInstance] = []  # the instances with time-based input clocks (known after setup)
        self._aperiodic: list[FmuInstance] = []  # those with aperiodic ones

    # ------------------------------------------------------------------------------------
    # The run

    def run(self) -> Stats:
        """The algorithm of the module's docstring: setup, the event iteration at the start, then
        from point to point up to the stop time, with Event Mode where an event is due. In the
        engine, unless there is no C compiler (or ROBOGEN_REFERENCE_LOOP is set)."""
        opt = self.options
        progress = Progress(opt.start, opt.stop, enabled=opt.progress)
        with signals.interruptible([SIGINT], only_if_default=True):
            try:
                self._setup()
                library = None if os.environ.get("ROBOGEN_REFERENCE_LOOP") else engine.load()
                if library is not None:
                    self.stats.loop = "C"
                    self.stats.end_time = engine.Engine(library, self).run(progress)
                else:
                    self.stats.loop = "Python"
                    self.stats.end_time = self._run_in_python(progress)
            except Narrowing as exc:
                raise self.narrowing(exc.key, exc.value) from None
            except FMI3Error as exc:
                if signals.caught() is not None:  # the FMU failed because the signal interrupted it
                    raise signals.Interrupted(signals.caught()) from None
                raise self._as_error(exc) from None
            finally:
                with signals.deferred():
                    self._shutdown()
                    progress.close()
                    self.recorder.close()
                    if self._pacer is not None:
                        self.stats.realtime = self._pacer.summary()
        return self.stats

    def start_pacing(self) -> Pacer | None:
        """The pacer of a paced run, started now: once the system is initialised (loading and
        instantiating the FMUs is not simulated time, and must not show as lag)."""
        opt = self.options
        self._pacer = Pacer(opt.realtime, opt.start) if opt.realtime else None
        return self._pacer

    def _run_in_python(self, progress: Progress) -> float:
        """The run after setup, point after point; the time reached."""
        opt = self.options
        t = opt.start
        if self.plan.event_instances:
            self._event_iteration(t)
        else:
            self._record(t, 0, event=False)
            self.recorder.flush()
        pacer = self.start_pacing()
        while not self._finished(t):
            t, event = self._advance(t, pacer)
            if event:
                self._event_mode(t)
            progress.update(t)
        return t

    def _tol(self, t: float) -> float:
        """How close to t counts as t (robogen.fmu.fmi.tolerance at the run's resolution)."""
        return tolerance(t, self.plan.resolution)

    def _finished(self, t: float) -> bool:
        return t >= self._stop_limit or self.stats.terminated_by is not None

    def terminated(self, u: FmuInstance, function: str, t: float) -> None:
        """An FMU asked to terminate: the run ends after this point (the first request is reported)."""
        if self.stats.terminated_by is None:
            self.stats.terminated_by = f"instance '{u.name}' asked to terminate in {function} at t={_when(t)}"

    # -- setup ------------------------------------------------------------------------------
    def _setup(self) -> None:
        opt = self.options
        self.notes.time[0] = opt.start
        for u in self.instances:
            u.instantiate(opt.start)
        for u in self.instances:
            u.binding.fmi3EnterInitializationMode(self.system.tolerance, opt.start, opt.stop)
        for u in self.instances:
            spec = self.system.instances[u.name]
            u.set_start_values(spec.start)
            u.schedule_clocks(opt.start, {name: timing for name, (timing, _span) in spec.clocks.items()})
        self._timed = [u for u in self.instances if u.periodic or u.aperiodic]
        self._aperiodic = [u for u in self.instances if u.aperiodic]
        # values in dependency order (Initialization Mode allows Get outputs / Set inputs)
        self._propagate(opt.start, clocks=False, event_mode=False)
        for u in self.instances:
            u.binding.fmi3ExitInitializationMode()

    # -- time ---------------------------------------------------------------------------------
    def _next_point(self, t: float) -> float:
        """The next grid point, clock tick or nextEventTime after t; one within the time tolerance
        of the stop time is the stop time (an event there is handled there)."""
        opt = self.options
        n = grid_index(opt.start, opt.step, t, self._tol(t))
        grid = opt.start + (n + 1) * opt.step
        if grid <= t + self._tol(t):
            grid = opt.start + (n + 2) * opt.step
        point = min(grid, opt.stop, self._next_event)
        return opt.stop if point >= self._stop_limit else point

    def _refresh_timing(self, t: float) -> None:
        """The earliest clock tick or nextEventTime after t, over all FMUs (after setup and each Event Mode)."""
        limit = t + self._tol(t)
        earliest = math.inf
        for u in self._timed:
            tick = u.next_tick()
            if limit < tick < earliest:
                earliest = tick
        for u in self.plan.event_instances:  # only those in Event Mode announce a next event time
            event = u.next_event_time
            if event is not None and limit < event < earliest:
                earliest = event
        self._next_event = earliest

    # -- Step Mode ------------------------------------------------------------------------------
    def _advance(self, t: float, pacer: Pacer | None) -> tuple[float, bool]:
        """From t to the next point where something happens; unless an event is due there,
        exchange values and record (t, 0). Returns (time reached, event pending)."""
        t_next = self._next_point(t)
        self.notes.time[0] = t
        if self.plan.early:
            t, event, terminating = self.step_with_early_returns(t, t_next)
        else:
            t, event, terminating = self._step_on_grid(t, t_next)
        for u, when in terminating:
            self.terminated(u, "fmi3DoStep", when)
        self.stats.steps += 1
        if pacer is not None:
            pacer.wait(t)
        if event or self._next_event <= t + self._tol(t):
            return t, True
        self.notes.time[0] = t
        self.values.exchange(self.instances)
        self._record(t, 0, event=False)
        return t, False

    def _step_on_grid(self, t: float, t_next: float) -> tuple[float, bool, list]:
        """Step every FMU from t to t_next (nobody can return early: one DoStep each, no
        bookkeeping); return (t_next, event pending, [(instance asking to terminate, time)])."""
        event, terminating = False, []
        for u in self.instances:
            result = u.binding.fmi3DoStep(t, t_next - t, True)
            u.time = t_next
            if result.terminate_simulation:
                terminating.append((u, t_next))
            event = event or (result.event_handling_needed and u.event_mode)
        return t_next, event, terminating

    def step_with_early_returns(self, t: float, end: float) -> tuple[float, bool, list]:
        """Step every FMU from t towards ``end``, early returners first; nobody goes past the
        earliest lastSuccessfulTime, and those already past it are rolled back (with FMU state)
        and stepped again, up to it. Returns (time reached by all, event pending, [(instance
        asking to terminate, its time)]); the engine calls it for every general step of a
        system whose FMUs roll back."""
        results: dict[str, StepResult] = {}  # of those that stepped
        stepped: list[tuple[FmuInstance, object, float]] = []  # (instance, its saved state, its time before)
        reached = end - self._tol(end)  # an instance at or after this time is at end
        rollback = self.plan.rollback
        for u in self.plan.step_order:
            if u.time >= reached:
                continue  # ahead after an early return it could not be rolled back from
            saved = u.binding.fmi3GetFMUState() if (rollback and u.early and u.can_state) else None
            t_u = u.time
            results[u.name] = self._do_step(u, end)
            if u.time < reached:  # early return: nobody goes past lastSuccessfulTime
                end = u.time
                reached = end - self._tol(end)
                self.stats.early_returns += 1
                for v, v_saved, t_v in stepped:
                    if v.time > end + self._tol(end) and v_saved is not None:
                        v.binding.fmi3SetFMUState(v_saved)
                        v.time = t_v
                        self.stats.rollbacks += 1
                        results[v.name] = self._do_step(v, end)
            stepped.append((u, saved, t_u))
        event, terminating = False, []
        for u in self.instances:
            result = results.get(u.name)
            if result is None:
                continue
            if result.terminate_simulation:
                terminating.append((u, u.time))
            event = event or (result.event_handling_needed and u.event_mode)
        return end, event, terminating

    def _do_step(self, u: FmuInstance, end: float) -> StepResult:
        result = u.binding.fmi3DoStep(u.time, end - u.time, not self.plan.rollback)
        u.time = result.last_successful_time if result.early_return else end
        return result

    # -- Event Mode -------------------------------------------------------------------------
    def _event_mode(self, t: float) -> None:
        for u in self.plan.event_instances:
            u.binding.fmi3EnterEventMode()
            u.new_instant()
        self._event_iteration(t)

    def _event_iteration(self, t: float) -> None:
        self.stats.event_iterations += 1
        self.notes.time[0] = t
        close = self._tol(t)
        for u in self._timed:
            u.activate_due_clocks(t, close)
        k = 0
        ticked_all: dict[str, set[int]] = {u.name: set() for u in self._aperiodic}  # for the changing clocks' intervals
        last = self.system.max_event_iterations - 1
        while True:
            self.stats.instants += 1
            self._propagate(t, clocks=True, event_mode=True)
            self._record(t, k)
            self._log_events(t, k)
            for u in self._aperiodic:
                ticked_all[u.name] |= u.active
            ticked = {u.name: set(u.active) for u in self.instances} if k >= last else None  # for the Zeno error
            needs = self._update_discrete_states(t)
            k += 1
            changed = self.values.exchange(self.instances) if not needs and self.values.connected else False
            if not needs and not changed:
                break
            if k >= self.system.max_event_iterations:
                self.zeno(t, k, needs, ticked)
        for u in self._timed:
            u.read_intervals(t, ticked_all.get(u.name, ()))
        self._record(t, k)
        self.recorder.flush()
        for u in self.plan.event_instances:
            u.binding.fmi3EnterStepMode()
        self._refresh_timing(t)

    def _update_discrete_states(self, t: float) -> list[FmuInstance]:
        """Close an instant on every FMU in Event Mode; those that ask for another."""
        needs = []
        for u in self.plan.event_instances:
            states = u.binding.fmi3UpdateDiscreteStates()
            u.active.clear()
            u.new_instant()
            u.next_event_time = states.next_event_time if states.next_event_time_defined else None
            if states.discrete_states_need_update:
                needs.append(u)
            if states.terminate_simulation:
                self.terminated(u, "fmi3UpdateDiscreteStates", t)
        return needs

    def _propagate(self, t: float, clocks: bool, event_mode: bool) -> None:
        """Forward clocks and values in dependency order until nothing new happens at this instant
        (without connections: read each instance's output clocks, nothing to forward)."""
        instances = self.plan.event_instances if event_mode else self.instances
        if not self.plan.routes and not self.plan.domain_routes and not self.values.connected:
            if clocks:
                for u in instances:
                    if u.out_clocks:
                        u.active.update(u.read_clocks())
            return
        heap = [(self.rank[u.name], u.name) for u in instances]
        heapq.heapify(heap)
        queued = {u.name for u in instances}
        forwarded: set[tuple[str, int]] = set()
        budget = 50 * (len(self.instances) + 1) ** 2
        woke: dict[tuple[str, str], int] = {}  # how often a set b's inputs, for naming an algebraic loop
        while heap:
            budget -= 1
            if budget < 0:
                raise self.algebraic_loop(t, woke)
            _, name = heapq.heappop(heap)
            queued.discard(name)
            u = self.by_name[name]
            woken = self._forward_clocks(u, forwarded) if clocks else set()
            woken |= self.values.forward(u)
            for w in woken:
                woke[name, w] = woke.get((name, w), 0) + 1
            for w in woken:
                if w not in queued and (not event_mode or self.by_name[w].event_mode):
                    queued.add(w)
                    heapq.heappush(heap, (self.rank[w], w))

    def algebraic_loop(self, t: float, woke: dict[tuple[str, str], int]) -> RobogenError:
        """The error for values that keep changing at t, located at the connections of the loop
        (among the instances that set each other's inputs most often)."""
        busiest = max(woke.values(), default=0)
        edges: dict[str, set[str]] = {}
        for (a, b), count in woke.items():
            if 2 * count >= busiest:
                edges.setdefault(a, set()).add(b)
        loop = self._connections_around(find_cycle(edges), clocks=False)
        where = " -> ".join([*(link.source for link in loop), loop[0].source]) if loop else "the connected instances"
        notes = [Note(f"'{link.source}.{link.src.name} -> {link.target}.{link.dst.name}' is part of the loop", link.span)
                 for link in loop[1:]]
        return RobogenError.at(f"values did not settle at t={_when(t)}: an algebraic loop {where} "
                               "(each instance's output changes the next one's input)",
                               loop[0].span if loop else self.system.span("connections"), *notes)

    def narrowing(self, key: tuple[str, int], value) -> RobogenError:
        """The error for a connected value that does not fit its input's type, at the connection."""
        target, vr = key
        link = next(k for k in self.links if k.target == target and k.dst.value_reference == vr)
        return RobogenError.at(f"connection '{link.source}.{link.src.name} -> {link.target}.{link.dst.name}': the value "
                               f"{value!r} of {link.src.type} '{link.source}.{link.src.name}' does not fit the input's type "
                               f"{link.dst.type} at t={_when(self.notes.time[0])}; the results recorded so far are kept",
                               link.span)

    def _connections_around(self, cycle: list[str], clocks: bool) -> list[Link]:
        """One connection (of clocks, or of values) for each step a -> b of an instance cycle."""
        loop = []
        for a, b in zip(cycle, cycle[1:]):
            link = next((k for k in self.links if k.source == a and k.target == b and k.src.is_clock == clocks), None)
            if link is not None:
                loop.append(link)
        return loop

    def _forward_clocks(self, u: FmuInstance, forwarded: set[tuple]) -> set[str]:
        """Note u's active output clocks; set the clocks (and clocked values) they drive, once per
        instant: the values a clock carries read with one Get call per type, and set with one
        Set call per type on each target. Then the values crossing clock domains at u's active
        clocks (in the order of their value references): held into inputs that are not clocked,
        sampled into u's clocked inputs. The names of the instances set."""
        woken = set()
        for vr in u.read_clocks():
            u.active.add(vr)
            if (u.name, vr) in forwarded:
                continue
            forwarded.add((u.name, vr))
            for target, target_clock, sources, batches in self.plan.routes.get((u.name, vr), ()):
                if target.event_mode:
                    self._forward(u, target, target_clock, sources, batches)
                    woken.add(target.name)
        for vr in u.clock_vrs:
            if vr not in u.active or (u.name, vr, "domains") in forwarded or (u.name, vr) not in self.plan.domain_routes:
                continue
            forwarded.add((u.name, vr, "domains"))
            for source, target, target_clock, sources, batches in self.plan.domain_routes[u.name, vr]:
                self._forward(source, target, target_clock, sources, batches)
                woken.add(target.name)
        return woken

    @staticmethod
    def _forward(source: FmuInstance, target: FmuInstance, target_clock: int | None, sources, batches) -> None:
        """One route: the target clock set (unless active, or none), the values it carries, each
        converted in one step as the engine converts it (its scale, then the input's type)."""
        if target_clock is not None and target_clock not in target.active:
            target.set_clocks([target_clock])
        if sources:
            values = source.clocked_values(sources)
            for fmi_type, vrs, indices, scales in batches:
                carried = [apply(scale, values[i]) for i, scale in zip(indices, scales)]
                for vr, value in zip(vrs, carried):
                    if not fits(fmi_type, value):
                        raise Narrowing((target.name, vr), value)
                target.set_values(fmi_type, vrs, carried)

    def zeno(self, t: float, k: int, needs: list[FmuInstance], ticked: dict) -> None:
        active = [f"{n}.{self.by_name[n].by_vr[vr].name}" for n, vrs in ticked.items() for vr in sorted(vrs)]
        who = ", ".join(f"'{u.name}'" for u in needs) or "none (connected values keep changing)"
        diag_notes = [Note(f"instance '{u.name}' is declared here", u.span) for u in needs]
        diag_notes.append(Note(f"clocks active in the last instant: {', '.join(active) or 'none'}"))
        loop = self._clock_loop(ticked)
        if loop:
            names = ", ".join(f"'{k.source}.{k.src.name} -> {k.target}.{k.dst.name}'" for k in loop)
            diag_notes.append(Note(f"the active clocks trigger each other around the loop {names}", loop[0].span))
        raise RobogenError.at(
            f"event iteration at t={_when(t)} did not settle after {k} super-dense instants (Zeno behaviour): "
            f"FMUs still asking for an update: {who}", (needs[0].span if needs else self.system.span("experiment")), *diag_notes)

    def _clock_loop(self, ticked: dict[str, set[int]]) -> list[Link]:
        """The connections of a loop of clocks active in the last instant (an instance may drive
        its own input clock), or none."""
        drives: dict[str, set[str]] = {}
        for (source, vr), routes in self.plan.wiring.clock_routes.items():
            if vr in ticked.get(source, ()):
                drives.setdefault(source, set()).update(r.target.name for r in routes if r.target_clock in ticked[r.target.name])
        return self._connections_around(find_cycle(drives), clocks=True)

    # -- recording ----------------------------------------------------------------------------
    def _record(self, t: float, k: int, event: bool = True) -> None:
        """Record the row (t, k): of an event iteration, or a plain one (``event`` false, which
        decimation may drop)."""
        # Instances with value connections were read while forwarding; read the others here.
        for u in self.plan.wiring.record_reads:
            u.read_outputs()
        row = [t, k]
        for kind, u, var, reader, index in self._columns:
            if kind == VALUE:
                row.append(reader.values[index])
            elif kind == CLOCK:
                row.append(1 if var.value_reference in u.active else 0)
            else:
                row.append(None)  # a clocked value: filled below while its clock is active
        for u, cells in self.plan.clocked_columns:
            if u.active:
                live = [(position, var) for position, var, clocks in cells if not clocks.isdisjoint(u.active)]
                if live:
                    for (position, _), value in zip(live, u.clocked_values([var for _, var in live])):
                        row[position] = value
        if event:
            self.recorder.append_event_row(row)
        else:
            self.recorder.append_row(row)

    def _log_events(self, t: float, k: int) -> None:
        if self.plan.event_values is None:
            return
        for u in self.instances:
            for vr in sorted(u.active):
                variables = self.plan.event_values[u.name].get(vr, [])
                values = dict(zip((v.name for v in variables), u.clocked_values(variables)))
                self.recorder.event(t, k, u.name, u.by_vr[vr].name, values)

    # -- errors and shutdown --------------------------------------------------------------------
    def _as_error(self, exc: FMI3Error) -> RobogenError:
        """A failed FMI call as a located error, at the failing instance's time."""
        u = self.by_name[exc.instance]
        u.failed_status = exc.status
        kept = "; the results recorded so far are kept"
        if isinstance(exc, FMUCrashed):
            return RobogenError.at(f"instance '{exc.instance}' crashed ({exc.how}) in {exc.function} at t={_when(u.time)}{kept}",
                                   u.span, Note("the instance ran in a process of its own (isolate = true); the run stopped cleanly"))
        what = "discarded the call (fmi3Discard; the master does not retry)" if exc.status == DISCARD else f"returned {status_name(exc.status)}"
        notes = [Note(f"the FMU logged: {exc.message}")] if exc.message else []
        return RobogenError.at(f"instance '{exc.instance}': {exc.function} {what} at t={_when(u.time)}{kept}", u.span, *notes)

    def _shutdown(self) -> None:
        """fmi3Terminate every healthy instance, free all but those that returned fmi3Fatal."""
        for u in self.instances:
            u.shut_down()
