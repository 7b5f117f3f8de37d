"""One model (or its FMU), one scenario: build (cached), co-simulate, and hand back what the run produced.

:func:`run_scenario` packages the model (:mod:`robogen.scenarios.build`), writes the system of
one instance, ``model``, driven by the scenario (``[instances.model] scenario = ...``, see
:mod:`robogen.cosim.player`), and runs it with :func:`robogen.cosim.simulate_system`. The
experiment: ``stop`` and ``step`` from the command line, else from the scenario file; the step
defaults to the interval of the FMU's periodic clock (``cycle`` or ``tock``), else the step of its
default experiment (a time-free RoboChart FMU's time unit), else 0.1 s.
"""

from __future__ import annotations

import argparse
import json
import tempfile
import zipfile
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Callable, Sequence

from robogen.cosim import SimulationResult, simulate_system
from robogen.cosim.scenario import Scenario, load_scenario
from robogen.diagnostics import Note, RobogenError, Span
from robogen.fmu.modeldesc import ModelDescription, read_model_description
from robogen.scenarios.build import Built, model_fmu, options_argv, parse_options

#: The name of the model's instance in the system a scenario runs in (its columns: model.<variable>).
INSTANCE = "model"
#: The step when neither the command line, the scenario nor a periodic clock of the FMU gives one.
DEFAULT_STEP = 0.1


@dataclass
class ScenarioRun:
    scenario: Scenario
    built: Built
    md: ModelDescription
    result: SimulationResult
    stop: float
    step: float


def fmu_description(fmu: Path) -> ModelDescription:
    with zipfile.ZipFile(fmu) as archive:
        return read_model_description(archive.read("modelDescription.xml"), f"{fmu}/modelDescription.xml")


def model_options(scenario: Scenario, given: argparse.Namespace | None) -> argparse.Namespace:
    """The options of ``robogen package`` for the scenario's model: its ``[options]``, then
    those given on the command line (``given`` holds only the options given there)."""
    options = scenario.data.get("options", {})
    args = parse_options(options_argv(options, lambda key: scenario.span("options", key)), scenario.span("options"))
    for key, value in vars(given or argparse.Namespace()).items():
        if key in vars(args):
            setattr(args, key, value)
    return args


def model_paths(scenario: Scenario, paths: Sequence[str] | None) -> list[str]:
    """The model: given on the command line, else the scenario's ``model`` (relative to it)."""
    if paths:
        return list(paths)
    model = scenario.data.get("model")
    if model is None:
        raise RobogenError.at("the scenario names no model: give model = \"PATH\" (relative to the file), or the model on "
                              "the command line", Span.point(str(scenario.path)))
    path = scenario.path.parent / model
    if not path.exists():
        raise RobogenError.at(f"model not found: {path}", scenario.span("model"))
    return [str(path)]


def experiment(scenario: Scenario, md: ModelDescription, stop: float | None, step: float | None) -> tuple[float, float]:
    stop = stop if stop is not None else scenario.number("stop")
    if stop is None:
        raise RobogenError.at("no stop time: give stop = SECONDS in the scenario, or --stop", Span.point(str(scenario.path)))
    if step is None:
        step = scenario.number("step")
    if step is None:
        periodic = [v.interval for v in md.variables if v.is_clock and v.causality == "input" and v.interval]
        default = md.default_experiment.step_size if md.default_experiment is not None else None
        # a RoboChart FMU without its tock clock (--time skip) gives its time unit as the default step
        step = min(periodic) if periodic else float(default) if default else DEFAULT_STEP
    return stop, step


def system_text(fmu: Path, scenario: Path, stop: float, step: float) -> str:
    """The system file of one instance of ``fmu`` driven by ``scenario`` (absolute paths)."""
    return "\n".join([
        "[experiment]", f"stop = {stop!r}", f"step = {step!r}", "",
        f"[instances.{INSTANCE}]", f"fmu = {json.dumps(str(fmu.resolve()))}",
        f"scenario = {json.dumps(str(scenario.resolve()))}", ""])


def run_scenario(scenario_path: str | Path, paths: Sequence[str] | None = None, given: argparse.Namespace | None = None, *,
                 stop: float | None = None, step: float | None = None, output: str | Path | None = None,
                 events: str | Path | None = None, progress: bool | None = False, keep_rows: bool = True,
                 warn: Callable | None = None, on_built: Callable[[Built], None] | None = None,
                 reference: bool = False) -> ScenarioRun:
    """Build the model of the scenario (cached) and run the scenario on it; ``reference``: on the
    reference interpreter of its IR instead of the FMU's binary (robogen.scenarios.reference)."""
    scenario = load_scenario(scenario_path)
    paths = model_paths(scenario, paths)
    args = model_options(scenario, given)
    if len(paths) == 1 and str(paths[0]).endswith(".fmu"):  # an FMU already built: driven as it is
        if reference:
            raise RobogenError.at("--reference needs the model, not its FMU", Span.of_path(str(paths[0])))
        built = Built(Path(paths[0]), False, 0.0, given=True)
    else:
        built = model_fmu(paths, args)
    if on_built is not None:
        on_built(built)
    md = fmu_description(built.fmu)
    stop, step = experiment(scenario, md, stop, step)
    with tempfile.TemporaryDirectory(prefix="robogen-scenario-") as tmp:
        system = Path(tmp) / "system.toml"
        system.write_text(system_text(built.fmu, scenario.path, stop, step), encoding="utf-8")
        try:
            result = simulate_system(system, output=output, events=events, progress=progress, keep_rows=keep_rows,
                                     warn=warn, bindings=_reference(paths, args) if reference else None)
        except RobogenError as exc:
            exc.diagnostics = tuple(_relocated(d, system, scenario) for d in exc.diagnostics)
            raise
    return ScenarioRun(scenario, built, md, result, stop, step)


def _relocated(d, system: Path, scenario: Scenario):
    """A diagnostic at the temporary system file, moved to the scenario (the file the user wrote);
    its notes there left out."""
    notes = tuple(n for n in d.notes if n.span is None or n.span.path != str(system))
    if d.span is not None and d.span.path == str(system):
        return replace(d, span=Span.point(str(scenario.path)),
                       notes=notes + (Note("while running the scenario on the model's FMU"),))
    return replace(d, notes=notes)


def _reference(paths: Sequence[str], args: argparse.Namespace) -> dict:
    """The model's instance bound to the reference interpreter of its IR (the same options)."""
    from robogen.codegen.api import lower_paths
    from robogen.codegen.cli import options_from
    from robogen.scenarios.reference import InterpreterBinding

    fmu, _model = lower_paths(list(paths), module=args.module, machine=args.machine, options=options_from(args))
    return {INSTANCE: lambda name, md, notes: InterpreterBinding(fmu, md, name, notes)}
