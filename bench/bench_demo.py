"""Benchmark of the UR5e co-simulation (`make demo`'s main run) against a bare PyBullet loop doing
the same physics, measured in the same run (interleaved, medians). Prints, never asserts.

- co-simulation: `robogen.cosim.simulate_system(models/ur5e/system.toml)` — controller FMU,
  generated d-model FMU, PyBullet platform FMU, 100 s, step 0.5 s, results streamed to a CSV;
  the wall time includes reading the system, loading the C FMU and instantiating the three FMUs.
  The two Python FMUs are extracted and loaded once per process (robogen.cosim.shared), by a
  first run before the measured ones, whose time is printed on its own.
- peer: one PyBullet client in this process, the same URDF, motors, physics step (1/240 s),
  the same 16 joint-space targets applied at the command times, joint states read every 0.5 s;
  the wall time includes connecting, loading the URDF and disconnecting. A call of stepSimulation
  a physics step, as the target (issue 12) was set against; printed beside it, the same loop
  with each 0.5 s of physics in one PyBullet call (robogen.platforms.scene.step_stretch, the
  same physics bit for bit), which is how the platform steps where it watches nothing.

A first co-simulation and a first bare loop warm up (the co-simulation's first run loads the
Python FMUs; both figures printed on their own), then REPEAT pairs, the order within a pair
alternating. Each run's wall time and CPU time of this process (``time.process_time``: the figure
that other processes on a loaded machine disturb least) are measured; the ratios are of the
medians, and each pair's ratio is printed too (the machine's speed drifts between pairs).

Then the cost of the Python FMUs' shim per FMI call: fmi3GetFloat64 of one value and an empty
fmi3DoStep through the same ctypes functions, on the platform FMU vs robogen's C test FMU
'ticker' (bench_platform.py's measurement, fewer calls).

Then the Python FMUs' calls inside one more co-simulation, per FMU and FMI function: how many,
the fastest and the median time (the slave's methods timed where the C engine calls them; the
FMUs run on this process's robogen modules). The fastest is a call with warm caches; the median
includes the first calls after each stretch of physics, which find the interpreter's data evicted.

Targets (issue 12): co-simulation / bare <= 1.2, and >= 100x faster than real time.

    python bench/bench_demo.py [--quick]
"""

from __future__ import annotations

import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

from bench_platform import joint_targets, per_call_figures, run_bare  # the same bare loop and per-call measurement

from robogen.cosim import simulate_system
from robogen.platforms.plan import load_plan
from robogen.platforms.urdf import ur5e_urdf
from robogen.pyfmu.slave import Slave

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # the UR5e example is repository code (examples/ur5e), not installed
from examples.ur5e.build import build_all  # noqa: E402

QUICK = "--quick" in sys.argv
REPEAT = 3 if QUICK else 11
STOP = 100.0


def main() -> int:
    with tempfile.TemporaryDirectory(prefix="robogen-bench-demo-") as tmp:
        folder = Path(tmp)
        print("== UR5e co-simulation vs a bare PyBullet loop (same run, interleaved)")
        t0 = time.perf_counter()
        built = build_all(folder / "fmus")
        print(f"  building the 5 FMUs: {time.perf_counter() - t0:.2f} s")
        system = built.systems["exhaustive"]
        urdf = folder / "ur5e.urdf"
        urdf.write_text(ur5e_urdf())
        commands = [(c.time, c.target) for c in load_plan(ROOT / "models" / "ur5e" / "plan.toml").events(until=STOP)]
        targets = joint_targets(commands)

        def cosim_run(i: int) -> tuple[float, float, object]:
            t0, c0 = time.perf_counter(), time.process_time()
            result = simulate_system(system, output=folder / f"results-{i}.csv", keep_rows=False)
            return time.perf_counter() - t0, time.process_time() - c0, result

        def bare_run(stretches: bool = False) -> tuple[float, float, int]:
            c0 = time.process_time()
            wall, steps = run_bare(urdf, targets, include_setup=True, stretches=stretches)
            return wall, time.process_time() - c0, steps

        first = cosim_run(-1)  # loads the Python FMUs (once per process); its own figure, not in the medians
        first_bare = bare_run()
        cosim, peer, cosim_cpu, peer_cpu, pairs, stretched = [], [], [], [], [], []
        for i in range(REPEAT):
            # one pair a repetition, the order alternating: a drift of the machine's speed during
            # a pair favours neither side; then the bare loop with stretches, the stronger peer
            if i % 2 == 0:
                wall, cpu, result = cosim_run(i)
                bare_wall, bare_cpu, steps = bare_run()
            else:
                bare_wall, bare_cpu, steps = bare_run()
                wall, cpu, result = cosim_run(i)
            stretched.append(bare_run(stretches=True)[0])
            cosim.append(wall)
            cosim_cpu.append(cpu)
            peer.append(bare_wall)
            peer_cpu.append(bare_cpu)
            pairs.append(wall / bare_wall)
        c, b = statistics.median(cosim), statistics.median(peer)
        c_cpu, b_cpu = statistics.median(cosim_cpu), statistics.median(peer_cpu)
        s = result.stats
        print(f"  co-simulation (3 FMUs, {s.steps} steps, {s.event_iterations} event iterations, {s.early_returns} early returns):"
              f" median {c:.3f} s wall, {c_cpu:.3f} s CPU of {REPEAT}  -> {STOP / c:.0f}x faster than real time")
        print(f"  bare PyBullet loop ({steps} physics steps):  median {b:.3f} s wall, {b_cpu:.3f} s CPU of {REPEAT}")
        print(f"  ratio co-simulation / bare: {c / b:.2f} wall, {c_cpu / b_cpu:.2f} CPU  (target <= 1.2)")
        print(f"  each pair's ratio: {', '.join(f'{x:.2f}' for x in sorted(pairs))} (median {statistics.median(pairs):.2f})")
        st = statistics.median(stretched)
        print(f"  the bare loop with each 0.5 s of physics in one PyBullet call (as the platform steps where it watches "
              f"nothing): median {st:.3f} s wall; co-simulation / that: {c / st:.2f}")
        print(f"  before the {REPEAT} pairs, the first co-simulation, which loads the Python FMUs: {first[0]:.3f} s wall, "
              f"{first[1]:.3f} s CPU; the first bare loop: {first_bare[0]:.3f} s wall")
        print(f"  load average: {', '.join(f'{x:.2f}' for x in os.getloadavg())}")
        print("== the Python FMUs' calls inside one co-simulation (fastest and median; the fastest has warm caches)")
        calls_inside(system, folder / "calls.csv")
        print("== the Python FMUs' shim per FMI call: platform FMU vs a C FMU (same ctypes calls, same run)")
        per_call_figures(built.folder / "platform.fmu", folder / "calls", 20_000)
    return 0


CALLS = ("set_clock", "get_clock", "get", "update_discrete_states", "enter_event_mode", "enter_step_mode", "do_step")


def calls_inside(system: Path, output: Path) -> None:
    """Time the slave's methods of both Python FMUs during one co-simulation (then restore them)."""
    times: dict[tuple[str, str], list[float]] = {}
    originals = {name: getattr(Slave, name) for name in CALLS}

    def timed(name, method):
        def call(self, *args):
            t0 = time.perf_counter()
            try:
                return method(self, *args)
            finally:
                times.setdefault((type(self.model).__name__, name), []).append(time.perf_counter() - t0)
        return call

    for name, method in originals.items():
        setattr(Slave, name, timed(name, method))
    try:
        simulate_system(system, output=output, keep_rows=False)
    finally:
        for name, method in originals.items():
            setattr(Slave, name, method)
    total = 0.0
    for (model, name), values in sorted(times.items()):
        total += sum(values) if name != "do_step" else 0.0
        print(f"  {model:15s} {name:24s} {len(values):5d} calls: fastest {min(values) * 1e6:7.2f} us, "
              f"median {statistics.median(values) * 1e6:7.2f} us")
    print(f"  every call but fmi3DoStep, in all: {total * 1e3:.1f} ms a run")


if __name__ == "__main__":
    sys.exit(main())
