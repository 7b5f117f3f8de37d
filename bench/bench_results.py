"""Benchmark of results for large runs (issue 12): a run of one trivial FMU recorded to Parquet,
1,000,000 and 10,000,000 rows, each in a process of its own, against the same runs recorded to CSV
(a stream, bounded by design) in the same script. Prints, never asserts:

  rows, seconds, file size, and the process's peak resident memory (ru_maxrss of the child);
  the growth of the peak from 1 M to 10 M rows, for Parquet and for CSV.

Bounded memory: ten times the rows must not mean ten times the memory (rows held in Python would
cost ~100 bytes each, ~900 MB more for the 9 M more rows).

    python bench/bench_results.py [--quick]     (--quick: 100,000 and 1,000,000 rows)
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
from pathlib import Path

from bench_master import load_builder, system

QUICK = "--quick" in sys.argv
SIZES = (100_000, 1_000_000) if QUICK else (1_000_000, 10_000_000)

CHILD = """
import json, resource, sys, time
from robogen.cosim import simulate_system
t0 = time.perf_counter()
simulate_system(sys.argv[1], output=sys.argv[2], keep_rows=False)
print(json.dumps({"seconds": time.perf_counter() - t0, "peak_kb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss}))
"""


def run(toml: Path, output: Path) -> dict:
    done = subprocess.run([sys.executable, "-c", CHILD, str(toml), str(output)], capture_output=True, text=True, check=True)
    figures = json.loads(done.stdout.strip().splitlines()[-1])
    figures["bytes"] = output.stat().st_size
    output.unlink()
    return figures


def main() -> int:
    with tempfile.TemporaryDirectory(prefix="robogen-bench-results-") as tmp:
        folder = Path(tmp)
        fmus = load_builder().build_all(folder / "fmus")
        print("== results for large runs: one trivial FMU, a row per step, each run in a process of its own")
        peaks: dict[str, list[int]] = {"parquet": [], "csv": []}
        for rows in SIZES:
            stop = rows * 0.001
            toml = system(folder, f"long{rows}", f'[experiment]\nstop = {stop!r}\nstep = 0.001\n'
                                                 f'[instances.a]\nfmu = "{fmus["trivial"]}"\n')
            for kind in ("parquet", "csv"):
                f = run(toml, folder / f"results.{kind}")
                peaks[kind].append(f["peak_kb"])
                print(f"  {rows:>11,} rows to {kind:<7}: {f['seconds']:6.2f} s, {f['bytes'] / 1e6:7.1f} MB written, "
                      f"peak memory {f['peak_kb'] / 1024:6.1f} MB")
        times = SIZES[1] // SIZES[0]
        for kind, (small, large) in peaks.items():
            print(f"  {kind}: {times}x the rows, peak memory {large / small:.2f}x ({(large - small) / 1024:+.1f} MB)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
