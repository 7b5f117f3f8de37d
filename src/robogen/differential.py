"""Differential testing of generated FMUs: drive an FMU and the reference interpreter
(:mod:`robogen.ir.interp`) with the same inputs, record both traces, report the first difference.

An input *scenario* is a list of time instants on a grid of half periods. In each instant the
periodic clock (``cycle`` or ``tock``) may tick, input clocks tick with payloads, either before
the instant is evaluated (``early``) or after its first read (``late``: the runtime latches them
for the next cycle, the interpreter receives them after ``evaluate``). Every super-dense step of
the instant is recorded: the active output clocks with their clocked values, each machine's state,
every machine variable and parameter, the counters ``cycles`` and ``dropped_events``, and
``discreteStatesNeedUpdate``. A run-time error ends the run with an ``error`` record at the step
where it happened (the FMU: an fmi3Error from the first read of the instant; the interpreter: a
RuntimeFault from ``evaluate``).

The FMU is driven through the project's thin binding (:mod:`robogen.cosim.fmi3`) with raw FMI
calls; values are read in one call per type. :func:`compare` runs one scenario through both and
returns the first record where they differ. The code generator's tests and the model fuzzer
(:mod:`robogen.fuzz`) build on this module.
"""

from __future__ import annotations

import math
import random
import shutil
import zipfile
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from xml.etree import ElementTree

from fmpy import read_model_description

from robogen.codegen.api import build_fmu, compile_model
from robogen.cosim import fmi3
from robogen.fmu.fmi import ERROR
from robogen.fmu.headers import PLATFORM_TUPLE
from robogen.ir import model as ir
from robogen.ir.interp import Interpreter, RuntimeFault
from robogen.codegen.generate import CodegenOptions
from robogen.ir.lower import LoweringOptions

# ---------------------------------------------------------------------------- scenarios


class TooManySteps(Exception):
    """An instant that never settles: more super-dense steps than the driver allows."""



@dataclass(frozen=True)
class Tick:
    clock: str
    payload: dict[str, object]  # FMI name of each clocked input -> value (a list for arrays)
    at: int = 0  # late ticks: the super-dense step of the instant after whose first read it comes


@dataclass(frozen=True)
class Instant:
    periodic: bool
    early: tuple[Tick, ...] = ()
    late: tuple[Tick, ...] = ()


class Scenario(list):
    """A list of instants; ``half``: the instants are half a period apart (the periodic clock is
    due on even instants only), else one period apart (due on every instant)."""

    def __init__(self, instants=(), half: bool = True):
        super().__init__(instants)
        self.half = half


@dataclass
class Step:
    """What one super-dense step shows."""

    instant: int
    k: int
    outputs: dict[str, dict[str, object]]
    states: dict[str, int]
    variables: dict[str, object]
    cycles: int
    dropped: int
    misses: int
    need: bool


@dataclass
class Error:
    instant: int
    k: int
    where: str  # FMU: the function that failed; interpreter: the fault message

    def key(self) -> tuple:
        return ("error", self.instant, self.k)


@dataclass
class Trace:
    steps: list[Step] = field(default_factory=list)
    error: Error | None = None

    def comparable(self) -> list:
        out: list = [(s.instant, s.k, canonical(s.outputs), s.states, canonical(s.variables), s.cycles, s.dropped, s.misses, s.need) for s in self.steps]
        if self.error is not None:
            out.append(self.error.key())
        return out


def canonical(value):
    """NaN equals NaN in traces; ints and bools keep their type."""
    if isinstance(value, dict):
        return {k: canonical(v) for k, v in sorted(value.items())}
    if isinstance(value, (list, tuple)):
        return [canonical(v) for v in value]
    if isinstance(value, float) and math.isnan(value):
        return "nan"
    return value


# ---------------------------------------------------------------------------- FMU description


@dataclass
class Var:
    name: str
    vr: int
    type: str  # Float64, Int64, UInt64, Boolean, Enumeration, Clock
    causality: str
    size: int  # 1, or the array length
    clock: str | None = None
    items: int = 0  # enumerations: number of items
    array: bool = False  # declared with dimensions (a vector of one element is an array too)


class Description:
    """The variables of a generated FMU, grouped for the driver."""

    def __init__(self, folder: Path):
        md = read_model_description(str(folder / "modelDescription.xml"))
        self.md = md
        self.token = md.guid
        self.identifier = md.coSimulation.modelIdentifier
        enum_items = {t.name: len(t.items) for t in md.typeDefinitions if getattr(t, "items", None)}
        self.vars: list[Var] = []
        for v in md.modelVariables:
            if v.causality == "independent":
                continue
            size = 1
            for d in v.dimensions:
                size *= int(d.start)
            clock = v.clocks[0].name if v.clocks else None
            self.vars.append(Var(v.name, v.valueReference, v.type, v.causality, size, clock,
                                 enum_items.get(v.declaredType, 0) if v.declaredType else 0, bool(v.dimensions)))
        self.by_name = {v.name: v for v in self.vars}
        clocks = [v for v in self.vars if v.type == "Clock"]
        root = ElementTree.parse(folder / "modelDescription.xml").getroot()
        periodic = [e.get("name") for e in root.iter("Clock") if e.get("intervalVariability") == "constant"]
        # rg_clocks index 0: cycle or tock; None for a RoboChart FMU compiled with --time skip
        self.periodic: str | None = periodic[0] if periodic else None
        self.input_clocks = [v.name for v in clocks if v.causality == "input" and v.name != self.periodic]
        self.output_clocks = [v.name for v in clocks if v.causality == "output"]
        self.clocked = {c.name: [v for v in self.vars if v.clock == c.name] for c in clocks}
        self.states = [v for v in self.vars if v.name.endswith(".state") and v.type == "Enumeration"]
        self.observed = [v for v in self.vars if v.type != "Clock" and v.clock is None and v.causality in ("local", "parameter")]
        if self.periodic is not None:
            clock = next(e for e in root.iter("Clock") if e.get("name") == self.periodic)
            self.interval = float(clock.get("intervalDecimal"))  # type: ignore[arg-type]  # fmpy does not read it
        else:  # a time-free FMU's time unit: its default step
            self.interval = float(md.defaultExperiment.stepSize)


# ---------------------------------------------------------------------------- random scenarios


INT_VALUES = [-7, -3, -2, -1, 0, 0, 1, 1, 2, 3, 5, 9]
INT_EXTREMES = [2**63 - 1, -(2**63), 2**62]
NAT_VALUES = [0, 0, 1, 1, 2, 3, 4, 7]
NAT_EXTREMES = [2**64 - 1, 2**63]
REAL_VALUES = [-2.5, -1.0, -0.5, 0.0, 0.0, 0.25, 0.5, 1.0, 1.5, 3.0]
REAL_EXTREMES = [1e300, -1e300, 1e-300]
STRING_VALUES = ["", "a", "hello", "bye", "\u00e9t\u00e9", "x" * 100]  # with UTF-8 beyond ASCII


def random_value(rng: random.Random, var: Var, choices: dict[str, list] | None = None):
    """A random value of ``var``'s type, drawn from ``choices[var.name]`` if given."""
    def one():
        if choices and var.name in choices:
            return rng.choice(choices[var.name])
        if var.type == "Boolean":
            return rng.random() < 0.5
        if var.type == "Enumeration":
            return rng.randrange(max(var.items, 1))
        if var.type == "String":
            return rng.choice(STRING_VALUES)
        extreme = rng.random() < 0.05
        if var.type == "Int64":
            return rng.choice(INT_EXTREMES if extreme else INT_VALUES)
        if var.type == "UInt64":
            return rng.choice(NAT_EXTREMES if extreme else NAT_VALUES)
        return rng.choice(REAL_EXTREMES if extreme else REAL_VALUES)

    if var.array:
        return [one() for _ in range(var.size)]
    return one()


def random_scenario(rng: random.Random, desc: Description, instants: int, *, rate: float = 0.3,
                    late_rate: float = 0.15, every_instant: bool = False,
                    choices: dict[str, list] | None = None) -> Scenario:
    """A random scenario: the periodic clock ticks on even instants (every instant if
    ``every_instant``); each input clock ticks with probability ``rate`` before the instant's
    first read, or with probability ``late_rate`` after the first read of super-dense step 0, 1
    or 2 of the instant (skipped if the instant has fewer steps)."""
    out = []
    for i in range(instants):
        periodic = every_instant or i % 2 == 0
        early, late = [], []
        for clock in desc.input_clocks:
            r = rng.random()
            payload = {v.name: random_value(rng, v, choices) for v in desc.clocked[clock]}
            if r < rate:
                early.append(Tick(clock, payload))
            elif r < rate + late_rate:
                late.append(Tick(clock, payload, at=rng.choice((0, 0, 1, 2))))
        rng.shuffle(early)
        out.append(Instant(periodic, tuple(early), tuple(late)))
    return Scenario(out, half=not every_instant)


# ---------------------------------------------------------------------------- the FMU side

COUNTERS = ("cycles", "dropped_events", "deadline_misses")


class FmuRunner:
    """One instance of a generated FMU, reset between scenarios."""

    def __init__(self, folder: Path, name: str = "driver", logging: bool = False):
        """``logging``: every message of the FMU is kept in ``messages`` (from fmi3InstantiateCoSimulation on)."""
        self.desc = Description(folder)
        so = folder / "binaries" / PLATFORM_TUPLE / f"{self.desc.identifier}.so"
        self.library = fmi3.Library(str(so))
        self.errors: list[str] = []  # the FMU's error messages in the current run
        self.messages: list[str] = []
        self.logging = logging
        self.inst = fmi3.Binding(self.library, name, log=self._log)
        self.inst.fmi3InstantiateCoSimulation(self.desc.token, None, loggingOn=logging, eventModeUsed=True)
        self.fresh = True
        d = self.desc
        self._vr_cache: dict[tuple[str, ...], object] = {}
        self.out_clock_vrs = fmi3.vr_array([d.by_name[c].vr for c in d.output_clocks])
        self.out_clock_values = fmi3.value_array("Clock", len(d.output_clocks))
        self.one_clock = fmi3.value_array("Clock", 1)
        self.one_clock[0] = True
        self.observed = _group(d.states + d.observed + [d.by_name[n] for n in COUNTERS])
        self.clocked_out = {c: _group(d.clocked[c]) for c in d.output_clocks}

    def _log(self, name: str, status: int, text: str) -> None:
        if self.logging:
            self.messages.append(text)
        if status >= ERROR:
            self.errors.append(text)

    def close(self) -> None:
        """Free the instance and unload the binary."""
        self.inst.fmi3FreeInstance()
        self.library.close()

    def set_tick(self, tick: Tick) -> None:
        d = self.desc
        self.inst.fmi3SetClock(fmi3.vr_array([d.by_name[tick.clock].vr]), 1, self.one_clock)
        for name, value in tick.payload.items():
            var = d.by_name[name]
            values = value if isinstance(value, list) else [value]
            buf, _, _keep = fmi3.encode(var.type, values)
            self.inst.set(var.type, fmi3.vr_array([var.vr]), 1, buf, n_values=len(values))

    def _read(self, group) -> dict[str, object]:
        out: dict[str, object] = {}
        for fmi_type, (vars_, vrs, n_values, buf) in group.items():
            self.inst.get(fmi_type, vrs, len(vars_), buf, n_values=n_values)
            if fmi_type == "String":
                buf = fmi3.decode_strings(buf, n_values)
            pos = 0
            for v in vars_:
                values = [_py(buf[pos + j], fmi_type) for j in range(v.size)]
                out[v.name] = values if v.array else values[0]
                pos += v.size
        return out

    def observe(self, instant: int, k: int) -> Step:
        d = self.desc
        outputs: dict[str, dict[str, object]] = {}
        if d.output_clocks:
            self.inst.fmi3GetClock(self.out_clock_vrs, len(d.output_clocks), self.out_clock_values)
            for i, c in enumerate(d.output_clocks):
                if self.out_clock_values[i]:
                    outputs[c] = self._read(self.clocked_out[c])
        seen = self._read(self.observed)
        states = {v.name: seen.pop(v.name) for v in d.states}
        counters = [seen.pop(n) for n in COUNTERS]
        return Step(instant, k, outputs, states, seen, *counters, False)

    def run(self, scenario: Scenario, max_k: int = 2000, parameters: dict[str, object] | None = None) -> Trace:
        """Reset (or the first run: the fresh instance), set ``parameters`` (FMI name -> value) in
        Initialization Mode, then drive the scenario."""
        inst, d = self.inst, self.desc
        trace = Trace()
        self.errors = []
        if not self.fresh:
            inst.fmi3Reset()
        self.fresh = False
        h = d.interval / 2 if getattr(scenario, "half", True) else d.interval
        where = "fmi3ExitInitializationMode"
        instant, k = 0, 0
        try:
            inst.fmi3EnterInitializationMode(None, 0.0, None)
            for name, value in (parameters or {}).items():
                var = d.by_name[name]
                values = value if isinstance(value, list) else [value]  # an array parameter: its elements
                buf, _, _keep = fmi3.encode(var.type, values)
                inst.set(var.type, fmi3.vr_array([var.vr]), 1, buf, n_values=len(values))
            inst.fmi3ExitInitializationMode()
            for instant, step in enumerate(scenario):
                k = 0
                if instant > 0:
                    where = "fmi3DoStep"
                    inst.fmi3EnterStepMode()
                    inst.fmi3DoStep((instant - 1) * h, h)
                    inst.fmi3EnterEventMode()
                where = "fmi3SetClock"
                if step.periodic and d.periodic is not None:  # a time-free FMU's tock is due by time
                    inst.fmi3SetClock(fmi3.vr_array([d.by_name[d.periodic].vr]), 1, self.one_clock)
                for tick in step.early:
                    self.set_tick(tick)
                while True:
                    where = "read"
                    record = self.observe(instant, k)
                    where = "late"
                    for tick in step.late:
                        if tick.at == k:
                            self.set_tick(tick)
                    where = "fmi3UpdateDiscreteStates"
                    need = inst.fmi3UpdateDiscreteStates()[0]
                    record.need = bool(need)
                    trace.steps.append(record)
                    if not need:
                        break
                    k += 1
                    if k > max_k:
                        raise TooManySteps(f"the FMU asks for more than {max_k} super-dense steps in instant {instant}")
        except fmi3.FMI3Error as exc:
            trace.error = Error(instant, k, f"{where}: {exc.function}: " + " | ".join(self.errors))
        return trace


def _group(vars_: list[Var]) -> dict[str, tuple]:
    by_type: dict[str, list[Var]] = {}
    for v in vars_:
        by_type.setdefault(v.type, []).append(v)
    out = {}
    for t, vs in by_type.items():
        n = sum(v.size for v in vs)
        out[t] = (vs, fmi3.vr_array([v.vr for v in vs]), n, fmi3.value_array(t, n))
    return out


def _py(value, fmi_type: str):
    if fmi_type == "String":
        return value
    if fmi_type == "Boolean":
        return bool(value)
    if fmi_type == "Float64":
        return float(value)
    return int(value)


# ---------------------------------------------------------------------------- the interpreter side


def interpret(fmu: ir.Fmu, scenario: list[Instant], desc: Description, max_k: int = 2000,
              parameters: dict[str, object] | None = None, functions: dict | None = None) -> Trace:
    it = Interpreter(fmu, parameters, functions)
    trace = Trace()
    params = {p.fmi_name for p in fmu.params}
    instant, k = 0, 0
    try:
        it.exit_initialization()
        for instant, step in enumerate(scenario):
            k = 0
            for tick in step.early:
                it.latch(tick.clock, tick.payload)
            while True:
                shown = it.evaluate(step.periodic and k == 0)
                variables = {n: v for n, v in it.variables().items() if n in desc.by_name or n in params}
                record = Step(instant, k, {c: dict(v) for c, v in shown.outputs.items()},
                              {m.name + ".state": node for m, node in zip(fmu.machines, shown.states)},
                              _fmi_values(variables), it.cycles, it.dropped, it.deadline_misses, False)
                for tick in step.late:
                    if tick.at == k:
                        it.latch(tick.clock, tick.payload)
                record.need = it.update()
                trace.steps.append(record)
                if not record.need:
                    break
                k += 1
                if k > max_k:
                    raise TooManySteps(f"the interpreter asks for more than {max_k} super-dense steps in instant {instant}")
    except RuntimeFault as exc:
        trace.error = Error(instant, k, str(exc))
    return trace


def _fmi_values(values: dict[str, object]) -> dict[str, object]:
    """Interpreter values as the FMU shows them (exact reals as floats)."""
    out = {}
    for n, v in values.items():
        if isinstance(v, Fraction):
            v = float(v)
        elif isinstance(v, list):
            v = [float(x) if isinstance(x, Fraction) else x for x in v]
        out[n] = v
    return out


# ---------------------------------------------------------------------------- time: ticking against skipping


@dataclass(frozen=True)
class Timed:
    """Input clock ticks at a time, ``half`` half time units after the start."""

    half: int
    ticks: tuple[Tick, ...]


def timed_events(rng: random.Random, desc: Description, units: int, *, rate: float = 0.05,
                 choices: dict[str, list] | None = None) -> list[Timed]:
    """Random input events over ``units`` time units: at each half unit, each input clock ticks
    with probability ``rate`` (with a random payload)."""
    out = []
    for half in range(1, 2 * units):
        ticks = [Tick(c, {v.name: random_value(rng, v, choices) for v in desc.clocked[c]})
                 for c in desc.input_clocks if rng.random() < rate]
        if ticks:
            out.append(Timed(half, tuple(ticks)))
    return out


@dataclass
class TimedTrace:
    """What a run in time shows: each transition and deadline miss (the FMU's logTransitions and
    warning messages of its machines), and each super-dense step where an output clock ticks or
    a state, variable or counter other than ``cycles`` changes, keyed by (time, k); and the
    number of Event Mode instants the run took."""

    records: list[tuple] = field(default_factory=list)
    instants: int = 0


def run_in_time(folder: Path, events: list[Timed], units: int, parameters: dict[str, object] | None = None,
                max_k: int = 2000) -> TimedTrace:
    """Drive the FMU in ``folder`` from 0 to ``units`` time units as a master does: Event Mode
    at each input event, and at each tick of ``tock`` (a ticking FMU) or at the next event time
    the FMU announces (a time-free one); DoStep in between."""
    runner = FmuRunner(folder, logging=True)
    d, inst = runner.desc, runner.inst
    names = [f"{inst.name}: {v.name[:-len('.state')]}: " for v in d.states]  # the machines' messages
    half_unit = d.interval / 2
    trace = TimedTrace()
    shown: tuple | None = None
    try:
        inst.fmi3EnterInitializationMode(None, 0.0, None)
        for name, value in (parameters or {}).items():
            var = d.by_name[name]
            buf, _, _keep = fmi3.encode(var.type, value if isinstance(value, list) else [value])
            inst.set(var.type, fmi3.vr_array([var.vr]), 1, buf, n_values=len(value) if isinstance(value, list) else 1)
        inst.fmi3ExitInitializationMode()
        half, pending, announced = 0, list(events), None
        while True:
            trace.instants += 1
            if d.periodic is not None and half % 2 == 0:
                inst.fmi3SetClock(fmi3.vr_array([d.by_name[d.periodic].vr]), 1, runner.one_clock)
            while pending and pending[0].half == half:
                for tick in pending.pop(0).ticks:
                    runner.set_tick(tick)
            k = 0
            while True:
                runner.messages = []
                step = runner.observe(half, k)
                trace.records += [("transition", half, k, text) for text in runner.messages if text.startswith(tuple(names))]
                now = (canonical(step.states), canonical(step.variables), step.dropped, step.misses)
                if step.outputs or now != shown:
                    trace.records.append(("step", half, k, canonical(step.outputs), *now, step.cycles))
                shown = now
                states = inst.fmi3UpdateDiscreteStates()
                if not states.discrete_states_need_update:
                    break
                k += 1
                if k > max_k:
                    raise TooManySteps(f"more than {max_k} super-dense steps at t={half * half_unit}")
            if d.periodic is None:
                announced = round(states.next_event_time / half_unit) if states.next_event_time_defined else None
            candidates = [h for h in (pending[0].half if pending else None, announced,
                                      half + 2 - half % 2 if d.periodic is not None else None, 2 * units) if h is not None]
            target = min(candidates)
            if half >= 2 * units:
                break
            if target <= half:
                trace.records.append(("error", "nextEventTime", f"{states.next_event_time} is not after t={half * half_unit}"))
                break
            inst.fmi3EnterStepMode()
            inst.fmi3DoStep(half * half_unit, (target - half) * half_unit)
            inst.fmi3EnterEventMode()
            half = target
    except fmi3.FMI3Error as exc:
        trace.records.append(("error", exc.function, " | ".join(runner.errors)))
    finally:
        runner.close()
    return trace


def first_time_difference(ticking: TimedTrace, skipping: TimedTrace) -> str | None:
    """Where the traces of the ticking and the time-free FMU part (None: they are the same)."""
    for i, (x, y) in enumerate(zip(ticking.records, skipping.records)):
        if x != y:
            return f"record {i}:\n  ticking  {x}\n  skipping {y}"
    if len(ticking.records) != len(skipping.records):
        return f"lengths differ: ticking {len(ticking.records)} records, skipping {len(skipping.records)}"
    return None


# ---------------------------------------------------------------------------- building


@dataclass
class Built:
    """A model compiled and packaged with one set of options."""

    fmu: ir.Fmu
    archive: Path  # the .fmu
    folder: Path  # unzipped: modelDescription.xml, binaries/, sources/
    sources: dict[str, str]

    @property
    def desc(self) -> Description:
        return Description(self.folder)


def build(paths: list[Path], work: Path, *, module: str | None = None, machine: str | None = None,
          options: LoweringOptions | None = None, functions: Path | None = None) -> Built:
    """compile_model + build_fmu (validated), then unzip the archive for loading; ``functions``
    is the C file of the model's user functions."""
    compiled = compile_model([str(p) for p in paths], work / "src", module=module, machine=machine, options=options,
                             codegen=CodegenOptions(functions=functions))
    archive = build_fmu(compiled.folder, work / f"{compiled.fmu.model_identifier}.fmu",
                        model_identifier=compiled.generated.model_identifier, validate=True)
    folder = work / "unzipped"
    if folder.exists():
        shutil.rmtree(folder)
    with zipfile.ZipFile(archive) as z:
        z.extractall(folder)
    return Built(compiled.fmu, archive, folder, dict(compiled.generated.files))


def first_difference(fmu_trace: Trace, interp_trace: Trace) -> str | None:
    """Where two traces part: the first record that differs, shown from both sides (or their
    lengths, when one is a prefix of the other); None when they are equal."""
    a, b = fmu_trace.comparable(), interp_trace.comparable()
    if a == b:
        return None
    for i, (x, y) in enumerate(zip(a, b)):
        if x != y:
            return f"record {i}:\n  FMU         {x}\n  interpreter {y}"
    return (f"lengths differ: FMU {len(a)} records (error {fmu_trace.error}), "
            f"interpreter {len(b)} (error {interp_trace.error})")


def compare(runner: FmuRunner, fmu: ir.Fmu, scenario: Scenario, *, parameters: dict[str, object] | None = None,
            functions: dict | None = None) -> tuple[Trace, str | None]:
    """Run ``scenario`` through the FMU of ``runner`` and through the interpreter of ``fmu`` (its
    IR): the FMU's trace and the first difference (None when they agree)."""
    got = runner.run(scenario, parameters=parameters)
    expected = interpret(fmu, scenario, runner.desc, parameters=parameters, functions=functions)
    return got, first_difference(got, expected)


__all__ = ["Timed", "timed_events", "TimedTrace", "run_in_time", "first_time_difference",
           "Tick", "Instant", "Scenario", "canonical", "Step", "Error", "Trace", "Var", "Description", "FmuRunner",
           "interpret", "random_value", "random_scenario", "build", "Built", "first_difference", "compare", "TooManySteps"]
