"""From a system file to a ready :class:`~robogen.cosim.master.Master`: load, check, order, wire.

:func:`build_master` reads the system file, extracts and checks each FMU once
(:class:`FmuCache`, which also removes the extracted files when the run is over), orders the
instances for the dependency order of their connections and binds each to its FMU's binary.
"""

from __future__ import annotations

import math
import shutil
import tempfile
from pathlib import Path

from robogen.cosim.fmi3 import Binding, Library, LoadError
from robogen.cosim.instances import FmuInstance
from robogen.cosim.master import Master, RunOptions
from robogen.cosim.recorder import Recorder
from robogen.cosim.system import Link, System, load_system, resolve, split_name
from robogen.diagnostics import DiagnosticSink, Note, RobogenError, Span
from robogen.fmu.extract import extract_fmu
from robogen.fmu.headers import PLATFORM_TUPLE
from robogen.fmu.modeldesc import ModelDescription, load_model_description


def build_master(path: Path, *, stop=None, step=None, output=None, events=None, realtime=None,
                 progress=False, trace=None, keep_rows=True) -> tuple[Master, FmuCache]:
    system = load_system(path)
    options = _options(system, stop, step, realtime, progress)
    cache = FmuCache()
    try:
        loaded = _load_fmus(system, cache)
        models = {n: md for n, (_folder, md) in loaded.items()}
        links = resolve(system, models)
        _check_event_mode(system, models)
        instances = []
        for name in dependency_order(system, links):
            folder, md = loaded[name]
            spec = system.instances[name]
            binding = Binding(cache.library(folder, md, spec.fmu_span), name, trace=trace)
            instances.append(FmuInstance(name, md, folder, binding, spec.span))
        record = _record_list(system, instances)
        recorder = Recorder([f"{u.name}.{v.name}" for u, v in record], Path(output) if output else None,
                            Path(events) if events else None, keep_rows)
        return Master(system, instances, links, record, options, recorder), cache
    except BaseException:
        cache.close()
        raise


def _load_fmus(system: System, cache: FmuCache) -> dict[str, tuple[Path, ModelDescription]]:
    """Each instance's extracted FMU and model description; every problem, located, at once."""
    loaded = {}
    sink = DiagnosticSink()
    for name, spec in system.instances.items():
        try:
            loaded[name] = cache.load(spec.fmu, spec.fmu_span)
        except RobogenError as exc:
            for d in exc.diagnostics:
                sink.add(d.with_note(f"while loading the FMU of instance '{name}'", spec.fmu_span) if d.span != spec.fmu_span else d)
    sink.raise_if_errors()
    return loaded


def _check_event_mode(system: System, models: dict[str, ModelDescription]) -> None:
    """An FMU with clocks must offer Event Mode: the master ticks its clocks there."""
    sink = DiagnosticSink()
    for name, md in models.items():
        if any(v.is_clock for v in md.variables) and not md.co_simulation.has_event_mode:
            sink.error(f"the FMU of instance '{name}' has clocks but no hasEventMode=\"true\"", system.instances[name].fmu_span)
    sink.raise_if_errors()


class FmuCache:
    """Extracts each distinct .fmu once per run and loads each binary once."""

    def __init__(self) -> None:
        self.root = Path(tempfile.mkdtemp(prefix="robogen-sim-"))
        self.folders: dict[Path, Path] = {}
        self.models: dict[Path, ModelDescription] = {}
        self.libraries: dict[str, Library] = {}

    def load(self, fmu: Path, span: Span) -> tuple[Path, ModelDescription]:
        key = fmu.resolve()
        if key not in self.folders:
            if not fmu.is_file():
                raise RobogenError.at(f"FMU file not found: {fmu}", span)
            folder = extract_fmu(fmu, self.root / str(len(self.folders)))
            self.folders[key] = folder
            self.models[key] = load_model_description(folder, f"{fmu}/modelDescription.xml")
        return self.folders[key], self.models[key]

    def library(self, folder: Path, md: ModelDescription, span: Span) -> Library:
        ident = md.co_simulation.model_identifier
        path = folder / "binaries" / PLATFORM_TUPLE / f"{ident}.so"
        if not path.is_file():
            found = sorted(p.name for p in (folder / "binaries").iterdir()) if (folder / "binaries").is_dir() else []
            raise RobogenError.at(f"the FMU has no binary for this platform: binaries/{PLATFORM_TUPLE}/{ident}.so is missing",
                                  span, Note(f"platforms in the archive: {', '.join(found) or 'none'}"))
        key = str(path)
        if key not in self.libraries:
            try:
                self.libraries[key] = Library(key)
            except LoadError as exc:
                raise RobogenError.at(str(exc), span) from None
        return self.libraries[key]

    def close(self) -> None:
        shutil.rmtree(self.root, ignore_errors=True)


def _options(system: System, stop, step, realtime, progress) -> RunOptions:
    stop = system.stop if stop is None else float(stop)
    step = system.step if step is None else float(step)
    if stop is None:
        raise RobogenError.at("no stop time: give [experiment] stop = ... or --stop", system.span("experiment"))
    if step is None:
        raise RobogenError.at("no communication step: give [experiment] step = ... or --step", system.span("experiment"))
    if not (math.isfinite(step) and step > 0):
        raise RobogenError.at(f"the communication step must be positive, not {step}", system.span("experiment", "step"))
    if not math.isfinite(stop) or stop < system.start:
        raise RobogenError.at(f"the stop time {stop} is before the start time {system.start}", system.span("experiment", "stop"))
    if realtime is not None and not (math.isfinite(realtime) and realtime > 0):
        raise RobogenError.at(f"the real-time factor must be positive, not {realtime}", None)
    return RunOptions(system.start, stop, step, realtime, progress)


def dependency_order(system: System, links: list[Link]) -> list[str]:
    """[experiment] order if given (others follow in declaration order); else a topological order
    of the connection graph, ties and cycles broken by declaration order."""
    names = list(system.instances)
    if system.order:
        return list(system.order) + [n for n in names if n not in system.order]
    succ: dict[str, set[str]] = {n: set() for n in names}
    indeg = {n: 0 for n in names}
    for l in links:
        if l.target not in succ[l.source]:
            succ[l.source].add(l.target)
            indeg[l.target] += 1
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


def _record_list(system: System, instances: list[FmuInstance]):
    """(instance, variable) pairs to record: the [record] list, else every output and input clock."""
    by_name = {u.name: u for u in instances}
    declared = [by_name[n] for n in system.instances]
    if system.record is None:
        return [(u, v) for u in declared for v in u.md.variables
                if v.causality == "output" or (v.is_clock and v.causality == "input")]
    out = []
    for name, _span in system.record:
        inst, var = split_name(name)
        u = by_name[inst]
        if var == "*":
            out += [(u, v) for v in u.md.variables if v.causality == "output" or (v.is_clock and v.causality == "input")]
        else:
            out.append((u, u.vars[var]))
    seen, unique = set(), []
    for u, v in out:
        if (u.name, v.name) not in seen:
            seen.add((u.name, v.name))
            unique.append((u, v))
    return unique
