"""The campaign file: a base system, a parameter space, metrics and a figure (docs/campaign-toml.md).

:func:`load_campaign` checks the file against its schema and returns a :class:`Campaign` whose
every element carries its :class:`Span`; every problem is collected before failing, as the
system file does. The base system is loaded with :func:`robogen.cosim.system.load_system` (an SSP
with :func:`robogen.cosim.ssp_read.load_ssp`), so a bad system file is reported where it is wrong. Checks that need the FMUs (parameter names, files
that templates name) come later, in :mod:`robogen.campaign.plan`, once the space is expanded.
"""

from __future__ import annotations

import atexit
import math
import os
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from robogen.campaign import tomlwrite
from robogen.campaign.templates import template_of
from robogen.cosim.assemble import FmuCache
from robogen.cosim.ssp_read import is_ssp, load_ssp
from robogen.cosim.system import System, load_system, split_name
from robogen.cosim.system_data import toml_data
from robogen.cosim.tomlspan import SpanIndex
from robogen.diagnostics import DiagnosticSink, RobogenError, Span, did_you_mean

TOP_KEYS = ("title", "system", "stop", "step", "timeout", "keep", "preload",
            "grid", "case", "random", "files", "metrics", "figure")
KEEP = ("metrics", "results")
DISTRIBUTIONS = {"uniform": "[low, high]", "normal": "[mean, standard deviation]", "choice": "[value, ...]"}
RANDOM_SETTINGS = ("samples", "seed")
BUILTIN_METRICS = ("final", "min", "max", "at", "first_tick", "ticks")
METRIC_OPTIONS = {"final": ("equals",), "min": (), "max": (), "at": ("time", "equals"),
                  "first_tick": ("since",), "ticks": ()}
FIGURE_KEYS = ("metric", "x", "y", "facet", "series", "kind", "where")
FIGURE_KINDS = ("heatmap", "line", "scatter")
DEFAULT_TIMEOUT = 600.0
_IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_FUNCTION = re.compile(r"([A-Za-z_][A-Za-z0-9_.]*):([A-Za-z_][A-Za-z0-9_]*)")

Value = int | float | bool | str


@dataclass(frozen=True)
class Target:
    """What a parameter name sets: a start value, an instance's FMU, a file in its resources,
    or a campaign variable (a bare name, used by [files] templates)."""

    kind: str  # "start" | "fmu" | "resource" | "setting" (interface, solver, solver_step) | "variable"
    instance: str | None
    name: str  # the variable, "fmu", the member path "resources/...", or the variable's name


@dataclass(frozen=True)
class Distribution:
    kind: str  # one of DISTRIBUTIONS
    args: tuple


@dataclass(frozen=True)
class FileRule:
    """A [files] entry: the file an instance gets in each run, named by a path pattern or
    written from a template, ``${NAME}`` replaced by the run's parameter values."""

    target: Target
    pattern: str | None  # a path (relative to the campaign file) with ${NAME} placeholders
    template: Path | None  # a text file with ${NAME} placeholders
    span: Span


@dataclass(frozen=True)
class Metric:
    name: str
    kind: str  # one of BUILTIN_METRICS, or "function"
    source: str  # "instance.variable", or "module:function"
    options: dict = field(default_factory=dict, compare=False, hash=False)
    span: Span | None = field(default=None, compare=False, hash=False)


@dataclass(frozen=True)
class Figure:
    metrics: tuple[str, ...]
    x: str | None
    y: str | None
    facet: str | None
    series: str | None
    kind: str | None
    where: str | None
    span: Span


@dataclass
class Campaign:
    path: Path
    text: str
    spans: SpanIndex
    title: str
    system_path: Path
    system: System
    stop: float | None
    step: float | None
    timeout: float
    keep: str
    preload: tuple[str, ...]
    targets: dict[str, Target]  # every parameter name of the space, in declaration order
    grid: dict[str, list[Value]]
    cases: list[dict[str, Value]]
    samples: int
    seed: int
    random: dict[str, Distribution]
    files: list[FileRule]
    metrics: list[Metric]
    figure: Figure | None

    def span(self, *path) -> Span:
        return self.spans.span(*path)

    @property
    def folder(self) -> Path:
        return self.path.parent


def read_toml(path: Path, what: str) -> tuple[str, dict]:
    """The text and data of a TOML file; unreadable files and syntax errors are located."""
    display = str(path)
    try:
        text = path.read_text(encoding="utf-8")
        return text, tomllib.loads(text)
    except OSError as exc:
        raise RobogenError.at(f"cannot read {what}: {exc.strerror}", Span.whole_file(display)) from None
    except UnicodeDecodeError:
        raise RobogenError.at(f"{what} is not UTF-8 text", Span.whole_file(display)) from None
    except tomllib.TOMLDecodeError as exc:
        where = re.search(r"\(at line (\d+), column (\d+)\)", str(exc))
        span = Span.point(display, int(where.group(1)), int(where.group(2))) if where else Span.whole_file(display)
        raise RobogenError.at(f"invalid TOML: {str(exc).split(' (at line')[0]}", span) from None


def is_number(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


class _Checker:
    """Schema checks of one campaign file, every problem into one sink."""

    def __init__(self, path: Path, text: str, data: dict) -> None:
        self.path, self.data = path, data
        self.idx = SpanIndex(text, str(path))
        self.sink = DiagnosticSink()

    def error(self, message: str, *where) -> None:
        self.sink.error(message, self.idx.span(*where))

    def table(self, key: str) -> dict:
        value = self.data.get(key, {})
        if not isinstance(value, dict):
            self.error(f"'{key}' must be a table: [{key}]", key)
            return {}
        return value

    def unknown_keys(self, table: dict, allowed, *where) -> None:
        for key in table:
            if key not in allowed:
                self.error(f"unknown key '{key}'{did_you_mean(key, allowed)}", *where, key)

    def number(self, key: str, *, positive: bool = False) -> float | None:
        if key not in self.data:
            return None
        value = self.data[key]
        if not is_number(value) or (positive and value <= 0):
            self.error(f"'{key}' must be a {'positive ' if positive else ''}finite number", key)
            return None
        return float(value)

    def value(self, value: object, *where) -> bool:
        """A parameter value: a number, a boolean or a string."""
        if isinstance(value, bool) or isinstance(value, str) or is_number(value):
            return True
        self.error("a parameter value must be a number, a boolean or a string", *where)
        return False


def load_campaign(path: str | Path) -> Campaign:
    path = Path(path)
    text, data = read_toml(path, "campaign file")
    c = _Checker(path, text, data)
    c.unknown_keys(data, TOP_KEYS)
    system_path, system = _system(c)
    names: dict[str, Span] = {}
    grid = _grid(c, names)
    cases = _cases(c, names)
    samples, seed, random = _random(c, names)
    if not any(part in data for part in ("grid", "case", "random")):
        c.sink.error("the parameter space is empty: give [grid], [[case]] or [random] (docs/campaign-toml.md)",
                     Span.whole_file(str(path)))
    files = _files(c, system)
    targets = _targets(c, system, names, files)
    metrics = _metrics(c, system)
    figure = _figure(c, list(names), [m.name for m in metrics], any(m.kind == "function" for m in metrics))
    keep = data.get("keep", "metrics")
    if keep not in KEEP:
        c.error(f"'keep' must be one of {', '.join(repr(k) for k in KEEP)}", "keep")
    preload = data.get("preload", [])
    if not isinstance(preload, list) or not all(isinstance(m, str) and _FUNCTION.fullmatch(f"{m}:f") for m in preload):
        c.error("'preload' must be a list of Python module names", "preload")
        preload = []
    title = data.get("title", path.stem)
    if not isinstance(title, str):
        c.error("'title' must be a string", "title")
    c.sink.raise_if_errors()
    return Campaign(path, text, c.idx, str(title), system_path, system, c.number("stop"), c.number("step", positive=True),
                    c.number("timeout", positive=True) or DEFAULT_TIMEOUT, str(keep), tuple(preload), targets,
                    grid, cases, samples, seed, random, files, metrics, figure)


def _system(c: _Checker) -> tuple[Path, System]:
    raw = c.data.get("system")
    if not isinstance(raw, str) or not raw:
        c.error('the campaign needs its base experiment: system = "path/to/system.toml"', "system")
        c.sink.raise_if_errors()
    system_path = Path(os.path.normpath(c.path.parent / raw))
    if not system_path.is_file():
        c.error(f"system file not found: {system_path}", "system")
        c.sink.raise_if_errors()
    try:
        return system_path, _base_system(system_path)
    except RobogenError as exc:  # the system file's problems, with what this file had so far
        raise RobogenError([*c.sink.sorted(), *exc.diagnostics]) from None


def _base_system(path: Path) -> System:
    """The base system: a system file, or an SSP (docs/ssp.md), unpacked for as long as this
    process runs; an SSP's system file text is derived from it, as each run's is from a system file."""
    if not is_ssp(path):
        return load_system(path)
    cache = FmuCache()
    owner = os.getpid()
    atexit.register(lambda: os.getpid() == owner and cache.close())  # not in a forked worker
    system = load_ssp(path, cache.root / "ssp", lambda fmu, span: cache.load(fmu, span)[1])
    package = cache.root / "ssp"

    def named(spec) -> str:  # as the archive names it: the text does not depend on where it was unpacked
        return f"{path}/{spec.fmu.relative_to(package).as_posix()}" if spec.fmu.is_relative_to(package) else str(spec.fmu)

    system.text = tomlwrite.dumps(toml_data(system, named))
    return system


def _declare(c: _Checker, names: dict[str, Span], name: str, *where) -> bool:
    if name in names:
        c.error(f"parameter '{name}' is given twice (first at line {names[name].line}); "
                "each parameter belongs to one of [grid], [[case]] and [random]", *where)
        return False
    names[name] = c.idx.span(*where)
    return True


def _grid(c: _Checker, names: dict[str, Span]) -> dict[str, list[Value]]:
    grid = {}
    for name, raw in c.table("grid").items():
        values = _grid_values(c, raw, "grid", name)
        if values is not None and _declare(c, names, name, "grid", name):
            grid[name] = values
    return grid


def _grid_values(c: _Checker, raw: object, *where) -> list[Value] | None:
    """A list of values, { range = [first, last(, step)] } (integers, inclusive) or
    { linspace = [first, last, count] }."""
    if isinstance(raw, list):
        if not raw:
            c.error(f"'{where[-1]}' has no values: the campaign would have no runs", *where)
            return None
        ok = all(c.value(v, *where, i) for i, v in enumerate(raw))
        return list(raw) if ok else None
    if isinstance(raw, dict) and len(raw) == 1 and "range" in raw:
        args = raw["range"]
        if not (isinstance(args, list) and len(args) in (2, 3) and all(isinstance(a, int) and not isinstance(a, bool) for a in args)):
            c.error("range = [first, last] or [first, last, step]: integers, 'last' included", *where)
            return None
        step = args[2] if len(args) == 3 else 1
        values = list(range(args[0], args[1] + (1 if step > 0 else -1), step)) if step else []
        if not values:
            c.error(f"range {args} has no values: the campaign would have no runs", *where)
            return None
        return values
    if isinstance(raw, dict) and len(raw) == 1 and "linspace" in raw:
        args = raw["linspace"]
        if not (isinstance(args, list) and len(args) == 3 and all(is_number(a) for a in args[:2])
                and isinstance(args[2], int) and not isinstance(args[2], bool) and args[2] >= 1):
            c.error("linspace = [first, last, count]: two numbers and a positive integer", *where)
            return None
        first, last, n = float(args[0]), float(args[1]), args[2]
        return [first] if n == 1 else [first + (last - first) * k / (n - 1) for k in range(n)]
    c.error("a grid parameter is a list of values, { range = [first, last] } or { linspace = [first, last, count] }", *where)
    return None


def _cases(c: _Checker, names: dict[str, Span]) -> list[dict[str, Value]]:
    raw = c.data.get("case", [])
    if not isinstance(raw, list) or not all(isinstance(case, dict) for case in raw):
        c.error("cases are tables written [[case]]", "case")
        return []
    cases: list[dict[str, Value]] = []
    seen: dict[str, Span] = {}
    for i, case in enumerate(raw):
        if not case:
            c.error("this case sets nothing", "case", i)
        for name, value in case.items():
            if c.value(value, "case", i, name) and name not in seen:
                seen[name] = c.idx.span("case", i, name)
        cases.append(dict(case))
    for name, span in seen.items():
        if name in names:
            c.sink.error(f"parameter '{name}' is given twice (first at line {names[name].line}); "
                         "each parameter belongs to one of [grid], [[case]] and [random]", span)
        names[name] = span
    return cases


def _random(c: _Checker, names: dict[str, Span]) -> tuple[int, int, dict[str, Distribution]]:
    table = c.table("random")
    if not table:
        return 0, 0, {}
    samples, seed = table.get("samples"), table.get("seed", 0)
    if not isinstance(samples, int) or isinstance(samples, bool) or samples < 1:
        c.error("[random] needs samples = N, a positive integer (the number of draws)", "random", "samples")
        samples = 0
    if not isinstance(seed, int) or isinstance(seed, bool) or seed < 0:
        c.error("'seed' must be a non-negative integer", "random", "seed")
        seed = 0
    dists = {}
    for name, raw in table.items():
        if name in RANDOM_SETTINGS:
            continue
        dist = _distribution(c, raw, "random", name)
        if dist is not None and _declare(c, names, name, "random", name):
            dists[name] = dist
    if not any(name not in RANDOM_SETTINGS for name in table):
        c.error("[random] draws nothing: add NAME = { uniform = [low, high] } (or normal, choice)", "random")
    return samples, seed, dists


def _distribution(c: _Checker, raw: object, *where) -> Distribution | None:
    if not isinstance(raw, dict) or len(raw) != 1:
        c.error("a random parameter is one of { uniform = [low, high] }, { normal = [mean, sd] }, "
                "{ choice = [value, ...] }", *where)
        return None
    (kind, args), = raw.items()
    if kind not in DISTRIBUTIONS:
        c.error(f"unknown distribution '{kind}'{did_you_mean(kind, DISTRIBUTIONS)}; "
                f"one of {', '.join(DISTRIBUTIONS)}", *where, kind)
        return None
    if kind == "choice":
        if not isinstance(args, list) or not args:
            c.error("choice = [value, ...] needs at least one value", *where, kind)
            return None
        return Distribution(kind, tuple(args)) if all(c.value(v, *where, kind, i) for i, v in enumerate(args)) else None
    if not (isinstance(args, list) and len(args) == 2 and all(is_number(a) for a in args)):
        c.error(f"{kind} = {DISTRIBUTIONS[kind]}: two finite numbers", *where, kind)
        return None
    a, b = float(args[0]), float(args[1])
    if kind == "uniform" and not a < b:
        c.error(f"uniform = [low, high] needs low < high, not [{a:g}, {b:g}]", *where, kind)
        return None
    if kind == "normal" and not b > 0:
        c.error(f"normal = [mean, sd] needs a positive standard deviation, not {b:g}", *where, kind)
        return None
    return Distribution(kind, (a, b))


#: The keys of an [instances.X] table a campaign may vary (how the instance uses its FMU).
INSTANCE_SETTINGS = ("interface", "solver", "solver_step")


def target_of(name: str, system: System) -> tuple[Target | None, str]:
    """The :class:`Target` a parameter name denotes, or None and why not."""
    if _IDENT.fullmatch(name):
        return Target("variable", None, name), ""
    parts = split_name(name)
    if parts is None:
        return None, f"'{name}' is not a parameter name: write instance.variable, instance.fmu, instance.resources/PATH or a bare NAME"
    instance, rest = parts
    if instance not in system.instances:
        return None, f"unknown instance '{instance}'{did_you_mean(instance, system.instances)} in '{name}'"
    if rest == "fmu":
        return Target("fmu", instance, "fmu"), ""
    if rest in INSTANCE_SETTINGS:
        return Target("setting", instance, rest), ""
    if rest.startswith("resources/"):
        member = rest.split("/")
        if any(p in ("", ".", "..") for p in member[1:]) or len(member) < 2 or "\\" in rest:
            return None, f"'{rest}' is not a file inside the FMU's resources folder"
        return Target("resource", instance, rest), ""
    return Target("start", instance, rest), ""


def _files(c: _Checker, system: System) -> list[FileRule]:
    rules = []
    for name, raw in c.table("files").items():
        target, why = target_of(name, system)
        if target is None or target.kind not in ("fmu", "resource"):
            c.error(why or f"[files] sets files: '{name}' must be instance.fmu or instance.resources/PATH", "files", name)
            continue
        if isinstance(raw, str):
            rules.append(FileRule(target, raw, None, c.idx.span("files", name)))
        elif isinstance(raw, dict) and set(raw) == {"template"} and isinstance(raw["template"], str) and target.kind == "resource":
            template = c.path.parent / raw["template"]
            if not template.is_file():
                c.error(f"template file not found: {template}", "files", name, "template")
                continue
            rules.append(FileRule(target, None, template, c.idx.span("files", name)))
        else:
            c.error('a [files] entry is "path/with/${NAME}" or, for a resource, { template = "file" }', "files", name)
    return rules


def _targets(c: _Checker, system: System, names: dict[str, Span], files: list[FileRule]) -> dict[str, Target]:
    """Classify every parameter; a bare name must be used by a [files] rule."""
    targets = {}
    set_by_files = {f"{r.target.instance}.{r.target.name}" for r in files}
    for name, span in names.items():
        target, why = target_of(name, system)
        if target is None:
            c.sink.error(f"unknown parameter: {why}", span)
            continue
        if target.kind == "variable" and not _used_by_files(c, name, files):
            c.sink.error(f"unknown parameter '{name}': not instance.variable, instance.fmu or instance.resources/PATH, "
                         "and no [files] entry uses ${" + name + "}", span)
            continue
        if target.kind != "variable" and name in set_by_files:
            c.sink.error(f"'{name}' is both a parameter and set by [files]", span)
        targets[name] = target
    return targets


def placeholders(rule: FileRule) -> set[str]:
    """The ${NAME} names a [files] rule uses."""
    text = rule.pattern if rule.pattern is not None else rule.template.read_text(encoding="utf-8")
    return set(template_of(text).get_identifiers())


def _used_by_files(c: _Checker, name: str, files: list[FileRule]) -> bool:
    return any(name in placeholders(rule) for rule in files)


def _metrics(c: _Checker, system: System) -> list[Metric]:
    metrics = []
    for name, raw in c.table("metrics").items():
        where = ("metrics", name)
        if not _IDENT.fullmatch(name):
            c.error(f"metric name '{name}' must be an identifier (letters, digits, '_')", *where)
            continue
        if isinstance(raw, str):
            if not _FUNCTION.fullmatch(raw):
                c.error(f"a user metric is \"module:function\", not '{raw}'", *where)
                continue
            metrics.append(Metric(name, "function", raw, {}, c.idx.span(*where)))
            continue
        kinds = [k for k in raw if k in BUILTIN_METRICS] if isinstance(raw, dict) else []
        if len(kinds) != 1:
            c.error(f"a metric is {{ KIND = \"instance.variable\" }} with KIND one of {', '.join(BUILTIN_METRICS)}, "
                    "or \"module:function\"", *where)
            continue
        kind = kinds[0]
        c.unknown_keys(raw, (kind, *METRIC_OPTIONS[kind]), *where)
        source = raw[kind]
        parts = split_name(source) if isinstance(source, str) else None
        if parts is None or parts[0] not in system.instances:
            c.error(f"'{kind}' names a recorded variable of an instance: \"instance.variable\"", *where, kind)
            continue
        if kind == "at" and not is_number(raw.get("time")):
            c.error("'at' needs time = SECONDS", *where)
            continue
        since = raw.get("since")
        if since is not None and (not isinstance(since, str) or split_name(since) is None):
            c.error("'since' names a clock: \"instance.clock\"", *where, "since")
            continue
        if "equals" in raw and not c.value(raw["equals"], *where, "equals"):
            continue
        options = {k: raw[k] for k in METRIC_OPTIONS[kind] if k in raw}
        metrics.append(Metric(name, kind, source, options, c.idx.span(*where)))
    return metrics


def _figure(c: _Checker, params: list[str], metrics: list[str], open_metrics: bool) -> Figure | None:
    table = c.table("figure")
    if not table:
        return None
    c.unknown_keys(table, FIGURE_KEYS, "figure")
    raw = table.get("metric")
    chosen = [raw] if isinstance(raw, str) else raw
    if not isinstance(chosen, list) or not chosen or not all(isinstance(m, str) for m in chosen):
        c.error('[figure] needs metric = "NAME" (or a list of names: one panel each)', "figure", "metric")
        return None
    for m in chosen:
        if m not in metrics and not open_metrics:
            c.error(f"unknown metric '{m}'{did_you_mean(m, metrics)}", "figure", "metric")
    axes = {}
    for key in ("x", "y", "facet", "series"):
        value = table.get(key)
        if value is not None and value not in params:
            c.error(f"'{key}' must be a parameter of the campaign{did_you_mean(str(value), params)}", "figure", key)
        axes[key] = value
    kind = table.get("kind")
    if kind is not None and kind not in FIGURE_KINDS:
        c.error(f"'kind' is one of {', '.join(FIGURE_KINDS)}{did_you_mean(str(kind), FIGURE_KINDS)}", "figure", "kind")
    where = table.get("where")
    if where is not None and where not in metrics and not open_metrics:
        c.error(f"'where' names a boolean metric{did_you_mean(str(where), metrics)}", "figure", "where")
    if axes["x"] is None:
        c.error("[figure] needs x = \"PARAMETER\"", "figure")
    return Figure(tuple(chosen), axes["x"], axes["y"], axes["facet"], axes["series"], kind, where, c.idx.span("figure"))
