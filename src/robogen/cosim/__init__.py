"""robogen's co-simulation master for FMI 3.0 Co-Simulation FMUs with clocks.

Python API::

    from robogen.cosim import simulate_system
    result = simulate_system("models/ur5e/system.toml", stop=100.0, output="results.csv",
                             events="events.jsonl", realtime=1.0)
    result.columns          # ["time", "superdense", "controller.moveDiscreteCommand", ...]
    result.table            # the results in columns: one NumPy array per column (robogen.cosim.columnar.Table)
    result.array("time")    # one column's array (numpy.float64; result.table.validity(name): its non-empty cells)
    result.table.to_numpy() # a structured array, as fmpy.simulate_fmu returns; .to_arrow(): a pyarrow.Table
                            # sharing the numeric columns' memory (pandas: result.table.to_arrow().to_pandas())
    result.rows             # one list per recorded row (clocks 0/1, inactive clocked values None), made when asked
    result.stats            # steps, event_iterations, instants, early_returns, end_time, terminated_by, realtime,
                            # stretch (the quiet stretches' loop: "C", "Python" or None)

``simulate_system(system_toml_path, *, stop=None, step=None, output=None, events=None,
realtime=None, progress=False, trace=None, keep_rows=True, isolate=False, watch=False, warn=None,
bindings=None)
-> SimulationResult``

- ``stop``/``step`` override ``[experiment] stop``/``step`` of the file.
- ``output``: CSV path, streamed as the run goes; ``events``: JSON-lines events log path. Both
  are written under temporary names and renamed when the run ends (the rows recorded so far,
  however it ended); neither may be the system file, one of its FMUs, or the other.
- ``realtime``: pace simulated time at this factor of the wall clock (1.0 = real time); the
  lag statistics land in ``result.stats.realtime``.
- ``progress``: draw a progress bar on stderr (None: only when stderr is a terminal).
- ``trace``: a callable receiving one line per FMI call.
- ``isolate``: run every FMU instance in a worker process of its own (instances with
  ``isolate = true`` in the file always are): a crash becomes an error (:mod:`robogen.cosim.proxy`).
- ``watch``: a watching process reports a crash of this process (:mod:`robogen.cosim.crash`).
- ``warn``: receives the warnings found before the run (default: printed on stderr).
- ``bindings``: instances bound by the caller, ``{name: make(name, model_description, notes)}``
  (``robogen test --reference`` binds the model to the reference interpreter).

Bad input (system file, FMUs) and failing FMUs raise :class:`robogen.diagnostics.RobogenError`
with located diagnostics; once the run has started, a :class:`RunError` whose ``results`` is the
CSV holding the rows recorded so far (None if none). SIGINT raises
:class:`robogen.cosim.signals.Interrupted` (with ``results`` too) after the same clean-up. The
system file format is described in docs/system-toml.md; the algorithm in :mod:`robogen.cosim.master`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable

from robogen.cosim.columnar import Table
from robogen.diagnostics import RobogenError

__all__ = ["simulate_system", "SimulationResult", "RunError"]


class SimulationResult:
    """A run's results: ``columns`` (names), ``table`` (the values in columns), ``stats``, the
    files written. ``rows`` may be given as a Table or as lists (then kept as they are)."""

    def __init__(self, columns: list[str], rows: "Table | list[list]", stats: "object", output: Path | None = None,
                 events: Path | None = None, notes: list[str] | None = None):
        self.columns = list(columns)
        self.table = rows if isinstance(rows, Table) else Table.from_rows(self.columns, rows)
        self.stats, self.output, self.events = stats, output, events
        self.notes = [] if notes is None else notes

    @property
    def rows(self) -> list[list]:
        """One list per row (made from the columns when first asked)."""
        return self.table.rows

    def column(self, name: str) -> list:
        """A column's values as Python values (None for an empty cell)."""
        return self.table.column(name)

    def array(self, name: str):
        """A column's values as its NumPy array (0 or None in an empty cell)."""
        return self.table.array(name)


class RunError(RobogenError):
    """A run that stopped on an error after it started; ``results`` holds its rows so far."""

    def __init__(self, diagnostics, results: Path | None):
        super().__init__(diagnostics)
        self.results = results


def simulate_system(system_toml_path: str | Path, *, stop: float | None = None, step: float | None = None,
                    output: str | Path | None = None, events: str | Path | None = None,
                    realtime: float | None = None, progress: bool | None = False,
                    trace: Callable[[str], None] | None = None, keep_rows: bool = True, isolate: bool = False,
                    watch: bool = False, warn: Callable | None = None, bindings: dict | None = None) -> SimulationResult:
    from robogen.cosim.assemble import FmuCache, build_master
    from robogen.cosim.crash import watch_run
    from robogen.cosim.shared import SHARED
    from robogen.cosim.signals import Interrupted, deferred

    watcher, recorder = watch_run(watch), None
    try:
        cache = FmuCache()
        watcher.publish(temp=cache.root)
        master, cache = build_master(Path(system_toml_path), stop=stop, step=step, output=output, events=events,
                                     realtime=realtime, progress=progress, trace=trace, keep_rows=keep_rows,
                                     isolate=isolate, cache=cache, notes=watcher.notes, warn=warn, bindings=bindings)
        recorder = master.recorder
        watcher.publish(temp=cache.root, shared=SHARED.root, files=recorder.files, output=output)
        try:
            stats = master.run()
        except RobogenError as exc:
            raise RunError(exc.diagnostics, recorder.kept) from None
        finally:
            with deferred():
                cache.close()
    except Interrupted as exc:  # in the run, or in its clean-up
        exc.results = recorder.kept if recorder is not None else None
        raise
    finally:
        with deferred():
            watcher.close()
    return SimulationResult(recorder.columns, recorder.table(), stats,
                            Path(output) if output else None, Path(events) if events else None)
