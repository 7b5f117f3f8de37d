"""The properties every generated model must have, checked in order on one model:

1. ``print``: printing its AST and parsing the text gives the same AST;
2. ``check``: ``robogen check`` reports no error;
3. ``package``: for each semantics, ``package`` gives an FMU that passes robogen's validation,
   or stops with a located "... is not supported for code generation" error. A C compiler error
   is a failure (``compile``), as is any exception that is not a RobogenError (``internal``);
4. ``differential``: the FMU and the reference interpreter give the same trace on random input
   scenarios, in both semantics;
5. ``sanitize`` (on a sample, or on request): the FMU's C, compiled with AddressSanitizer and
   UndefinedBehaviorSanitizer, runs the same scenarios without a finding
   (:mod:`robogen.fuzz.sanitize`).

:func:`check_model` returns an :class:`Outcome`: which properties held, the first failure (its
property, its kind and a message), and a "not supported" construct when code generation
refused the model (a model it refuses is not compiled or run further).
"""

from __future__ import annotations

import random
import re
import resource
import shutil
import time
import traceback
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

from robogen import differential
from robogen.codegen import binary
from robogen.codegen.api import build_fmu, compile_checked
from robogen.codegen.generate import CodegenOptions
from robogen.diagnostics import RobogenError
from robogen.fmu.headers import PLATFORM_TUPLE
from robogen.fuzz.model import Generated
from robogen.ir.boundary import select_boundary
from robogen.ir.lower import LoweringOptions
from robogen.semantics import check_paths
from robogen.syntax import printer
from robogen.syntax.parser import parse_text

PROPERTIES = ("print", "check", "package", "differential", "sanitize")
SEMANTICS = ("exhaustive", "stepwise")
# failure kinds, as the summary line counts them
KINDS = ("compile", "difference", "internal", "print", "check", "sanitize")


@dataclass
class Budget:
    """How much of the differential test each model gets."""

    scenarios: int = 6
    instants: int = 16
    sanitize: bool = False  # run property 5 on this model
    validate: bool = True  # validate the FMU (the archive, the XSD, fmpy's and robogen's rules)
    semantics: tuple[str, ...] = ("exhaustive", "stepwise")  # (shrinking looks at the failing one only)
    through: str = "sanitize"  # the last property checked (shrinking stops at the one that failed)
    build: bool = True  # compile the generated C (shrinking a failure of code generation does not)
    # the semantics whose FMU is packaged with the product's flags (-O2) and validated; the
    # others' binary is built alone at -O0 (the runner alternates, to halve the compiler's time)
    optimise: tuple[str, ...] = ("exhaustive", "stepwise")


@dataclass
class Failure:
    prop: str  # the property that failed
    kind: str  # one of KINDS
    message: str

    def same(self, other: "Failure | None") -> bool:
        """Is ``other`` the same failure, for shrinking: same property, same kind, and the same
        first line once numbers and names are blurred."""
        return other is not None and (self.prop, self.kind) == (other.prop, other.kind) and \
            _signature(self.kind, self.message) == _signature(other.kind, other.message)


@dataclass
class Outcome:
    seed: str
    language: str = ""
    passed: list[str] = field(default_factory=list)
    failure: Failure | None = None
    unsupported: str | None = None  # the construct code generation refused
    warnings: int = 0
    seconds: dict[str, float] = field(default_factory=dict)
    steps: int = 0  # super-dense steps compared
    cpu: float = 0.0  # CPU seconds it took (with the C compiler's)
    outputs: int = 0  # output clock ticks compared


def _signature(kind: str, message: str) -> str:
    """What tells one failure from another: the compiler's first error, the exception of an
    internal error, else the first line; with names and numbers blurred."""
    lines = [line for line in message.strip().splitlines() if line.strip()] or [""]
    line = lines[0]
    if kind in ("compile", "sanitize"):
        line = next((x[x.index("error:"):] for x in lines if "error:" in x), line)
    elif kind == "internal":
        line = lines[-1]
    line = re.sub(r"\S*/", "", line)  # the folders of the model's files (a temporary folder each time)
    line = re.sub(r"\b[A-Za-z_]+\d+\b", "N", line)
    return re.sub(r"\d+", "0", line)[:160]


class _Stop(Exception):
    """The model is done: a failure, or a construct code generation does not support."""


def check_model(g: Generated, work: Path, budget: Budget) -> Outcome:
    """Check the properties of model ``g`` in the folder ``work`` (created, and left for the caller
    to remove)."""
    out = Outcome(g.seed, g.language)
    work.mkdir(parents=True, exist_ok=True)
    cpu = _cpu()
    try:
        _run(g, work, budget, out)
    except _Stop:
        pass
    except Exception:  # noqa: BLE001 - any other exception is robogen's own bug: that is what this reports
        out.failure = Failure(_next(out), "internal", traceback.format_exc())
    out.cpu = _cpu() - cpu
    return out


def _cpu() -> float:
    """CPU seconds of this process and of the processes it waited for (the C compiler)."""
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.process_time() + children.ru_utime + children.ru_stime


def _next(out: Outcome) -> str:
    """The property being checked: the one after the last that held."""
    return next((p for p in PROPERTIES if p not in out.passed), "sanitize")


def _timed(out: Outcome, phase: str, started: float) -> None:
    out.seconds[phase] = out.seconds.get(phase, 0.0) + time.perf_counter() - started


def _run(g: Generated, work: Path, budget: Budget, out: Outcome) -> None:
    started = time.perf_counter()
    text = g.text()
    _print_parse(g, text, out)
    path = work / Path(g.path).name
    path.write_text(text, encoding="utf-8")
    functions = None
    if g.c_functions is not None:
        functions = work / "functions.c"
        functions.write_text(g.c_functions, encoding="utf-8")
    _timed(out, "print", started)
    started = time.perf_counter()
    model = check_paths([path])
    out.warnings = sum(1 for d in model.diagnostics if not d.is_error)
    _timed(out, "check", started)
    if model.errors:
        raise _fail(out, "check", "check", "\n".join(d.render() for d in model.errors[:5]))
    out.passed.append("check")
    if budget.through == "check":
        return
    try:
        boundary = select_boundary(model)
    except RobogenError as exc:
        raise _fail(out, "package", "internal", f"{budget.semantics[0]}: no boundary: {exc}") from None
    inputs = [path] + ([functions] if functions is not None else [])
    builds = {s: _package(g, (model, boundary, inputs), work / s, s, budget, out) for s in budget.semantics}
    out.passed.append("package")
    if budget.through == "package":
        return
    scenarios = _scenarios(g, builds, budget)
    traces = _differential(g, builds, scenarios, out)
    out.passed.append("differential")
    if budget.sanitize and budget.through == "sanitize":
        _sanitize(builds, traces, scenarios, work, out)
        out.passed.append("sanitize")


def _sanitize(builds: dict[str, "_Build"], traces: dict[str, list[differential.Trace]],
              scenarios: list[differential.Scenario], work: Path, out: Outcome) -> None:
    from robogen.fuzz.sanitize import sanitize

    started = time.perf_counter()
    for semantics, b in builds.items():
        try:
            problem = sanitize(b.built.folder, traces[semantics], scenarios, work / f"asan-{semantics}")
        except RobogenError as exc:
            problem = f"the sanitized build failed: {exc}"
        if problem is not None:
            _timed(out, "sanitize", started)
            raise _fail(out, "sanitize", "sanitize", f"{semantics}: {problem}")
    _timed(out, "sanitize", started)


def _fail(out: Outcome, prop: str, kind: str, message: str) -> _Stop:
    out.failure = Failure(prop, kind, message)
    return _Stop()


def _print_parse(g: Generated, text: str, out: Outcome) -> None:
    try:
        again = parse_text(text, g.path)
    except RobogenError as exc:
        raise _fail(out, "print", "print", "the printed model does not parse: " + str(exc)) from None
    if again != g.file:
        raise _fail(out, "print", "print", "parsing the printed model gives another AST: " + _ast_difference(g.file, again))
    out.passed.append("print")


def _ast_difference(a, b) -> str:
    """The first top-level item whose printed form differs (for the report)."""
    for x, y in zip(a.items, b.items):
        if x != y:
            return f"{printer.file(type(a)(a.path, a.language, None, (), (x,)))[:400]}"
    return "the numbers of items differ"


@dataclass
class _Build:
    semantics: str
    built: differential.Built


def _package(g: Generated, checked: tuple, work: Path, semantics: str, budget: Budget, out: Outcome) -> _Build:
    """Generate the FMU of one semantics and build it: packaged and validated (the product's
    -O2), or, for a semantics not in ``budget.optimise``, its binary alone at -O0 (faster)."""
    model, boundary, inputs = checked
    started = time.perf_counter()
    options = LoweringOptions(semantics=semantics, capacity=g.capacity)
    functions = inputs[1] if len(inputs) > 1 else None
    try:
        compiled = compile_checked(model, boundary, work / "src", options=options,
                                   codegen=CodegenOptions(functions=functions), inputs=inputs)
    except RobogenError as exc:
        _timed(out, "generate", started)
        raise _refused(out, exc, semantics) from None
    except Exception:  # noqa: BLE001 - robogen's own bug
        raise _fail(out, "package", "internal", f"{semantics}: code generation crashed:\n{traceback.format_exc()}") from None
    _timed(out, "generate", started)
    if not budget.build:
        return _Build(semantics, differential.Built(compiled.fmu, work, work, {}))
    started = time.perf_counter()
    ident = compiled.generated.model_identifier
    optimised = semantics in budget.optimise
    try:
        if optimised:
            archive = build_fmu(compiled.folder, work / f"{ident}.fmu", model_identifier=ident, validate=budget.validate)
        else:
            binary.compile_fmu_binary(compiled.folder / "sources", ident,
                                      compiled.folder / "binaries" / PLATFORM_TUPLE / f"{ident}.so", extra_cflags=("-O0",))
    except RobogenError as exc:
        _timed(out, "compile", started)
        message = str(exc) + "\n" + "\n".join(d.message for d in exc.diagnostics[1:4])
        kind = "compile" if "compiling FMU" in exc.diagnostics[0].message else "internal"
        raise _fail(out, "package", kind, f"{semantics}{'' if optimised else ' (-O0)'}: {message}") from None
    _timed(out, "compile", started)
    if not optimised:
        return _Build(semantics, differential.Built(compiled.fmu, compiled.folder, compiled.folder, {}))
    folder = work / "unzipped"
    with zipfile.ZipFile(archive) as z:
        z.extractall(folder)
    return _Build(semantics, differential.Built(compiled.fmu, archive, folder, {}))


def _refused(out: Outcome, exc: RobogenError, semantics: str) -> _Stop:
    """Code generation refused the model: a located "not supported" error is an answer, any other
    error of a model that checks is a failure."""
    first = exc.diagnostics[0]
    if "is not supported for code generation" in first.message and first.span is not None:
        out.unsupported = construct(first.message)
        return _Stop()
    return _fail(out, "package", "internal", f"{semantics}: code generation failed: " + str(exc))


def construct(message: str) -> str:
    """The construct a "not supported" message names, with the model's names and numbers blurred,
    so that the table counts kinds of constructs."""
    what = message.replace(" is not supported for code generation", "")
    what = re.sub(r"'[^']*'", "'…'", what)
    return re.sub(r"\d+", "N", what)[:100]


def _scenarios(g: Generated, builds: dict[str, _Build], budget: Budget) -> list[differential.Scenario]:
    """The model's random input scenarios (one list for both semantics: their FMUs have the same
    variables)."""
    rng = random.Random(f"scenarios {g.seed}")
    desc = differential.Description(next(iter(builds.values())).built.folder)
    return [differential.random_scenario(rng, desc, budget.instants, every_instant=rng.random() < 0.3)
            for _ in range(budget.scenarios)]


def _differential(g: Generated, builds: dict[str, _Build], scenarios: list[differential.Scenario],
                  out: Outcome) -> dict[str, list[differential.Trace]]:
    """Property 4 for each semantics: the FMU's traces of the scenarios, once equal to the
    interpreter's."""
    started = time.perf_counter()
    functions = g.py_functions()
    traces: dict[str, list[differential.Trace]] = {}
    for semantics, b in builds.items():
        runner = differential.FmuRunner(b.built.folder)
        mine = traces[semantics] = []
        try:
            for n, scenario in enumerate(scenarios):
                try:
                    trace, difference = differential.compare(runner, b.built.fmu, scenario, functions=functions)
                except differential.TooManySteps as exc:
                    raise _fail(out, "differential", "difference", f"{semantics}, scenario {n}: {exc}") from None
                if difference is not None:
                    raise _fail(out, "differential", "difference", f"{semantics}, scenario {n}: {difference}")
                mine.append(trace)
                out.steps += len(trace.steps)
                out.outputs += sum(len(s.outputs) for s in trace.steps)
        finally:
            runner.close()
    _timed(out, "differential", started)
    return traces


def remove(work: Path) -> None:
    shutil.rmtree(work, ignore_errors=True)


__all__ = ["Budget", "Failure", "Outcome", "check_model", "construct", "PROPERTIES", "KINDS", "SEMANTICS", "remove"]
