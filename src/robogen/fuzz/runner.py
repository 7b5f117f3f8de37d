"""Run the model fuzzer: N models from a seed, in parallel worker processes, with the table of
results and the summary line scripts read.

Each worker process generates a model, checks its properties (:mod:`robogen.fuzz.properties`)
in a folder of its own and, when one fails, shrinks it (:mod:`robogen.fuzz.shrink`) and writes
the shrunk model as a regression file (:mod:`robogen.fuzz.regressions`). The parent hands out
the models and collects the outcomes; a worker that dies (an FMU that crashes its host) or
takes too long is replaced, and its model counts as a failure: the generated C must never crash
or hang its host.
"""

from __future__ import annotations

import multiprocessing
import os
import queue
import signal
import tempfile
import time
import traceback
from collections import Counter
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Callable, TextIO

from robogen.fuzz.features import FEATURES
from robogen.fuzz.model import generate, model_seed
from robogen.fuzz.properties import KINDS, PROPERTIES, SEMANTICS, Budget, Failure, Outcome, check_model, remove


@dataclass
class Settings:
    seed: int | str = 1
    count: int = 100
    on: frozenset[str] = frozenset()
    jobs: int = 2
    sanitize_every: int = 20  # property 5 on one model in this many (0: never); all with sanitize_all
    sanitize_all: bool = False
    shrink_seconds: float = 300.0  # 0: do not shrink
    regressions: Path | None = None  # where shrunk failures are written
    timeout: float = 600.0  # seconds one model may take (shrinking not counted)
    budget: Budget = field(default_factory=Budget)
    work: Path | None = None  # where models are built (default: a temporary folder)
    optimise_all: bool = False  # both semantics at -O2 (else one of them, in turn)
    optimise_every: int = 1  # the product's -O2 build (one semantics, in turn) on one model in this many


def budget_for(settings: Settings, index: int) -> Budget:
    """Model ``index``'s budget: the sanitizers on a sample; the product's -O2 (and validation)
    for one semantics, the other built at -O0, in turn (unless ``settings.optimise_all``), on one
    model in ``settings.optimise_every`` (the others: both semantics at -O0, same warnings)."""
    b = settings.budget
    sample = settings.sanitize_all or (settings.sanitize_every > 0 and index % settings.sanitize_every == 0)
    every = max(1, settings.optimise_every)
    if settings.optimise_all:
        optimise = b.optimise
    elif index % every == 0:
        optimise = (SEMANTICS[(index // every) % 2],)
    else:
        optimise = ()
    return replace(b, sanitize=sample, optimise=optimise)


# ---------------------------------------------------------------------------- the worker


def _worker(settings: Settings, tasks, results) -> None:
    for s in (signal.SIGINT, signal.SIGTERM):  # the parent stops the run (and kills its workers)
        signal.signal(s, signal.SIG_IGN)
    while True:
        index = tasks.get()
        if index is None:
            return
        seed = model_seed(settings.seed, index)
        results.put(("start", index, os.getpid()))
        try:
            outcome = check_one(seed, settings, budget_for(settings, index))
        except Exception:  # noqa: BLE001 - the fuzzer's own bug: reported, and the run goes on
            outcome = Outcome(seed, failure=Failure("generate", "internal", traceback.format_exc()))
        results.put(("done", index, outcome))


def check_one(seed: str, settings: Settings, budget: Budget) -> Outcome:
    """Generate and check one model; shrink it and write its regression file if it fails."""
    from robogen.fuzz import regressions

    g = generate(seed, settings.on)
    base = settings.work or Path(tempfile.gettempdir())
    base.mkdir(parents=True, exist_ok=True)
    work = Path(tempfile.mkdtemp(prefix=f"fuzz-{seed}-", dir=base))
    try:
        out = check_model(g, work / "model", budget)
        if out.failure is not None and settings.shrink_seconds > 0:
            started = time.perf_counter()
            small = regressions.shrink_failure(g, out.failure, budget, work / "shrink", settings.shrink_seconds)
            out.seconds["shrink"] = time.perf_counter() - started
            if settings.regressions is not None:
                path = regressions.write(settings.regressions, small, out.failure, settings.on)
                out.failure.message += f"\nshrunk model: {path}"
        return out
    finally:
        remove(work)


# ---------------------------------------------------------------------------- the parent


@dataclass
class Report:
    settings: Settings
    outcomes: list[Outcome] = field(default_factory=list)
    seconds: float = 0.0
    interrupted: bool = False  # stopped (SIGINT, SIGTERM) before every model was checked: outcomes are those done

    def count(self, kind: str) -> int:
        return sum(1 for o in self.outcomes if o.failure is not None and o.failure.kind == kind)

    @property
    def unsupported(self) -> Counter:
        return Counter(o.unsupported for o in self.outcomes if o.unsupported)

    def summary(self) -> str:
        """The line scripts read."""
        return (f"fuzz: {len(self.outcomes)} models, C compile failures {self.count('compile')}, "
                f"differences {self.count('difference')}, internal errors {self.count('internal')}, "
                f"print/parse differences {self.count('print')}, not supported {sum(self.unsupported.values())}")

    @property
    def failed(self) -> bool:
        return any(o.failure is not None for o in self.outcomes)


def run(settings: Settings, out: TextIO, progress: Callable[[str], None] | None = None) -> Report:
    """Check ``settings.count`` models from ``settings.seed``; print the table to ``out``."""
    report = Report(settings)
    started = time.perf_counter()
    ctx = multiprocessing.get_context("fork")
    tasks, results = ctx.Queue(), ctx.Queue()
    for i in range(settings.count):
        tasks.put(i)
    workers: dict[int, multiprocessing.Process] = {}
    running: dict[int, tuple[int, float]] = {}  # pid -> (model index, start time)

    def spawn() -> None:
        p = ctx.Process(target=_worker, args=(settings, tasks, results), daemon=True)
        p.start()
        workers[p.pid] = p  # type: ignore[index]

    for _ in range(max(1, min(settings.jobs, settings.count))):
        spawn()
    done: dict[int, Outcome] = {}
    stop = _stop_on_signals()
    while len(done) < settings.count and not stop:
        try:
            message = results.get(timeout=1.0)
        except queue.Empty:
            _reap(settings, workers, running, done, spawn)
            continue
        if message[0] == "start":
            running[message[2]] = (message[1], time.monotonic())
        else:
            index, outcome = message[1], message[2]
            done[index] = outcome
            running = {pid: v for pid, v in running.items() if v[0] != index}
            if progress is not None:
                progress(_progress_line(index, outcome, len(done), settings.count))
    for _ in workers:
        tasks.put(None)
    for p in workers.values():
        if stop:
            p.kill()  # (the models they were checking are not counted)
        p.join(timeout=5)
    report.interrupted = bool(stop)
    report.outcomes = [done[i] for i in sorted(done)]
    report.seconds = time.perf_counter() - started
    print_table(report, out)
    return report


def _stop_on_signals() -> list[int]:
    """A list that SIGINT or SIGTERM makes non-empty: the run then stops and prints the table of
    the models checked so far (a run cut short by a deadline still reports what it did)."""
    stop: list[int] = []

    def note(signum, frame) -> None:
        stop.append(signum)

    for s in (signal.SIGINT, signal.SIGTERM):
        signal.signal(s, note)
    return stop


def _reap(settings: Settings, workers, running, done, spawn) -> None:
    """Replace a worker that died or overran its model: the model is a failure."""
    now = time.monotonic()
    for pid, p in list(workers.items()):
        index, since = running.get(pid, (None, now))
        overran = index is not None and now - since > settings.timeout + settings.shrink_seconds
        if p.is_alive() and not overran:
            continue
        if overran:
            p.kill()
        p.join(timeout=5)
        del workers[pid]
        running.pop(pid, None)
        if index is not None and index not in done:
            seed = model_seed(settings.seed, index)
            why = f"the worker {'took more than ' + str(settings.timeout) + ' s' if overran else f'died (exit {p.exitcode})'}"
            done[index] = Outcome(seed, failure=Failure("differential", "difference",
                                                        f"{why} on model {seed}: the FMU crashed or hung its host"))
        spawn()


def _progress_line(index: int, o: Outcome, done: int, total: int) -> str:
    state = "ok" if o.failure is None else f"FAIL {o.failure.prop}/{o.failure.kind}"
    if o.unsupported:
        state = f"not supported: {o.unsupported}"
    line = f"[{done}/{total}] model {o.seed} ({o.language}): {state}"
    if o.failure is not None:
        line += "\n    " + o.failure.message.strip().replace("\n", "\n    ")[:2000]
    return line


# ---------------------------------------------------------------------------- the table


def print_table(report: Report, out: TextIO) -> None:
    s = report.settings
    off = sorted(f.name for f in FEATURES if f.name not in s.on)
    n = len(report.outcomes)
    print(f"fuzz: seed {s.seed}, {n} models, jobs {s.jobs}, {s.budget.scenarios} scenarios x {s.budget.instants} "
          f"instants per semantics, sanitizers on {'every' if s.sanitize_all else f'1 in {s.sanitize_every}'} model(s), "
          f"-O2 and validation on {'both semantics of every' if s.optimise_all else f'one semantics of 1 in {max(1, s.optimise_every)}'} "
          "model(s)", file=out)
    if report.interrupted:
        print(f"interrupted: {n} of {s.count} models checked (the table counts those)", file=out)
    print(f"features off: {', '.join(off) or 'none'}", file=out)
    languages = Counter(o.language for o in report.outcomes)
    print("models: " + ", ".join(f"{k} {v}" for k, v in sorted(languages.items()) if k), file=out)
    print(f"\n{'property':<14}{'pass':>8}{'fail':>8}{'not run':>9}", file=out)
    for p in PROPERTIES:
        passed = sum(1 for o in report.outcomes if p in o.passed)
        failed = sum(1 for o in report.outcomes if o.failure is not None and o.failure.prop == p)
        print(f"{p:<14}{passed:>8}{failed:>8}{n - passed - failed:>9}", file=out)
    print(f"\n{'failures by kind':<22}" + "  ".join(f"{k} {report.count(k)}" for k in KINDS), file=out)
    warned = sum(1 for o in report.outcomes if o.warnings)
    print(f"models with check warnings: {warned} of {n}", file=out)
    print(f"super-dense steps compared: {sum(o.steps for o in report.outcomes)}, output ticks compared: "
          f"{sum(o.outputs for o in report.outcomes)}", file=out)
    unsupported = report.unsupported
    print(f"\nnot supported ({sum(unsupported.values())} models):", file=out)
    for what, c in sorted(unsupported.items(), key=lambda kv: (-kv[1], kv[0])):
        print(f"{c:>6}  {what}", file=out)
    phases = Counter()
    for o in report.outcomes:
        phases.update(o.seconds)
    cpu = sum(o.cpu for o in report.outcomes)
    print(f"\nseconds: {report.seconds:.0f} in all, {report.seconds / max(n, 1):.2f} per model; CPU {cpu:.0f} s "
          f"({cpu / max(n, 1):.2f} per model, C compiler included); wall seconds by phase: "
          + ", ".join(f"{k} {v:.0f}" for k, v in phases.most_common()), file=out)
    for o in report.outcomes:
        if o.failure is not None:
            print(f"\nmodel {o.seed}: {o.failure.prop} ({o.failure.kind})\n  "
                  + o.failure.message.strip().replace("\n", "\n  ")[:3000], file=out)
    print(report.summary(), file=out)


__all__ = ["Settings", "Report", "run", "check_one", "print_table"]
