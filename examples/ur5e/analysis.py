"""Read a UR5e co-simulation run (results CSV, events log) and measure what the case study is
about: for each command, when the d-model called the platform, when the arm moved, completed and
stopped, how far the flange ended from its target, and whether every property the demo must
show holds.

Times are pairs (t, k) of super-dense time: t in seconds, k the index within the instant.
"""

from __future__ import annotations

import csv
import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterable

from robogen.platforms.kinematics import grid_position

At = tuple[float, int]

EE_TOLERANCE_MM = 1.0


@dataclass
class Run:
    name: str
    columns: list[str]
    rows: list[list[object]]
    events: list[dict]
    node_names: dict[int, str]
    machine: str  # the d-model machine (its state column is dmodel.<machine>.state)
    wall: float = 0.0  # seconds of wall time of the simulation
    event_iterations: int = 0
    instants: int = 0

    def index(self, column: str) -> int:
        return self.columns.index(column)

    def column(self, column: str) -> list[object]:
        i = self.index(column)
        return [r[i] for r in self.rows]

    @property
    def state_column(self) -> str:
        return f"dmodel.{self.machine}.state"

    def times(self, fmu: str, clock: str) -> list[tuple[At, dict]]:
        return [((e["time"], e["index"]), e["values"]) for e in self.events if e["fmu"] == fmu and e["clock"] == clock]


def _value(text: str) -> object:
    if text == "":
        return None
    try:
        return int(text)
    except ValueError:
        return float(text)


def load_run(name: str, results: Path, events: Path, node_names: dict[int, str], machine: str) -> Run:
    with results.open(newline="") as f:
        reader = csv.reader(f)
        columns = next(reader)
        rows = [[_value(x) for x in row] for row in reader]
    with events.open() as f:
        log = [json.loads(line) for line in f if line.strip()]
    return Run(name, columns, rows, log, node_names, machine)


def node_names_of(fmu: Path) -> tuple[dict[int, str], str]:
    """The d-model's node enumeration (value -> name) and machine name, from its .fmu."""
    import zipfile
    from xml.etree import ElementTree

    with zipfile.ZipFile(fmu) as z:
        root = ElementTree.fromstring(z.read("modelDescription.xml"))
    for var in root.iter("Enumeration"):
        name = var.get("name", "")
        if name.endswith(".state"):
            declared = var.get("declaredType")
            for t in root.iter("EnumerationType"):
                if t.get("name") == declared:
                    return {int(i.get("value")): i.get("name") for i in t.iter("Item")}, name[: -len(".state")]
    raise ValueError(f"{fmu}: no <machine>.state variable")


@dataclass
class Command:
    index: int
    at: At
    target: tuple[int, int, int]
    next_time: float | None
    dmodel_call: At | None = None
    platform_call: At | None = None
    feasible: At | None = None
    motion_start: float | None = None
    motions: int = 0
    completed: At | None = None
    completed_sample: At | None = None
    stop: At | None = None
    stopped: At | None = None
    idle: float | None = None
    ee_error_mm: float | None = None
    early_stop: bool = False  # a stop before moveCompleted: the defect the reference had

    @property
    def idle_before_next(self) -> bool:
        return self.idle is not None and (self.next_time is None or self.idle <= self.next_time)


@dataclass
class Report:
    run: Run
    commands: list[Command]
    checks: dict[str, bool] = field(default_factory=dict)
    max_index: int = 0
    instants_by_index: dict[int, int] = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return all(self.checks.values())


def _first(items: Iterable[tuple[At, dict]], after: At, before: float | None, where=lambda v: True) -> At | None:
    for at, values in items:
        if at >= after and (before is None or at[0] < before) and where(values):
            return at
    return None


def analyse(run: Run, cycle: float) -> Report:
    commands = run.times("controller", "moveDiscreteCommand")
    calls = run.times("dmodel", "movediscrete")
    received = run.times("platform", "movediscrete")
    feasible = run.times("platform", "feasibleMoveDiscreteCommand")
    completed = run.times("platform", "moveCompleted")
    stops = run.times("dmodel", "stop")
    stopped = run.times("platform", "robotStopped")
    samples = {at for at, _ in run.times("platform", "sample")}
    t_col, state_col = run.index("time"), run.index(run.state_column)
    motions_col = run.index("platform.motions")
    ee = [run.index(f"platform.ee_{a}") for a in "xyz"]
    out: list[Command] = []
    for i, (at, values) in enumerate(commands):
        target = tuple(values[f"moveDiscreteCommand.target_{a}"] for a in "XYZ")
        next_time = commands[i + 1][0][0] if i + 1 < len(commands) else None
        c = Command(i, at, target, next_time)  # type: ignore[arg-type]
        same = lambda v: tuple(v.get(f"movediscrete.target_{a}") for a in "XYZ") == target  # noqa: E731
        c.dmodel_call = _first(calls, at, next_time, same)
        c.platform_call = _first(received, at, next_time, same)
        # Conditions count from the instant the platform has the new command (in stepwise
        # semantics that is a later super-dense index than the controller's command).
        since = c.platform_call or at
        c.feasible = _first(feasible, since, next_time)
        c.completed = _first(completed, since, next_time)
        c.completed_sample = next((a for a, _ in completed if a >= since and (next_time is None or a[0] < next_time) and a in samples), None)
        c.stop = _first(stops, since, next_time)
        c.early_stop = c.stop is not None and (c.completed is None or c.stop < c.completed)
        if c.stop is not None:
            c.stopped = _first(stopped, c.stop, next_time)
        # motions: increments of the platform's counter while this command is current
        before = [r[motions_col] for r in run.rows if (r[t_col], 0) < at and r[motions_col] is not None]
        during = [(r[t_col], r[motions_col]) for r in run.rows if at[0] <= r[t_col] and (next_time is None or r[t_col] < next_time)]
        base = before[-1] if before else 0
        c.motions = (during[-1][1] - base) if during else 0  # type: ignore[operator]
        c.motion_start = next((t for t, m in during if m is not None and m > base), None)  # type: ignore[operator]
        # back in Idle: the first row at or after the stop where the machine rests in Idle
        if c.stop is not None:
            c.idle = next((r[t_col] for r in run.rows if (r[t_col], 0) >= (c.stop[0], 0) and
                           run.node_names.get(r[state_col]) == "Idle"), None)  # type: ignore[arg-type]
        # where the flange rests: the last row before the next command (or the end)
        rest = [r for r in run.rows if r[t_col] >= at[0] and (next_time is None or r[t_col] < next_time)]
        if rest:
            x, y, z = (rest[-1][j] for j in ee)
            gx, gy, gz = grid_position(*target)
            c.ee_error_mm = 1000.0 * math.dist((x, y, z), (gx, gy, gz))  # type: ignore[arg-type]
        out.append(c)
    report = Report(run, out)
    index_col = run.index("superdense")
    per_time: dict[float, int] = {}
    for r in run.rows:
        per_time[r[t_col]] = max(per_time.get(r[t_col], 0), r[index_col])  # type: ignore[arg-type, assignment]
    report.max_index = max(per_time.values(), default=0)
    for k in per_time.values():
        report.instants_by_index[k] = report.instants_by_index.get(k, 0) + 1
    report.checks = {
        "16 commands were sent": len(out) == 16,
        "every command reaches its target (flange within 1 mm)": all(c.ee_error_mm is not None and c.ee_error_mm <= EE_TOLERANCE_MM for c in out),
        "movediscrete fires at the same time instant as its moveDiscreteCommand": all(c.dmodel_call is not None and c.dmodel_call[0] == c.at[0] for c in out),
        "the platform receives movediscrete in that instant too": all(c.platform_call is not None and c.platform_call[0] == c.at[0] for c in out),
        "stop only after moveCompleted, within one cycle of the first sample where it holds": all(
            c.stop is not None and not c.early_stop and c.completed_sample is not None
            and c.stop[0] - c.completed_sample[0] <= cycle + 1e-9 for c in out),
        "each command produces exactly one motion": all(c.motions == 1 for c in out),
        "the arm is back in Idle before the next command": all(c.idle_before_next for c in out),
    }
    return report
