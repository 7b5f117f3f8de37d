"""From an expanded campaign to the runs to execute: files resolved, names checked, specs hashed.

For every run this module decides which FMU each instance uses, which files replace files in
its resources, and which start values it gets; then it checks all of that against the FMUs'
model descriptions before anything runs (unknown or unsettable variables, values of the wrong
type, missing files, metrics over variables that do not exist), each problem located in the
campaign file.

A run is identified by the SHA-256 of its full specification: the base system's text, the
content of every FMU and replaced file, the start values, the settings (stop, step, timeout,
keep), the metrics and the source of user metric modules, and robogen's version. That key makes
campaigns resumable (a run already recorded under its key is not run again) and tells which
FMUs to ship (by content, once per worker).
"""

from __future__ import annotations

import hashlib
import importlib.util
import json
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

from robogen import __version__
from robogen.campaign.space import expand
from robogen.campaign.templates import render
from robogen.campaign.spec import Campaign, FileRule, Metric, Value, is_number
from robogen.cosim.system import INTERFACES, SOLVERS
from robogen.diagnostics import DiagnosticSink, Note, RobogenError, Span, did_you_mean
from robogen.fmu.modeldesc import ModelDescription, Variable, read_model_description

SETTABLE = ("parameter", "input")


@dataclass(frozen=True)
class Context:
    """What every run of a campaign shares; shipped to each worker once."""

    system_text: str
    system_name: str
    stop: float | None
    step: float | None
    timeout: float
    keep: str
    metrics: tuple[Metric, ...]
    modules: dict[str, str]  # user metric module -> its source, when it lives beside the campaign
    preload: tuple[str, ...]


@dataclass(frozen=True)
class RunSpec:
    """One run as a worker needs it: FMUs by content hash, files and start values per instance."""

    key: str
    fmus: dict[str, str]  # instance -> SHA-256 of its .fmu
    resources: dict[str, dict[str, bytes]] = field(default_factory=dict)  # instance -> member -> content
    start: dict[str, dict[str, Value]] = field(default_factory=dict)  # instance -> variable -> value
    #: instance -> [instances.X] key (interface, solver, solver_step) -> value
    settings: dict[str, dict[str, Value]] = field(default_factory=dict)


@dataclass
class Run:
    index: int
    values: dict[str, Value]
    spec: RunSpec

    @property
    def id(self) -> str:
        return self.spec.key[:12]


@dataclass
class CampaignPlan:
    campaign: Campaign
    runs: list[Run]
    context: Context
    fmu_files: dict[str, Path]  # SHA-256 -> a path of that FMU on this machine


def sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


class _Files:
    """Reads each FMU and file once: content hashes and model descriptions."""

    def __init__(self) -> None:
        self.hashes: dict[Path, str] = {}
        self.models: dict[Path, ModelDescription | str] = {}
        self.texts: dict[Path, str] = {}

    def text(self, path: Path) -> str:
        if path not in self.texts:
            self.texts[path] = path.read_text(encoding="utf-8")
        return self.texts[path]

    def digest(self, path: Path) -> str:
        key = path.resolve()
        if key not in self.hashes:
            self.hashes[key] = sha256(key.read_bytes())
        return self.hashes[key]

    def model(self, path: Path) -> ModelDescription | str:
        """The model description of an .fmu, or why it cannot be read."""
        key = path.resolve()
        if key not in self.models:
            try:
                with zipfile.ZipFile(key) as z:
                    data = z.read("modelDescription.xml")
                self.models[key] = read_model_description(data, f"{path}/modelDescription.xml")
            except (OSError, KeyError, zipfile.BadZipFile) as exc:
                self.models[key] = f"cannot read the model description of {path}: {exc}"
            except RobogenError as exc:
                self.models[key] = f"{path}: {exc}"
        return self.models[key]


def make_plan(campaign: Campaign) -> CampaignPlan:
    """Expand, resolve and check every run; raise every problem found, located."""
    sink = DiagnosticSink()
    files = _Files()
    context = _context(campaign, sink)
    runs, fmu_files = [], {}
    for index, values in enumerate(expand(campaign)):
        resolved = _resolve(campaign, values, files, sink)
        if resolved is None:
            continue
        paths, resources, start, settings = resolved
        hashes = {}
        for instance, path in paths.items():
            hashes[instance] = files.digest(path)
            fmu_files.setdefault(hashes[instance], path)
        key = _key(context, hashes, resources, start, settings)
        runs.append(Run(index, values, RunSpec(key, hashes, resources, start, settings)))
    _check_metrics(campaign, _models_by_instance(runs, fmu_files, files), sink)
    sink.raise_if_errors()
    return CampaignPlan(campaign, runs, context, fmu_files)


def _resolve(campaign: Campaign, values: dict[str, Value], files: _Files, sink: DiagnosticSink):
    """(instance -> FMU path, instance -> {member: bytes}, instance -> {variable: value}) of one
    run, or None when something is missing (reported once per location)."""
    system = campaign.system
    paths = {name: spec.fmu for name, spec in system.instances.items()}
    resources: dict[str, dict[str, bytes]] = {}
    start: dict[str, dict[str, Value]] = {}
    settings: dict[str, dict[str, Value]] = {}
    ok = True
    for name, value in values.items():
        target, span = campaign.targets[name], _param_span(campaign, name)
        if target.kind == "setting":
            settings.setdefault(target.instance, {})[target.name] = value
        elif target.kind == "fmu":
            paths[target.instance] = _existing(campaign.folder / str(value), span, sink, f"FMU for '{name}'")
        elif target.kind == "resource":
            data = _read(campaign.folder / str(value), span, sink, f"file for '{name}'")
            resources.setdefault(target.instance, {})[target.name] = data
        elif target.kind == "start":
            start.setdefault(target.instance, {})[target.name] = value
    for rule in campaign.files:
        content = _apply(campaign, rule, values, files, sink)
        if content is None:
            ok = False
        elif rule.target.kind == "fmu":
            paths[rule.target.instance] = _existing(campaign.folder / content, rule.span, sink, "FMU")
        else:
            resources.setdefault(rule.target.instance, {})[rule.target.name] = content
    if None in paths.values() or any(v is None for r in resources.values() for v in r.values()):
        return None
    for instance, path in paths.items():
        ok = _check_instance(campaign, instance, path, start.get(instance, {}), files, sink) and ok
        ok = _check_settings(campaign, instance, path, settings.get(instance, {}), files, sink) and ok
    return (paths, resources, start, settings) if ok else None


def _check_settings(campaign: Campaign, instance: str, path: Path, settings: dict[str, Value], files: _Files,
                    sink: DiagnosticSink) -> bool:
    """The interface (one the FMU offers), the solver (a known one), Euler's step (positive)."""
    md = files.model(path)
    ok = True
    for name, value in settings.items():
        span = _param_span(campaign, f"{instance}.{name}")
        offered = md.interfaces() if not isinstance(md, str) else INTERFACES
        allowed = {"interface": offered, "solver": SOLVERS}.get(name)
        if allowed is not None and value not in allowed:
            sink.error(f"'{instance}.{name}' must be one of {', '.join(repr(a) for a in allowed)}, not {value!r}"
                       + (" (the FMU offers those interfaces)" if name == "interface" else ""), span)
            ok = False
        elif name == "solver_step" and not (is_number(value) and value > 0):
            sink.error(f"'{instance}.solver_step' must be a positive number, not {value!r}", span)
            ok = False
    return ok


def _param_span(campaign: Campaign, name: str) -> Span:
    for table in ("grid", "random"):
        if name in (campaign.grid if table == "grid" else campaign.random):
            return campaign.span(table, name)
    for i, case in enumerate(campaign.cases):
        if name in case:
            return campaign.span("case", i, name)
    return campaign.span()


def _existing(path: Path, span: Span, sink: DiagnosticSink, what: str) -> Path | None:
    if path.is_file():
        return path
    sink.error(f"{what} not found: {path}", span)
    return None


def _read(path: Path, span: Span, sink: DiagnosticSink, what: str) -> bytes | None:
    try:
        return path.read_bytes()
    except OSError as exc:
        sink.error(f"cannot read the {what}: {path}: {exc.strerror}", span)
        return None


def _apply(campaign: Campaign, rule: FileRule, values: dict[str, Value], files: _Files, sink: DiagnosticSink):
    """A [files] rule for one run: the path it names (an FMU) or the content it gives."""
    text = rule.pattern if rule.pattern is not None else files.text(rule.template)
    try:
        rendered = render(text, values)
    except KeyError as exc:
        sink.error(f"${{{exc.args[0]}}} has no value in this run: it is not a parameter of the campaign, or a "
                   "[[case]] leaves it out", rule.span)
        return None
    except ValueError as exc:
        sink.error(f"bad placeholder: {exc}", rule.span)
        return None
    if rule.template is not None:
        return rendered.encode("utf-8")
    if rule.target.kind == "fmu":
        return rendered
    return _read(campaign.folder / rendered, rule.span, sink, "file")


def _check_instance(campaign: Campaign, instance: str, path: Path, start: dict[str, Value], files: _Files,
                    sink: DiagnosticSink) -> bool:
    span = campaign.system.instances[instance].fmu_span
    if campaign.system.instances[instance].player_of is not None:
        return _check_scenario(campaign, instance, path, start, sink)
    md = files.model(path)
    if isinstance(md, str):
        sink.error(md, span)
        return False
    variables = md.by_name()
    ok = True
    for name, value in start.items():
        problem = _start_problem(variables.get(name), name, value, variables)
        if problem:
            sink.error(problem, _param_span(campaign, f"{instance}.{name}"), Note(f"variables are declared in {md.path}"))
            ok = False
    return ok


def _check_scenario(campaign: Campaign, instance: str, path: Path, start: dict[str, Value], sink: DiagnosticSink) -> bool:
    """The parameters a campaign gives the instance that plays a scenario: the scenario's own."""
    from robogen.cosim.scenario import load_scenario

    try:
        declared = load_scenario(path).parameters
    except RobogenError as exc:
        sink.extend(exc.diagnostics)
        return False
    ok = True
    for name, value in start.items():
        if name not in declared:
            sink.error(f"unknown parameter: the scenario {path} has no parameter '{name}'{did_you_mean(name, declared)}",
                       _param_span(campaign, f"{instance}.{name}"))
            ok = False
    return ok


def _start_problem(var: Variable | None, name: str, value: Value, variables: dict) -> str | None:
    if var is None:
        return f"unknown parameter: the FMU has no variable '{name}'{did_you_mean(name, variables)}"
    if var.causality not in SETTABLE and var.initial not in ("exact", "approx"):
        return f"'{name}' cannot be given a value (causality {var.causality}, initial {var.initial or 'calculated'})"
    if var.is_clock or var.type in ("Binary", "Clock"):
        return f"'{name}' is a {var.type}; it cannot be given a start value"
    if var.type == "Boolean" and not isinstance(value, bool):
        return f"'{name}' is a Boolean: give true or false, not {value!r}"
    if var.type == "String" and not isinstance(value, str):
        return f"'{name}' is a String: give a string, not {value!r}"
    if var.type.startswith("Float") and not is_number(value):
        return f"'{name}' is a {var.type}: give a number, not {value!r}"
    if var.type.startswith(("Int", "UInt", "Enum")) and (isinstance(value, bool) or not isinstance(value, int)):
        return f"'{name}' is a{'n' if var.type[0] in 'EIU' else ''} {var.type}: give an integer, not {value!r}"
    return None


def _models_by_instance(runs: list[Run], fmu_files: dict[str, Path], files: _Files) -> dict[str, list[ModelDescription]]:
    seen: dict[str, dict[str, ModelDescription]] = {}
    for run in runs:
        for instance, digest in run.spec.fmus.items():
            md = files.model(fmu_files[digest])
            if not isinstance(md, str):
                seen.setdefault(instance, {})[digest] = md
    return {instance: list(mds.values()) for instance, mds in seen.items()}


def _check_metrics(campaign: Campaign, models: dict[str, list[ModelDescription]], sink: DiagnosticSink) -> None:
    """Every variable a built-in metric reads exists in every FMU its instance uses; clocks where
    a clock is needed."""
    for metric in campaign.metrics:
        if metric.kind == "function":
            continue
        names = [(metric.source, metric.kind)] + ([(metric.options["since"], "since")] if "since" in metric.options else [])
        for source, role in names:
            instance, variable = source.split(".", 1)
            if instance not in campaign.system.instances:
                sink.error(f"unknown instance '{instance}'{did_you_mean(instance, campaign.system.instances)}",
                           campaign.span("metrics", metric.name, role))
                continue
            for md in models.get(instance, []):
                var = md.by_name().get(variable)
                if var is None:
                    sink.error(f"FMU instance '{instance}' has no variable '{variable}'{did_you_mean(variable, md.by_name())}",
                               campaign.span("metrics", metric.name, role), Note(f"variables are declared in {md.path}"))
                    break
                if role in ("first_tick", "ticks", "since") and not var.is_clock:
                    sink.error(f"'{role}' counts ticks of a clock; '{source}' is a {var.type}",
                               campaign.span("metrics", metric.name, role))
                    break


def _context(campaign: Campaign, sink: DiagnosticSink) -> Context:
    modules = {}
    for metric in campaign.metrics:
        if metric.kind != "function":
            continue
        module, function = metric.source.split(":")
        beside = campaign.folder / (module.replace(".", "/") + ".py")
        if beside.is_file():
            modules[module] = beside.read_text(encoding="utf-8")
            problem = _function_problem_in_source(modules[module], str(beside), function)
        else:
            problem = _function_problem_installed(module, function)
        if problem:
            sink.error(problem, metric.span)
    return Context(campaign.system.text, str(campaign.system_path), campaign.stop, campaign.step, campaign.timeout,
                   campaign.keep, tuple(campaign.metrics), modules, campaign.preload)


def _function_problem_in_source(source: str, filename: str, function: str) -> str | None:
    namespace: dict = {"__name__": "robogen_campaign_check", "__file__": filename}
    try:
        exec(compile(source, filename, "exec"), namespace)
    except Exception as exc:  # the user's module: any failure is a problem of the input
        return f"cannot load the metric module {filename}: {type(exc).__name__}: {exc}"
    if not callable(namespace.get(function)):
        return f"{filename} defines no function '{function}'{did_you_mean(function, namespace)}"
    return None


def _function_problem_installed(module: str, function: str) -> str | None:
    try:
        found = importlib.util.find_spec(module)
    except (ImportError, ValueError):
        found = None
    if found is None:
        return f"metric module '{module}' is neither a file beside the campaign nor an installed module"
    try:
        imported = importlib.import_module(module)
    except Exception as exc:  # the user's module: any failure is a problem of the input
        return f"cannot import the metric module '{module}': {type(exc).__name__}: {exc}"
    if not callable(getattr(imported, function, None)):
        return f"module '{module}' defines no function '{function}'{did_you_mean(function, dir(imported))}"
    return None


def _key(context: Context, fmus: dict[str, str], resources: dict[str, dict[str, bytes]],
         start: dict[str, dict[str, Value]], instance_settings: dict[str, dict[str, Value]]) -> str:
    spec = {
        "robogen": __version__,
        "system": sha256(context.system_text.encode("utf-8")),
        "fmus": fmus,
        "resources": {i: {m: sha256(data) for m, data in files.items()} for i, files in resources.items()},
        "start": start,
        "settings": [context.stop, context.step, context.timeout, context.keep],
        **({"instances": instance_settings} if instance_settings else {}),  # (runs without them keep their keys)
        "metrics": [[m.name, m.kind, m.source, sorted(m.options.items())] for m in context.metrics],
        "modules": {name: sha256(source.encode("utf-8")) for name, source in context.modules.items()},
    }
    return sha256(json.dumps(spec, sort_keys=True, separators=(",", ":")).encode("utf-8"))
