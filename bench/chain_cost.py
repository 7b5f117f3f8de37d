"""The cost of one FMU-step of a chain of trivial FMUs, CSV to disk (bench_master.py's figure 4),
with the robogen found at --src, so that two checkouts can be run alternately in the same
minutes (a figure without a peer moves with the machine from one run to the next).

    python bench/chain_cost.py [--src OTHER_CHECKOUT/src] [--fmu trivial.fmu]

The trivial FMU is built by this checkout's test builder (tests/cosim/fmus/build.py) unless
--fmu names one. Prints one line: the cost per FMU-step for 1, 10, 100 and 1,000 FMUs (the time
of 1,000,000 FMU-steps, or of 500 steps, less that of 10 steps; medians of 3).
"""

from __future__ import annotations

import argparse
import importlib.util
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def chain_system(fmu: Path, n: int, stop: float, step: float) -> str:
    text = "connections = [\n" + "".join(f'  "t{i}.y -> t{i + 1}.u",\n' for i in range(n - 1)) + "]\n"
    text += f"[experiment]\nstop = {stop!r}\nstep = {step!r}\n"
    return text + "".join(f'[instances.t{i}]\nfmu = "{fmu}"\n' for i in range(n))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--src", type=Path, help="a robogen source folder to run instead of the installed one")
    parser.add_argument("--fmu", type=Path, help="the trivial FMU (default: built by this checkout's test builder)")
    args = parser.parse_args()
    if args.src is not None:
        sys.path.insert(0, str(args.src.resolve()))
    from robogen.cosim import simulate_system  # the robogen of --src, when given

    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        fmu = args.fmu
        if fmu is None:
            spec = importlib.util.spec_from_file_location("robogen_test_fmus_build", ROOT / "tests" / "cosim" / "fmus" / "build.py")
            builder = importlib.util.module_from_spec(spec)
            spec.loader.exec_module(builder)
            fmu = builder.build_all(folder / "fmus", ["trivial"])["trivial"]
        costs = {}
        for n in (1, 10, 100, 1000):
            steps, runs = max(1_000_000 // n, 500), {}
            for count in (10, steps):
                path = folder / f"chain{n}-{count}.toml"
                path.write_text(chain_system(fmu, n, count * 0.01, 0.01))
                times = []
                for _ in range(3):
                    t0 = time.perf_counter()
                    simulate_system(path, keep_rows=False, output=folder / f"chain{n}.csv")
                    times.append(time.perf_counter() - t0)
                runs[count] = statistics.median(times)
            costs[n] = (runs[steps] - runs[10]) / ((steps - 10) * n)
    import robogen

    print(f"{Path(robogen.__file__).parent}: " + " / ".join(f"{1e6 * c:.3f}" for c in costs.values())
          + " us per FMU-step (1 / 10 / 100 / 1,000 FMUs)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
