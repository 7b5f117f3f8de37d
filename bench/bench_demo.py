"""Benchmark of the UR5e co-simulation (`make demo`'s main run) against a bare PyBullet loop doing
the same physics, measured in the same run (interleaved, medians). Prints, never asserts.

- co-simulation: `robogen.cosim.simulate_system(models/ur5e/system.toml)` — controller FMU,
  generated d-model FMU, PyBullet platform FMU, 100 s, step 0.5 s, results streamed to a CSV;
  the wall time includes loading and instantiating the three FMUs.
- peer: one PyBullet client in this process, the same URDF, motors, physics step (1/240 s),
  the same 16 joint-space targets applied at the command times, joint states read every 0.5 s;
  the wall time includes connecting and loading the URDF.

Targets: co-simulation / bare <= 1.5, and >= 100x faster than real time.

    python bench/bench_demo.py [--quick]
"""

from __future__ import annotations

import statistics
import sys
import tempfile
import time
from pathlib import Path

from bench_platform import joint_targets, run_bare  # the same bare loop as the platform benchmark

from robogen.cosim import simulate_system
from robogen.platforms.plan import load_plan
from robogen.platforms.urdf import ur5e_urdf

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # the UR5e example is repository code (examples/ur5e), not installed
from examples.ur5e.build import build_all  # noqa: E402

QUICK = "--quick" in sys.argv
REPEAT = 3 if QUICK else 7
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
        cosim, peer = [], []
        for i in range(REPEAT):
            t0 = time.perf_counter()
            result = simulate_system(system, output=folder / f"results-{i}.csv", keep_rows=False)
            cosim.append(time.perf_counter() - t0)
            wall, steps = run_bare(urdf, targets, include_setup=True)
            peer.append(wall)
        c, b = statistics.median(cosim), statistics.median(peer)
        s = result.stats
        print(f"  co-simulation (3 FMUs, {s.steps} steps, {s.event_iterations} event iterations, {s.early_returns} early returns):"
              f" median {c:.3f} s of {REPEAT}  -> {STOP / c:.0f}x faster than real time")
        print(f"  bare PyBullet loop ({steps} physics steps):  median {b:.3f} s of {REPEAT}")
        print(f"  ratio co-simulation / bare: {c / b:.2f}  (target <= 1.5)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
