"""Benchmark of RoboChart time for free (issue 22): an idle-waiting RoboChart controller
simulated over 10^6 time units by robogen's master, the FMU compiled with ``--time skip`` (the
default: it announces its next event time) against the same model compiled with ``--time tick``
(the master ticks ``tock`` at every time unit), in the same run.

The controller waits 400,000 time units (``wait(n)``), says so, then waits for an event that never
comes and, 900,000 units after it entered its state, gives up: three moments in 10^6 time units
at which anything happens. Both runs record the same variables (every output and input clock,
the machine's state) in memory, with a communication step of 10^6 time units (the ticking FMU's
clock stops the master at every tock anyway); the two results must agree on every row the
skipping run has. Prints both wall times and their ratio (target: >= 100x).

    python bench/bench_robochart_time.py [--quick]   # --quick: 10^5 time units
"""

from __future__ import annotations

import statistics
import sys
import tempfile
import time
from pathlib import Path

from robogen.codegen.api import build_fmu, compile_model
from robogen.cosim import simulate_system
from robogen.ir.lower import LoweringOptions

QUICK = "--quick" in sys.argv
UNITS = 100_000 if QUICK else 1_000_000

MODEL = f"""
package idler
interface Commands {{ event go }}
interface Reports {{ event ready  event gaveup }}
stm Idler {{
	uses Commands uses Reports
	initial i
	state Waiting {{ entry wait({UNITS * 2 // 5}) ; send ready }}
	state Done {{ entry send gaveup }}
	transition t0 {{ from i to Waiting }}
	transition t1 {{ from Waiting to Waiting trigger go }}
	transition t2 {{ from Waiting to Done condition sinceEntry(Waiting) >= {UNITS * 9 // 10} }}
}}
"""

SYSTEM = """
[experiment]
start = 0.0
stop = {stop}
step = {stop}

[instances.idler]
fmu = "{fmu}"
"""


def build(work: Path, time_option: str) -> Path:
    model = work / "idler.rct"
    model.write_text(MODEL, encoding="utf-8")
    compiled = compile_model([str(model)], work / f"src-{time_option}", machine="Idler",
                             options=LoweringOptions(time=time_option))
    fmu = build_fmu(compiled.folder, work / f"idler-{time_option}.fmu", model_identifier=compiled.generated.model_identifier)
    system = work / f"system-{time_option}.toml"
    system.write_text(SYSTEM.format(stop=float(UNITS), fmu=fmu.name), encoding="utf-8")
    return system


def run(system: Path, repeat: int):
    """The median wall time of ``repeat`` runs (after one that warms up: the master's C engine,
    the FMU's extraction cache), and the last run's results."""
    simulate_system(system)
    times = []
    for _ in range(repeat):
        started = time.perf_counter()
        result = simulate_system(system)
        times.append(time.perf_counter() - started)
    return statistics.median(times), result


def output_ticks(result) -> list[tuple[float, str]]:
    """(time, clock) of each output clock tick the run recorded."""
    clocks = [(i, c) for i, c in enumerate(result.columns) if c in ("idler.ready", "idler.gaveup")]
    return [(row[0], c) for row in result.rows for i, c in clocks if row[i] in (1, True)]


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        skip_system, tick_system = build(work, "skip"), build(work, "tick")
        skip_seconds, skipped = run(skip_system, 5)
        tick_seconds, ticked = run(tick_system, 1)
        ticks, shows = output_ticks(ticked), output_ticks(skipped)
        assert ticks == shows == [(UNITS * 2 // 5, "idler.ready"), (UNITS * 9 // 10, "idler.gaveup")], (ticks, shows)
        print(f"idle-waiting RoboChart controller, {UNITS:,} time units (outputs at t={UNITS * 2 // 5:,} and {UNITS * 9 // 10:,}):")
        print(f"  --time skip (nextEventTime): {skip_seconds:8.3f} s, {len(skipped.rows):,} rows (median of 5 runs)")
        print(f"  --time tick (tock clock):    {tick_seconds:8.3f} s, {len(ticked.rows):,} rows (1 run)")
        print(f"  ratio tick / skip: {tick_seconds / skip_seconds:,.0f}x (target >= 100x)")


if __name__ == "__main__":
    main()
