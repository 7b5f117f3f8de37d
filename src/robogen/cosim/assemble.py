"""From a system file to a ready :class:`~robogen.cosim.master.Master`: load, check, order, wire.

:func:`build_master` reads the system file, checks that the results files are not among its
inputs, extracts and checks each FMU once (:class:`FmuCache`, which also removes the extracted
files and stops the worker processes when the run is over), orders the instances for the
dependency order of their connections and binds each to its FMU's binary: in this process, or,
for an isolated instance, in a worker process of its own (:mod:`robogen.cosim.proxy`).
"""

from __future__ import annotations

import math
import shutil
import sys
import tempfile
from pathlib import Path
from typing import Callable

from robogen.cosim import interfaces
from robogen.cosim.fmi3 import Binding, CallNotes, Library, LoadError
from robogen.cosim.instances import FmuInstance
from robogen.cosim.master import Master, RunOptions
from robogen.cosim.plan import make_plan
from robogen.cosim.player import ScenarioBinding, player_description, player_links
from robogen.cosim.proxy import ProxyBinding
from robogen.cosim.recorder import Recorder
from robogen.cosim.ssp_read import is_ssp, load_ssp
from robogen.cosim.scenario import load_scenario, timeline
from robogen.cosim.shared import SHARED
from robogen.cosim.system import Link, System, load_system, record_list, resolve
from robogen.cosim.clocks import PERIODIC
from robogen.diagnostics import Diagnostic, DiagnosticSink, Note, RobogenError, SourceMap, Span, did_you_mean, render, warning
from robogen.fmu.extract import extract_fmu, needed_to_run
from robogen.fmu.fmi import TIME_ULPS, resolvable, time_resolution
from robogen.fmu.headers import FMI2_PLATFORM, PLATFORM_TUPLE
from robogen.fmu.modeldesc import ModelDescription, load_model_description
from robogen.outputs import check_not_input, output_file

#: A run that would record more rows than this gets a warning before it starts.
MANY_ROWS = 10**8


def build_master(path: Path, *, stop=None, step=None, output=None, events=None, realtime=None,
                 progress=False, trace=None, keep_rows=True, isolate=False, cache: FmuCache | None = None,
                 notes: CallNotes | None = None, warn: Callable[[Diagnostic], None] | None = None,
                 bindings: dict[str, Callable] | None = None) -> tuple[Master, FmuCache]:
    """The master of one run of the system file at ``path`` and the cache it loaded the FMUs
    into (close it after the run). ``isolate``: every instance in a worker process (else those
    with ``isolate = true``); ``notes``: where the bindings note their calls; ``warn`` receives
    the warnings found before the run (default: printed on stderr); ``bindings``: instances the
    caller binds itself, by name, ``make(name, model_description, notes)`` giving an object with
    the binding's methods in place of the FMU's binary (the reference interpreter of a model)."""
    cache = cache if cache is not None else FmuCache()
    notes = notes if notes is not None else CallNotes()
    try:
        system = read_system(path, cache, warn or _print_warning)
        output, events = _outputs(system, output, events)
        options = _options(system, stop, step, realtime, progress, warn or _print_warning)
        loaded, choices, players, links = _checked(system, cache, warn or _print_warning, options, notes)
        models = {n: md for n, (_folder, md) in loaded.items()}
        instances = []
        for name in dependency_order(system, links):
            folder, md = loaded[name]
            spec = system.instances[name]
            if name in players:
                binding = players[name]
            elif bindings and name in bindings:
                binding = bindings[name](name, md, notes)
            else:
                binding = cache.bind_instance(folder, md, spec, name, trace, notes, isolate, choices[name], options.step)
            instances.append(FmuInstance(name, md, folder, binding, spec.span))
        by_name = {u.name: u for u in instances}
        for name, player in players.items():
            player.attach(by_name[system.instances[name].player_of].binding)
        record = [(by_name[n], v) for n, v in record_list(system, models)]
        recorder = Recorder([f"{u.name}.{n}" for u, v in record for n in u.md.element_names(v)], output, events, keep_rows,
                            [v.type for u, v in record for _n in u.md.element_names(v)],
                            every=system.record_every, start=options.start, rows_hint=_rows_expected(options))
        plan = make_plan(instances, links, record, start=options.start, step=options.step, stop=options.stop,
                         max_iterations=system.max_event_iterations, events_logged=recorder.recording_events,
                         resolution=_resolution(system, models, options.step))
        return Master(system, plan, links, options, recorder, notes), cache
    except BaseException:
        cache.close()
        raise


def _rows_expected(options: RunOptions) -> int:
    """The rows a run records at least: one per communication point and the start's event
    iteration's second (the table makes room for them at once)."""
    points = (options.stop - options.start) / options.step if options.step > 0 else 0.0
    return math.ceil(points) + 2 if math.isfinite(points) and points >= 0 else 0


def check_system(system: System, cache: FmuCache, warn: Callable[[Diagnostic], None]) -> dict[str, ModelDescription]:
    """The checks of a run that need the FMUs (loaded into ``cache``) of a system without scenario
    players: each instance's FMU and interface, the connections, Event Mode; the model description
    the master works with per instance (the interface's view). A located error for every problem."""
    loaded, _choices, _players, _links = _checked(system, cache, warn, None, CallNotes())
    return {n: md for n, (_folder, md) in loaded.items()}


def _checked(system: System, cache: FmuCache, warn: Callable[[Diagnostic], None], options: RunOptions | None,
             notes: CallNotes) -> tuple[dict, dict, dict, list[Link]]:
    """The FMUs loaded (each as the master sees it through its interface), the interfaces chosen,
    the scenario players and the connections, all checked."""
    loaded = _load_fmus(system, cache)
    choices = _interfaces(system, loaded, warn)
    players = _players(system, {n: md for n, (_folder, md) in loaded.items()}, options, notes)
    loaded.update({n: (binding.scenario.path.parent, binding.md) for n, binding in players.items()})
    models = {n: md for n, (_folder, md) in loaded.items()}
    links = resolve(system, models)
    links += _player_links(system, players, models, links)
    _check_event_mode(system, models)
    return loaded, choices, players, links


def read_system(path: Path, cache: FmuCache, warn: Callable[[Diagnostic], None]) -> System:
    """The system at ``path``: a system file (TOML), or an SSP (``.ssp`` archive, ``.ssd`` file)
    whose archive and FMUs ``cache`` unpacks."""
    if is_ssp(path):
        return load_ssp(path, cache.root / "ssp", lambda fmu, span: cache.load(fmu, span)[1], warn)
    return load_system(path)


def _outputs(system: System, output, events) -> tuple[Path | None, Path | None]:
    """The results and events files, checked: neither is the system file, an FMU of the system or
    the other one; each can be written (its folder is created)."""
    inputs = [system.path, *(spec.fmu for spec in system.instances.values())]
    out = output_file(output, inputs=inputs, option="-o") if output is not None else None
    if events is not None:
        if out is not None:
            check_not_input(Path(events), [out], "--events")
        events = output_file(events, inputs=inputs, option="--events")
    return out, events


def _print_warning(diagnostic: Diagnostic) -> None:
    print(render(diagnostic, SourceMap()), file=sys.stderr)


def _load_fmus(system: System, cache: FmuCache) -> dict[str, tuple[Path, ModelDescription]]:
    """Each instance's extracted FMU and model description; every problem, located, at once."""
    loaded = {}
    sink = DiagnosticSink()
    for name, spec in system.instances.items():
        if spec.player_of is not None:
            continue
        try:
            loaded[name] = cache.load(spec.fmu, spec.fmu_span)
        except RobogenError as exc:
            for d in exc.diagnostics:
                sink.add(d.with_note(f"while loading the FMU of instance '{name}'", spec.fmu_span) if d.span != spec.fmu_span else d)
    sink.raise_if_errors()
    return loaded


def _players(system: System, models: dict[str, ModelDescription], options: RunOptions,
             notes: CallNotes) -> dict[str, ScenarioBinding]:
    """The binding of each instance that plays a scenario (robogen.cosim.player), its scenario
    checked against the FMU it drives; every problem, located, at once."""
    players = {}
    sink = DiagnosticSink()
    for name, spec in system.instances.items():
        target = spec.player_of
        if target is None or target not in models:
            continue
        if not spec.fmu.is_file():
            sink.error(f"scenario file not found: {spec.fmu}", spec.fmu_span)
            continue
        try:
            scenario = load_scenario(spec.fmu)
            plan = timeline(scenario, models[target], options.start, options.stop)
            md = player_description(name, scenario, plan, models[target])
        except RobogenError as exc:
            sink.extend(d.with_note(f"in the scenario of instance '{target}'", spec.fmu_span) for d in exc.diagnostics)
            continue
        for key, (_value, span) in spec.start.items():
            if key not in scenario.parameters:
                sink.error(f"the scenario has no parameter '{key}'{did_you_mean(key, scenario.parameters)}", span,
                           Note("its parameters are declared in its [parameters]", scenario.span("parameters")))
        players[name] = ScenarioBinding(name, scenario, models[target], md, notes)
    sink.raise_if_errors()
    return players


def _player_links(system: System, players: dict[str, ScenarioBinding], models: dict[str, ModelDescription],
                  links: list[Link]) -> list[Link]:
    """The connections of each player to the instance it drives; an input the system connects
    too is an error (an input has one source)."""
    made = []
    connected = {(k.target, k.dst.name): k.span for k in links}
    for name, player in players.items():
        spec = system.instances[name]
        for link in player_links(name, player.md, spec.player_of, models[spec.player_of], spec.fmu_span):
            other = connected.get((link.target, link.dst.name))
            if other is not None:
                raise RobogenError.at(f"'{link.target}.{link.dst.name}' is driven by its scenario and by a connection",
                                      other, Note("the scenario", spec.fmu_span))
            made.append(link)
    return made


def _interfaces(system: System, loaded: dict[str, tuple[Path, ModelDescription]],
                warn: Callable[[Diagnostic], None]) -> dict[str, tuple[ModelDescription, interfaces.Choice]]:
    """Each instance's interface (``[instances.X] interface``, else co-simulation where offered):
    its description replaced in ``loaded`` by the one the master works with (the adapter's, where
    one is needed); per instance, the original description and the choice. A pre-release of FMI
    3.0 is warned about."""
    sink = DiagnosticSink()
    choices = {}
    for name, (folder, md) in list(loaded.items()):
        spec = system.instances[name]
        interface = spec.interface or interfaces.default_interface(md) or "co-simulation"
        where = system.span("instances", name, "interface") if spec.interface else spec.fmu_span
        try:
            loaded[name] = (folder, interfaces.view(md, interface, where))
        except RobogenError as exc:
            sink.extend(exc.diagnostics)
            continue
        if md.prerelease:
            warn(warning(f"the FMU of instance '{name}' declares fmiVersion=\"{md.fmi_version}\", a pre-release of "
                         "FMI 3.0: it is imported as FMI 3.0", spec.fmu_span))
        choices[name] = (md, interfaces.Choice(interface, spec.solver, interfaces.tolerance(system.tolerance, md),
                                               spec.solver_step))
    sink.raise_if_errors()
    return choices


def _check_event_mode(system: System, models: dict[str, ModelDescription]) -> None:
    """An FMU with clocks must offer Event Mode: the master ticks its clocks there."""
    sink = DiagnosticSink()
    for name, md in models.items():
        if any(v.is_clock for v in md.variables) and not md.co_simulation.has_event_mode:
            sink.error(f"the FMU of instance '{name}' has clocks but no hasEventMode=\"true\"", system.instances[name].fmu_span)
    sink.raise_if_errors()


class FmuCache:
    """Extracts each distinct .fmu once per run, loads each binary once, starts the worker
    processes of isolated instances, and removes it all in :meth:`close`; a Python FMU is
    extracted and loaded once per process (:mod:`robogen.cosim.shared`)."""

    def __init__(self) -> None:
        self.root = Path(tempfile.mkdtemp(prefix="robogen-sim-"))
        self.folders: dict[Path, Path] = {}
        self.models: dict[Path, ModelDescription] = {}
        self.libraries: dict[str, Library] = {}
        self.workers: list[ProxyBinding] = []

    def load(self, fmu: Path, span: Span) -> tuple[Path, ModelDescription]:
        key = fmu.resolve()
        if key not in self.folders:
            if not fmu.is_file():
                raise RobogenError.at(f"FMU file not found: {fmu}", span)
            shared = SHARED.load(fmu)  # a Python FMU: once per process
            if shared is not None:
                self.folders[key], self.models[key] = shared
            else:
                folder = extract_fmu(fmu, self.root / str(len(self.folders)), wanted=needed_to_run)
                self.folders[key] = folder
                self.models[key] = load_model_description(folder, f"{fmu}/modelDescription.xml")
        return self.folders[key], self.models[key]

    def binary(self, folder: Path, md: ModelDescription, span: Span) -> Path:
        """The FMU's shared object for this platform."""
        ident = md.co_simulation.model_identifier
        platform = FMI2_PLATFORM if md.is_fmi2 else PLATFORM_TUPLE
        path = folder / "binaries" / platform / f"{ident}.so"
        if not path.is_file():
            found = sorted(p.name for p in (folder / "binaries").iterdir()) if (folder / "binaries").is_dir() else []
            raise RobogenError.at(f"the FMU has no binary for this platform: binaries/{platform}/{ident}.so is missing",
                                  span, Note(f"platforms in the archive: {', '.join(found) or 'none'}"))
        return path

    def library(self, folder: Path, md: ModelDescription, span: Span) -> Library:
        key = str(self.binary(folder, md, span))
        if SHARED.holds(folder):
            try:
                return SHARED.library(key)
            except LoadError as exc:
                raise RobogenError.at(str(exc), span) from None
        if key not in self.libraries:
            try:
                self.libraries[key] = Library(key)
            except LoadError as exc:
                raise RobogenError.at(str(exc), span) from None
        return self.libraries[key]

    def bind_instance(self, folder: Path, md: ModelDescription, spec, name: str, trace, notes: CallNotes, isolate: bool,
                      choice: tuple[ModelDescription, interfaces.Choice], step: float) -> Binding | ProxyBinding:
        """The binding of the system's instance ``name``: behind an adapter where its interface
        needs one (in this process), else :meth:`bind`'s."""
        original, chosen = choice
        if not interfaces.adapted(original, chosen.interface):
            return self.bind(folder, md, spec.fmu_span, name, trace, notes, isolate or spec.isolate)
        if isolate or spec.isolate:
            raise RobogenError.at(f"instance '{name}' uses its FMU through an adapter ({'FMI 2.0 ' if original.is_fmi2 else ''}"
                                  f"{chosen.interface}), which runs in the master's process: isolate = true is "
                                  "not available for it", spec.span)
        return interfaces.bind(original, chosen, self.binary(folder, md, spec.fmu_span), step, name, spec.fmu_span,
                               trace=trace, notes=notes)

    def bind(self, folder: Path, md: ModelDescription, span: Span, name: str, trace, notes: CallNotes,
             isolate: bool) -> Binding | ProxyBinding:
        """A binding of a new instance of the FMU: in this process, or in a worker process."""
        if not isolate:
            return Binding(self.library(folder, md, span), name, trace=trace, notes=notes)
        try:
            worker = ProxyBinding(str(self.binary(folder, md, span)), name, trace=trace, notes=notes)
        except LoadError as exc:
            raise RobogenError.at(str(exc), span) from None
        self.workers.append(worker)
        return worker

    def close(self) -> None:
        for worker in self.workers:
            worker.close()
        self.workers.clear()
        shutil.rmtree(self.root, ignore_errors=True)


def _options(system: System, stop, step, realtime, progress, warn: Callable[[Diagnostic], None]) -> RunOptions:
    step_span = system.span("experiment", "step") if step is None and system.step is not None else None
    stop = system.stop if stop is None else float(stop)
    step = system.step if step is None else float(step)
    if stop is None:
        raise RobogenError.at(f"no stop time: give {_setting(system, 'stop')} or --stop", system.span("experiment"))
    if step is None:
        raise RobogenError.at(f"no communication step: give {_setting(system, 'step')} or --step", system.span("experiment"))
    if not (math.isfinite(step) and step > 0):
        raise RobogenError.at(f"the communication step must be positive, not {step}", step_span)
    if not math.isfinite(stop) or stop < system.start:
        raise RobogenError.at(f"the stop time {stop} is before the start time {system.start}", system.span("experiment", "stop"))
    if realtime is not None and not (math.isfinite(realtime) and realtime > 0):
        raise RobogenError.at(f"the real-time factor must be positive, not {realtime}", None)
    _check_step(system, stop, step, step_span, warn)
    return RunOptions(system.start, stop, step, realtime, progress)


def _setting(system: System, name: str) -> str:
    """Where the system's file gives the setting ``name`` (stop or step)."""
    if not is_ssp(system.path):
        return f"[experiment] {name} = ..."
    return ("<ssd:DefaultExperiment stopTime=...>" if name == "stop"
            else '<rg:Experiment step=...> in a robogen annotation of <ssd:DefaultExperiment> (docs/ssp.md)')


def _resolution(system: System, models: dict[str, ModelDescription], step: float) -> float | None:
    """The run's time resolution (robogen.fmu.fmi.time_resolution): the step, and the intervals and
    shifts of the periodic input clocks as the model descriptions and the system file give them."""
    times = [step]
    for name, md in models.items():
        overrides = system.instances[name].clocks
        for v in md.variables:
            if v.is_clock and v.causality == "input" and v.interval_variability in PERIODIC:
                timing = overrides.get(v.name, ({}, None))[0]
                times += [timing.get("interval", v.interval), timing.get("shift", v.shift)]
    return time_resolution(t for t in times if t is not None)


def _check_step(system: System, stop: float, step: float, where: Span | None, warn: Callable[[Diagnostic], None]) -> None:
    """A step must advance time everywhere in the run: doubles tell the latest time and the
    latest time plus the step apart (robogen.fmu.fmi.resolvable). Warn before a run of over
    MANY_ROWS rows."""
    latest = max(abs(system.start), abs(stop))
    if not resolvable(step, latest):  # includes latest + step == latest
        spacing = math.ulp(max(1.0, latest))
        raise RobogenError.at(f"the communication step {step!r} cannot advance time exactly: at t={latest:g}, doubles "
                              f"are {spacing:.3g} apart, and a step must be more than {4 * TIME_ULPS} of those "
                              f"({4 * TIME_ULPS * spacing:.3g})", where, Note("choose a larger step (or --step)"))
    rows = (stop - system.start) / step
    if rows > MANY_ROWS:
        warn(warning(f"this run records about {rows:.3g} rows (({stop:g} - {system.start:g}) / {step!r}); "
                     "at tens of bytes each that is far more than a results file should hold", where,
                     Note("a larger step, an earlier stop time or fewer [record] variables make it smaller")))


def dependency_order(system: System, links: list[Link]) -> list[str]:
    """[experiment] order if given (others follow in declaration order); else a topological order
    of the connection graph, ties and cycles broken by declaration order."""
    names = list(system.instances)
    if system.order:
        order = list(system.order) + [n for n in names if n not in system.order and system.instances[n].player_of is None]
        players = {spec.player_of: n for n, spec in system.instances.items() if spec.player_of is not None}
        return [m for n in order for m in ([players[n]] if n in players else []) + [n]]
    succ: dict[str, set[str]] = {n: set() for n in names}
    indeg = {n: 0 for n in names}
    for link in links:
        if link.target not in succ[link.source] and link.target != link.source:  # an instance feeding itself orders nothing
            succ[link.source].add(link.target)
            indeg[link.target] += 1
    order: list[str] = []
    remaining = list(names)
    while remaining:
        ready = [n for n in remaining if indeg[n] == 0] or remaining[:1]  # a cycle: take the first declared
        n = ready[0]
        remaining.remove(n)
        order.append(n)
        for m in succ[n]:
            indeg[m] -= 1
    return order
