"""One run, inside its own process: the derived system, the simulation, the metrics.

This is what the isolated child (:mod:`robogen.campaign.isolate`) executes. It writes, in a
fresh folder of its own, the FMUs whose resources the run replaces and the run's system file
(the base system with this run's FMUs and start values), calls
:func:`robogen.cosim.simulate_system` and computes the metrics. Whatever goes wrong in Python is
returned as the run's failure, with a message that does not depend on where the run executed
(the run's folder and the worker's FMU cache are named ``run:`` and ``fmus:``).
"""

from __future__ import annotations

import importlib
import sys
import tempfile
import tomllib
import types
import zipfile
from dataclasses import replace
from pathlib import Path

from robogen.campaign import tomlwrite
from robogen.campaign.metrics import MetricError, compute, enumeration_names
from robogen.campaign.plan import Context, RunSpec
from robogen.diagnostics import RobogenError, SourceMap, render_all


def derived_fmu(base: Path, replaced: dict[str, bytes], target: Path) -> Path:
    """``base`` with some of its files replaced (or added): a new .fmu at ``target``. The
    members are stored, not compressed again: the archive lives only as long as its run."""
    with zipfile.ZipFile(base) as source, zipfile.ZipFile(target, "w", zipfile.ZIP_STORED) as copy:
        for info in source.infolist():
            if info.filename not in replaced:
                kept = zipfile.ZipInfo(info.filename, info.date_time)
                kept.external_attr, kept.create_system = info.external_attr, info.create_system
                copy.writestr(kept, source.read(info))
        for name in sorted(replaced):
            copy.writestr(zipfile.ZipInfo(name), replaced[name])
    return target


def derived_system(context: Context, fmus: dict[str, Path], start: dict[str, dict],
                   settings: dict[str, dict] | None = None) -> str:
    """The base system file with these FMU paths, start values (merged over the base's) and
    instance settings (interface, solver, solver_step)."""
    data = tomllib.loads(context.system_text)
    for name, instance in data.get("instances", {}).items():
        instance["fmu"] = str(fmus[name])
        if start.get(name):
            instance["start"] = {**instance.get("start", {}), **start[name]}
        player = f"{name}_scenario"  # the instance that plays its scenario (robogen.cosim.player)
        if "scenario" in instance and player in fmus:
            instance["scenario"] = str(fmus[player])
            if start.get(player):
                instance["scenario_parameters"] = {**instance.get("scenario_parameters", {}), **start[player]}
        instance.update((settings or {}).get(name, {}))
    return tomlwrite.dumps(data)


def load_functions(context: Context) -> dict[str, object]:
    """"module:function" -> the callable, modules shipped as source loaded under their name."""
    functions = {}
    for metric in context.metrics:
        if metric.kind != "function":
            continue
        module_name, function = metric.source.split(":")
        if module_name in context.modules and module_name not in sys.modules:
            module = types.ModuleType(module_name)
            module.__file__ = f"{module_name}.py"
            sys.modules[module_name] = module
            exec(compile(context.modules[module_name], module.__file__, "exec"), module.__dict__)
        functions[metric.source] = getattr(importlib.import_module(module_name), function)
    return functions


def simulate(context: Context, spec: RunSpec, fmus: dict[str, Path], folder: Path) -> dict:
    """Run one simulation in ``folder``; returns the row fields (status, error, end_time,
    metrics) and, with keep = "results", the time series."""
    from robogen.cosim import simulate_system

    local = dict(fmus)
    for instance, replaced in spec.resources.items():
        local[instance] = derived_fmu(fmus[instance], replaced, folder / f"{instance}.fmu")
    system = folder / "system.toml"
    system.write_text(derived_system(context, local, spec.start, spec.settings), encoding="utf-8")
    result = simulate_system(system, stop=context.stop, step=context.step, keep_rows=True, progress=False)
    terminated = result.stats.terminated_by
    row = {"status": "terminated" if terminated else "ok", "error": terminated or "",
           "end_time": result.stats.end_time,
           "metrics": compute(context.metrics, result, _enumerations(context, local), load_functions(context))}
    if context.keep == "results":
        row["series"] = (list(result.columns), result.rows)
    return row


def rehearsal(context: Context, spec: RunSpec, fmus: dict[str, Path], folder: Path, cache: Path) -> dict:
    """The run's first communication step, without metrics (their modules loaded): what a zygote
    does in itself once per combination of FMUs, after a run of them succeeded in a child, to
    warm itself (:func:`robogen.campaign.isolate.serve`); a step, so that the master's stepping
    loop has been through its first use too."""
    from robogen.cosim.shared import SHARED

    experiment = tomllib.loads(context.system_text).get("experiment", {})
    step = context.step or experiment.get("step") or 0.0
    stop = experiment.get("start", 0.0) + step
    load_functions(context)  # user metric modules shipped as source: compiled once, here
    tempfile.tempdir = str(cache)  # the worker's folder, the zygote's as long as it lives (run() sets the run's)
    for path in fmus.values():
        SHARED.load(path)  # its Python FMUs, extracted and loaded for every later child (robogen.cosim.shared)
    return run(replace(context, stop=stop, metrics=(), keep="metrics"), spec, fmus, folder, cache)


def _enumerations(context: Context, fmus: dict[str, Path]) -> dict[str, dict[int, str]]:
    """Item names of the Enumerations that 'final' and 'at' metrics read."""
    read = {m.source.split(".", 1)[0] for m in context.metrics if m.kind in ("final", "at")}
    return enumeration_names({i: p for i, p in fmus.items() if i in read})


def run(context: Context, spec: RunSpec, fmus: dict[str, Path], folder: Path, cache: Path) -> dict:
    """:func:`simulate`, with every failure turned into a failed row. Runs in the run's own
    process (it makes ``folder`` the process's temporary folder)."""

    def stable(text: str) -> str:
        return text.replace(f"{folder}/", "run:").replace(f"{cache}/", "fmus:")

    tempfile.tempdir = str(folder)  # this process is the run's own: the master unpacks the FMUs here
    try:
        return simulate(context, spec, fmus, folder)
    except RobogenError as exc:
        return failed(stable(render_all(exc.diagnostics, SourceMap())))
    except MetricError as exc:
        return failed(f"metric: {stable(str(exc))}")
    except Exception as exc:  # a bug in robogen: this run fails, the campaign goes on
        return failed(f"internal error: {type(exc).__name__}: {stable(str(exc))}")


def failed(message: str) -> dict:
    return {"status": "failed", "error": message, "end_time": None, "metrics": {}}
