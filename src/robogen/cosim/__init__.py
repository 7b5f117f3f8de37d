"""robogen's co-simulation master for FMI 3.0 Co-Simulation FMUs with clocks.

Python API::

    from robogen.cosim import simulate_system
    result = simulate_system("models/ur5e/system.toml", stop=100.0, output="results.csv",
                             events="events.jsonl", realtime=1.0)
    result.columns          # ["time", "superdense", "controller.moveDiscreteCommand", ...]
    result.rows             # one list per recorded row (clocks 0/1, inactive clocked values None)
    result.stats            # steps, event_iterations, instants, early_returns, end_time, terminated_by, realtime,
                            # stretch (the quiet stretches' loop: "C", "Python" or None)

``simulate_system(system_toml_path, *, stop=None, step=None, output=None, events=None,
realtime=None, progress=False, trace=None, keep_rows=True) -> SimulationResult``

- ``stop``/``step`` override ``[experiment] stop``/``step`` of the file.
- ``output``: CSV path, streamed as the run goes; ``events``: JSON-lines events log path.
- ``realtime``: pace simulated time at this factor of the wall clock (1.0 = real time); the
  lag statistics land in ``result.stats.realtime``.
- ``progress``: draw a progress bar on stderr (None: only when stderr is a terminal).
- ``trace``: a callable receiving one line per FMI call.

Bad input (system file, FMUs) and failing FMUs raise :class:`robogen.diagnostics.RobogenError`
with located diagnostics; the CSV written up to the failure stays on disk. The system file
format is described in docs/system-toml.md; the algorithm in :mod:`robogen.cosim.master`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

__all__ = ["simulate_system", "SimulationResult"]


@dataclass
class SimulationResult:
    columns: list[str]
    rows: list[list]
    stats: "object"
    output: Path | None = None
    events: Path | None = None
    notes: list[str] = field(default_factory=list)

    def column(self, name: str) -> list:
        i = self.columns.index(name)
        return [r[i] for r in self.rows]


def simulate_system(system_toml_path: str | Path, *, stop: float | None = None, step: float | None = None,
                    output: str | Path | None = None, events: str | Path | None = None,
                    realtime: float | None = None, progress: bool | None = False,
                    trace: Callable[[str], None] | None = None, keep_rows: bool = True) -> SimulationResult:
    from robogen.cosim.assemble import build_master

    master, cache = build_master(Path(system_toml_path), stop=stop, step=step, output=output, events=events,
                                 realtime=realtime, progress=progress, trace=trace, keep_rows=keep_rows)
    try:
        stats = master.run()
    finally:
        cache.close()
    return SimulationResult(master.recorder.columns, master.recorder.rows, stats,
                            Path(output) if output else None, Path(events) if events else None)
