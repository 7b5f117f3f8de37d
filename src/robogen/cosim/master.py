"""The co-simulation algorithm: FMI 3.0 Co-Simulation with Event Mode, clocks and early return.

It follows docs/fmi3.md §1.5 (shared/docs) step by step:

    setup       instantiate (eventModeUsed where hasEventMode, earlyReturnAllowed where the FMU
                might return early), Initialization Mode in dependency order, exit
    events      event iteration at (t_start, 0)
    loop        t_next = min(next grid point, next clock tick, nextEventTime, stop)
                step every FMU (early returners first); on an early return the others step only
                to lastSuccessfulTime, or are rolled back to it with FMU state
                on an event (eventHandlingNeeded, a tick, a reached nextEventTime): Event Mode on
                every FMU that uses it, event iteration at t, Step Mode
                else: exchange values, record (t, 0)

An event iteration runs super-dense instants (t, 0), (t, 1), ... Each instant activates the due
time-based clocks (first instant only), then forwards clocks and values through a worklist in
dependency order (an FMU's outputs are read after its inputs for the instant were set), records
the instant, and closes it with fmi3UpdateDiscreteStates on every FMU. It continues while an FMU
asks for an update or a connected value changed, up to ``max_event_iterations`` instants.
"""

from __future__ import annotations

import heapq
import math
from dataclasses import dataclass, field

from robogen.cosim.fmi3 import DISCARD, FATAL, ffi, FMI3Error, INTERVAL_CHANGED, INTERVAL_NOT_YET_KNOWN, status_name, vr_array
from robogen.cosim.recorder import Pacer, Progress, Recorder
from robogen.cosim.system import Link, System
from robogen.cosim.instances import APERIODIC, PERIODIC, Aperiodic, Periodic, FmuInstance, tolerance
from robogen.diagnostics import Note, RobogenError


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


@dataclass
class _ClockRoute:
    """Forward one output clock: set the target clock, then copy the clocked values."""

    target: FmuInstance
    target_clock: int
    values: list = field(default_factory=list)  # (source var, target var)


class Master:
    def __init__(self, system: System, units: list[FmuInstance], links: list[Link], record: list, options: RunOptions, recorder: Recorder):
        self.system, self.options, self.recorder = system, options, recorder
        self.instances = units
        self.by_name = {u.name: u for u in units}
        self.stats = Stats()
        self.rank = {u.name: i for i, u in enumerate(units)}  # units arrive in dependency order
        self.event_instances = [u for u in units if u.event_mode]
        self.step_order = [u for u in units if u.early] + [u for u in units if not u.early]
        self.rollback = len([u for u in units if u.early]) > 1
        self.any_early = any(u.early for u in units)
        # the plain-step loop needs: nobody returns early, no call trace
        self.plain_ok = not self.any_early and all(u.binding.trace is None for u in units)
        self._stepper = None  # the C plain-step loop, built at its first use (False: unavailable)
        self._next_event = math.inf
        self._wire(links, record)

    # ------------------------------------------------------------------------------------
    # Wiring: who reads what, which clock goes where

    def _wire(self, links: list[Link], record: list) -> None:
        observe: dict[str, list] = {u.name: [] for u in self.instances}
        watch: dict[str, list[int]] = {u.name: [] for u in self.instances}
        self.value_links: dict[str, list] = {u.name: [] for u in self.instances}  # source -> [(vr, target, var)]
        self.clock_routes: dict[tuple[str, int], list[_ClockRoute]] = {}
        self.last_set: dict[tuple[str, int], object] = {}
        for l in links:
            src, dst = self.by_name[l.source], self.by_name[l.target]
            if l.src.is_clock:
                watch[src.name].append(l.src.value_reference)
                self.clock_routes.setdefault((src.name, l.src.value_reference), []).append(_ClockRoute(dst, l.dst.value_reference))
            elif not l.src.is_clocked:
                observe[src.name].append(l.src)
                self.value_links[src.name].append((l.src.value_reference, dst, l.dst))
        for l in links:  # clocked values ride on their clock's route
            if l.src.is_clocked and not l.src.is_clock:
                for route in (r for c in l.src.clocks for r in self.clock_routes.get((l.source, c), [])):
                    if route.target.name == l.target and route.target_clock in l.dst.clocks:
                        route.values.append((l.src, l.dst))
        # recorded columns: (kind, unit, var)
        self.columns = []
        for unit, var in record:
            if var.is_clock:
                kind = "clock"
                if var.causality == "output":
                    watch[unit.name].append(var.value_reference)
            elif var.is_clocked:
                kind = "clocked"
                watch[unit.name] += [c for c in var.clocks if c in unit.by_vr and unit.by_vr[c].causality == "output"]
            else:
                kind = "value"
                observe[unit.name].append(var)
            self.columns.append((kind, unit, var))
        for u in self.instances:
            u.observe(observe[u.name])
            u.watch_clocks(watch[u.name])
        self.value_columns = [(kind, u, var, u.reader_of.get(var.value_reference)) for kind, u, var in self.columns]
        recorded = {u.name for kind, u, _ in self.columns if kind == "value"}
        self.record_reads = [u for u in self.instances if u.name in recorded and not self.value_links[u.name]]
        self.clocked_by = {}
        for kind, u, var in self.columns:
            if kind == "clocked":
                self.clocked_by[(u.name, var.value_reference)] = var.clocks

    # ------------------------------------------------------------------------------------
    # The run

    def run(self) -> Stats:
        opt = self.options
        progress = Progress(opt.start, opt.stop, enabled=opt.progress)
        pacer: Pacer | None = None
        self._t = opt.start
        try:
            self._setup()
            t = opt.start
            self._event_iteration(t)
            # Pacing starts once the system is initialised: loading and instantiating the FMUs
            # is not simulated time, and must not show as lag.
            pacer = Pacer(opt.realtime, opt.start) if opt.realtime else None
            stop_limit = opt.stop - tolerance(opt.stop)
            while t < stop_limit and self.stats.terminated_by is None:
                if self.plain_ok:
                    t = self._plain_steps(t, pacer, progress)
                    if t >= stop_limit or self.stats.terminated_by is not None:
                        break
                t_next = self._next_point(t)
                self._t = t
                t, event = self._step(t, t_next)
                self._t = t
                self.stats.steps += 1
                if pacer is not None:
                    pacer.wait(t)
                if event or self._next_event <= t + tolerance(t):
                    for u in self.event_instances:
                        u.binding.fmi3EnterEventMode()
                    self._event_iteration(t)
                else:
                    self._exchange_values(t)
                    self._record(t, 0)
                progress.update(t)
            self.stats.end_time = t
        except FMI3Error as exc:
            raise self._as_error(exc) from None
        finally:
            self._shutdown()
            progress.close()
            self.recorder.close()
            if pacer is not None:
                self.stats.realtime = pacer.summary()
        return self.stats

    # -- setup ------------------------------------------------------------------------------
    def _setup(self) -> None:
        opt = self.options
        for u in self.instances:
            u.time = opt.start
            u.binding.fmi3InstantiateCoSimulation(u.md.instantiation_token, u.resource_path(), False, False,
                                               eventModeUsed=u.event_mode, earlyReturnAllowed=u.early)
        for u in self.instances:
            u.binding.fmi3EnterInitializationMode(self.system.tolerance, opt.start, opt.stop)
        for u in self.instances:
            self._start_values(u)
            self._clock_timing(u)
        # values in dependency order (Initialization Mode allows Get outputs / Set inputs)
        self._propagate(opt.start, clocks=False, event_mode=False)
        for u in self.instances:
            u.binding.fmi3ExitInitializationMode()

    def _start_values(self, u: FmuInstance) -> None:
        spec = self.system.instances[u.name]
        by_type: dict[str, tuple[list, list]] = {}
        for name, (value, _span) in spec.start.items():
            var = u.vars[name]
            vrs, vals = by_type.setdefault(var.type, ([], []))
            vrs.append(var.value_reference)
            vals.append(value)
        for fmi_type, (vrs, vals) in sorted(by_type.items()):
            u.set_values(fmi_type, vrs, vals)

    def _clock_timing(self, u: FmuInstance) -> None:
        spec = self.system.instances[u.name]
        start = self.options.start
        for var in u.md.variables:
            if not var.is_clock or var.causality != "input":
                continue
            kind = var.interval_variability
            vr = vr_array([var.value_reference])
            if kind in PERIODIC:
                override = spec.clocks.get(var.name, ({}, None))[0]
                if "interval" in override:
                    u.binding.fmi3SetIntervalDecimal(vr, 1, [override["interval"]])
                if "shift" in override:
                    u.binding.fmi3SetShiftDecimal(vr, 1, [override["shift"]])
                interval = override.get("interval", var.interval)
                shift = override.get("shift", var.shift)
                if kind != "constant" and (interval is None or shift is None):
                    if interval is None:
                        interval = u.binding.fmi3GetIntervalDecimal(vr, 1)[0][0]
                    if shift is None:
                        shift = u.binding.fmi3GetShiftDecimal(vr, 1)[0]
                if interval is None or interval <= 0:
                    raise RobogenError.at(f"instance '{u.name}': periodic clock '{var.name}' has no positive interval", u.span)
                u.periodic.append(Periodic(var, start, float(interval), float(shift or 0.0)))
            elif kind in APERIODIC:
                intervals, qualifiers = u.binding.fmi3GetIntervalDecimal(vr, 1)
                ok = qualifiers[0] != INTERVAL_NOT_YET_KNOWN
                u.aperiodic.append(Aperiodic(var, start + intervals[0] if ok else None))

    # -- time ---------------------------------------------------------------------------------
    def _next_point(self, t: float) -> float:
        opt = self.options
        n = math.floor((t - opt.start) / opt.step + 1e-9)
        grid = opt.start + (n + 1) * opt.step
        if grid <= t + tolerance(t):
            grid = opt.start + (n + 2) * opt.step
        return min(grid, opt.stop, self._next_event)

    def _plain_steps(self, t: float, pacer, progress) -> float:
        """The same steps as the general loop, specialised for the quiet stretch up to the next
        time event: no early returns, so every FMU steps on the grid; stops after the first step
        after which an FMU asks for Event Mode or to terminate. Returns the time reached."""
        opt = self.options
        start, h = opt.start, opt.step
        horizon = min(self._next_event, opt.stop)
        n = math.floor((t - start) / h + 1e-9)
        calls = [(u, u.binding.lib.fmi3DoStep, u.binding.handle, *u.binding.step_outputs) for u in self.instances]
        event_instances = self.event_instances
        linked = any(self.value_links.values())
        stats = self.stats
        # a step row: values from the readers' buffers, clocks 0, clocked values empty
        cols = [(reader[0].values, reader[1]) if kind == "value" else ((0,) if kind == "clock" else (None,), 0)
                for kind, _u, _v, reader in self.value_columns]
        recorder = self.recorder
        reads = [(r.c_function, u.binding.handle, r.c_vrs, r.n, r.buffer, r, u.binding)
                 for u in self.instances for r in u.readers if r.fmi_type != "String"]
        slow_reads = [u for u in self.instances if any(r.fmi_type == "String" for r in u.readers)]
        rows_append = recorder.rows.append if recorder.keep_rows and recorder._writer is None else None
        limit = horizon - 1e-9 * max(1.0, abs(horizon))  # the last grid point before the horizon
        show_progress = progress.enabled
        if pacer is None and not linked and not slow_reads:
            stepper = self._c_stepper(calls, reads)
            if stepper is not None:
                return self._plain_steps_in_c(stepper, t, n, start, h, limit, calls, reads, progress)
        # Counters live in locals while stepping (this loop runs millions of times) and are
        # added to the statistics and the recorder on the way out.
        steps = rows = 0
        try:
            while True:
                n += 1
                t_next = start + n * h
                if t_next >= limit or t_next <= t:
                    return t
                event = terminated = False
                for u, do_step, handle, ev, term, er, lst in calls:
                    status = do_step(handle, t, t_next - t, True, ev, term, er, lst)
                    if status > 1:
                        u.binding._fail("fmi3DoStep", status)
                    if ev[0] or term[0]:
                        event = event or (ev[0] and u.event_mode)
                        if term[0]:
                            terminated = True
                            if stats.terminated_by is None:
                                stats.terminated_by = f"instance '{u.name}' asked to terminate in fmi3DoStep at t={_when(t_next)}"
                    u.time = t_next
                t = self._t = t_next
                steps += 1
                if pacer is not None:
                    pacer.wait(t)
                if event:
                    for u in event_instances:
                        u.binding.fmi3EnterEventMode()
                    stats.steps += steps
                    steps = 0
                    self._event_iteration(t)
                    return t
                if linked:
                    self._exchange_values(t)
                else:
                    for get, handle, vrs, count, buf, r, inst in reads:
                        status = get(handle, vrs, count, buf, count)
                        if status > 1:
                            inst._fail(r.function, status)
                    for u in slow_reads:
                        u.read_outputs()
                row = [t, 0]
                row += [src[i] for src, i in cols]
                if rows_append is not None:
                    rows_append(row)
                    rows += 1
                else:
                    recorder.row(row)
                if show_progress:
                    progress.update(t)
                if terminated:
                    return t
        finally:
            stats.steps += steps
            recorder.count += rows

    def _c_stepper(self, calls, reads):
        """The C plain-step loop bound to this system (built once per run), or None."""
        if self._stepper is False:
            return None
        if self._stepper is None:
            from robogen.cosim import stepper as c_stepper

            lib = c_stepper.load()
            if lib is None:
                self._stepper = False
                return None
            units = [(do_step, handle) for _u, do_step, handle, *_ in calls]
            read_index = {id(r): i for i, (*_, r, _inst) in enumerate(reads)}
            c_reads = [(get, handle, vrs, count, buf, r.fmi_type) for get, handle, vrs, count, buf, r, _inst in reads]
            c_cols = []
            for kind, _u, _v, reader in self.value_columns:
                if kind == "value":
                    c_cols.append((read_index[id(reader[0])], reader[1]))
                else:
                    c_cols.append(("const", 0 if kind == "clock" else None))
            event_mode = [u.event_mode for u, *_ in calls]
            self._stepper = c_stepper.Stepper(lib, units, c_reads, event_mode, c_cols)
        return self._stepper

    def _plain_steps_in_c(self, stepper, t: float, n: int, start: float, h: float, limit: float,
                          calls, reads, progress) -> float:
        """_plain_steps through the C stepper: the same steps, rows and outcomes, chunk by chunk."""
        from robogen.cosim.stepper import CHUNK, WHY_EVENT, WHY_GET_FAILED, WHY_LIMIT, WHY_STEP_FAILED

        stats = self.stats
        while True:
            steps, rows, n, t_new, why, who, status = stepper.run(start, h, n, t, limit)
            self.recorder.rows_many(stepper.rows(rows))
            stats.steps += steps
            if steps:
                t = self._t = t_new
                for u, *_ in calls:
                    u.time = t
            if why == WHY_STEP_FAILED:
                calls[who][0].binding._fail("fmi3DoStep", status)
            if why == WHY_GET_FAILED:
                get, handle, vrs, count, buf, r, inst = reads[who]
                inst._fail(r.function, status)
            flags = stepper.s.flags
            for i, (u, *_) in enumerate(calls):
                if steps and flags[4 * i + 1] and stats.terminated_by is None:
                    stats.terminated_by = f"instance '{u.name}' asked to terminate in fmi3DoStep at t={_when(t)}"
            if progress.enabled:
                progress.update(t)
            if why == WHY_EVENT:
                for u in self.event_instances:
                    u.binding.fmi3EnterEventMode()
                self._event_iteration(t)
                return t
            if why != WHY_LIMIT or rows < CHUNK:
                return t

    def _refresh_timing(self, t: float) -> None:
        """The earliest clock tick or nextEventTime after t, over all FMUs (after setup and each Event Mode)."""
        limit = t + tolerance(t)
        times = [math.inf]
        for u in self.instances:
            tick = u.next_tick()
            times.append(tick if tick > limit else math.inf)
            if u.next_event_time is not None and u.next_event_time > limit:
                times.append(u.next_event_time)
        self._next_event = min(times)

    def _step(self, t: float, t_next: float) -> tuple[float, bool]:
        """Step every FMU from t towards t_next; return (time reached by all, event pending)."""
        if not self.any_early:  # nobody can return early: one DoStep each, no bookkeeping
            event = False
            for u in self.instances:
                ev, term, _er, _lst = u.binding.fmi3DoStep(t, t_next - t, True)
                u.time = t_next
                if term and self.stats.terminated_by is None:
                    self.stats.terminated_by = f"instance '{u.name}' asked to terminate in fmi3DoStep at t={_when(t_next)}"
                event = event or (ev and u.event_mode)
            return t_next, event
        end = t_next
        stepped: list[tuple[FmuInstance, object, float]] = []
        for u in self.instances:
            u.flags = (False, False, False, u.time)
        for u in self.step_order:
            if u.time >= end - tolerance(end):
                continue  # ahead after an early return it could not be rolled back from
            saved = u.binding.fmi3GetFMUState() if (self.rollback and u.early and u.can_state) else None
            t_u = u.time
            self._do_step(u, end)
            if u.time < end - tolerance(end):  # early return: nobody goes past lastSuccessfulTime
                end = u.time
                self.stats.early_returns += 1
                for v, v_saved, t_v in stepped:
                    if v.time > end + tolerance(end) and v_saved is not None:
                        v.binding.fmi3SetFMUState(v_saved)
                        v.time = t_v
                        self.stats.rollbacks += 1
                        self._do_step(v, end)
            stepped.append((u, saved, t_u))
        event = False
        for u in self.instances:
            ev, term, _er, _lst = u.flags
            if term and self.stats.terminated_by is None:
                self.stats.terminated_by = f"instance '{u.name}' asked to terminate in fmi3DoStep at t={_when(u.time)}"
            event = event or (ev and u.event_mode)
        return end, event

    def _do_step(self, u: FmuInstance, end: float) -> None:
        ev, term, er, lst = u.binding.fmi3DoStep(u.time, end - u.time, not self.rollback)
        u.flags = (ev, term, er, lst)
        u.time = lst if er else end

    # -- Event Mode -------------------------------------------------------------------------
    def _event_iteration(self, t: float) -> None:
        self.stats.event_iterations += 1
        limit = t + tolerance(t)
        for u in self.instances:
            due = [p for p in u.periodic if p.next_time() <= limit] + [a for a in u.aperiodic if a.next is not None and a.next <= limit]
            if due:
                u.set_clocks(sorted(c.var.value_reference for c in due))
                for c in due:
                    if isinstance(c, Periodic):
                        c.k = max(c.k + 1, math.floor((t - c.start - c.shift) / c.interval + 1e-9) + 1)
                    else:
                        c.next = None
        k = 0
        ticked_all: dict[str, set[int]] = {u.name: set() for u in self.instances}
        while True:
            self.stats.instants += 1
            self._propagate(t, clocks=True, event_mode=True)
            self._record(t, k)
            self._log_events(t, k)
            ticked = {u.name: set(u.active) for u in self.instances}
            for name, vrs in ticked.items():
                ticked_all[name] |= vrs
            needs = []
            for u in self.event_instances:
                need, term, defined, nxt = u.binding.fmi3UpdateDiscreteStates()
                u.active.clear()
                u.next_event_time = nxt if defined else None
                if need:
                    needs.append(u)
                if term and self.stats.terminated_by is None:
                    self.stats.terminated_by = f"instance '{u.name}' asked to terminate in fmi3UpdateDiscreteStates at t={_when(t)}"
            k += 1
            changed = self._exchange_values(t) if not needs else False
            if not needs and not changed:
                break
            if k >= self.system.max_event_iterations:
                self._zeno(t, k, needs, ticked)
        self._read_intervals(t, ticked_all)
        self._record(t, k)
        for u in self.event_instances:
            u.binding.fmi3EnterStepMode()
        self._refresh_timing(t)

    def _read_intervals(self, t: float, ticked: dict) -> None:
        for u in self.instances:
            for a in u.aperiodic:
                kind, vr = a.var.interval_variability, a.var.value_reference
                if kind == "countdown" or vr in ticked[u.name]:
                    intervals, qualifiers = u.binding.fmi3GetIntervalDecimal(vr_array([vr]), 1)
                    if qualifiers[0] == INTERVAL_CHANGED or (qualifiers[0] != INTERVAL_NOT_YET_KNOWN and a.next is None):
                        a.next = t + intervals[0]

    def _propagate(self, t: float, clocks: bool, event_mode: bool) -> None:
        """Forward clocks and values in dependency order until nothing new happens at this instant."""
        units = self.event_instances if event_mode else self.instances
        heap = [(self.rank[u.name], u.name) for u in units]
        heapq.heapify(heap)
        queued = {u.name for u in units}
        forwarded: set[tuple[str, int]] = set()
        budget = 50 * (len(self.instances) + 1) ** 2
        while heap:
            budget -= 1
            if budget < 0:
                names = ", ".join(sorted(queued))
                raise RobogenError.at(f"values did not settle at t={_when(t)}: an algebraic loop between {names}", self.system.span("connections"))
            _, name = heapq.heappop(heap)
            queued.discard(name)
            u = self.by_name[name]
            woken: set[str] = set()
            if clocks:
                for vr in u.read_clocks():
                    u.active.add(vr)
                    if (name, vr) in forwarded:
                        continue
                    forwarded.add((name, vr))
                    for route in self.clock_routes.get((name, vr), ()):
                        dst = route.target
                        if not dst.event_mode:
                            continue
                        if route.target_clock not in dst.active:
                            dst.set_clocks([route.target_clock])
                        for src_var, dst_var in route.values:
                            value = u.get_one(src_var)
                            dst.set_values(dst_var.type, [dst_var.value_reference], [value])
                        woken.add(dst.name)
            woken |= self._forward_values(u, t)
            for w in woken:
                if w not in queued and (not event_mode or self.by_name[w].event_mode):
                    queued.add(w)
                    heapq.heappush(heap, (self.rank[w], w))

    def _forward_values(self, u: FmuInstance, t: float) -> set[str]:
        """Read u's observed outputs; set connected inputs whose value changed. Returns targets set."""
        links = self.value_links[u.name]
        if not links:
            return set()  # nothing to forward: recording reads what it records
        u.read_outputs()
        woken = set()
        for vr, dst, dst_var in links:
            value = u.value(vr)
            key = (dst.name, dst_var.value_reference)
            if self.last_set.get(key, _UNSET) != value:
                self.last_set[key] = value
                dst.set_values(dst_var.type, [dst_var.value_reference], [value])
                woken.add(dst.name)
        return woken

    def _exchange_values(self, t: float) -> bool:
        """Step Mode (or after the last update): read outputs, set changed inputs. True if any changed."""
        changed = False
        for u in self.instances:
            if self._forward_values(u, t):
                changed = True
        return changed

    def _zeno(self, t: float, k: int, needs: list[FmuInstance], ticked: dict) -> None:
        active = [f"{n}.{self.by_name[n].by_vr[vr].name}" for n, vrs in ticked.items() for vr in sorted(vrs)]
        who = ", ".join(f"'{u.name}'" for u in needs) or "none (connected values keep changing)"
        diag_notes = [Note(f"instance '{u.name}' is declared here", u.span) for u in needs]
        diag_notes.append(Note(f"clocks active in the last instant: {', '.join(active) or 'none'}"))
        raise RobogenError.at(
            f"event iteration at t={_when(t)} did not settle after {k} super-dense instants (Zeno behaviour): "
            f"FMUs still asking for an update: {who}", (needs[0].span if needs else self.system.span("experiment")), *diag_notes)

    # -- recording ----------------------------------------------------------------------------
    def _record(self, t: float, k: int) -> None:
        # Instances with value connections were read while forwarding; read the others here.
        for u in self.record_reads:
            u.read_outputs()
        row = [t, k]
        for kind, u, var, reader in self.value_columns:
            if kind == "value":
                r, i = reader
                row.append(r.values[i])
            elif kind == "clock":
                row.append(1 if var.value_reference in u.active else 0)
            elif any(c in u.active for c in var.clocks):
                row.append(u.get_one(var))
            else:
                row.append(None)
        self.recorder.row(row)

    def _log_events(self, t: float, k: int) -> None:
        if not self.recorder.recording_events:
            return
        for u in self.instances:
            for vr in sorted(u.active):
                clock = u.by_vr[vr]
                values = {v.name: u.get_one(v) for v in u.md.variables
                          if vr in v.clocks and not v.is_clock and v.causality in ("input", "output")}
                self.recorder.event(t, k, u.name, clock.name, values)

    # -- errors and shutdown --------------------------------------------------------------------
    def _as_error(self, exc: FMI3Error) -> RobogenError:
        u = self.by_name.get(exc.instance)
        if u is not None:
            u.failed_status = exc.status
        what = "discarded the call (fmi3Discard; the master does not retry)" if exc.status == DISCARD else f"returned {status_name(exc.status)}"
        notes = [Note(f"the FMU logged: {exc.message}")] if exc.message else []
        return RobogenError.at(f"instance '{exc.instance}': {exc.function} {what} at t={_when(self._t)}; the results recorded so far are kept",
                               u.span if u else None, *notes)

    def _shutdown(self) -> None:
        """fmi3Terminate every healthy instance, free all but those that returned fmi3Fatal."""
        for u in self.instances:
            if u.failed_status == FATAL or u.binding.handle == ffi.NULL:
                continue  # never call an instance again after fmi3Fatal
            if u.failed_status is None:
                try:
                    u.binding.fmi3Terminate()
                except FMI3Error:
                    pass
            u.binding.fmi3FreeInstance()


_UNSET = object()
