"""Benchmark of `robogen package --platforms`: the UR5e d-model packaged for all five platforms,
beside the host-only package of the same run (never asserted anywhere).

Prints, in seconds (medians of RUNS runs unless said):
  host only      package for x86_64-linux (system C compiler), the peer of the rows below;
  all, warm      package for the five platforms with zig's C libraries already built;
  each, warm     the host plus one other platform, one run each (what each platform adds);
  all, cold      one package for the five platforms with an empty zig cache (zig builds every
                 platform's C library first: minutes for Windows' mingw-w64), skipped by --no-cold.

The warm rows use zig's global cache (~/.cache/zig, or $ZIG_GLOBAL_CACHE_DIR), as users and CI
do; the cold row points ZIG_GLOBAL_CACHE_DIR at a fresh temporary folder, deleted afterwards.

    python bench/bench_platforms.py [--quick] [--no-cold]
"""

from __future__ import annotations

import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

from robogen.codegen.api import package_model
from robogen.fmu.platforms import BUILT, HOST

ROOT = Path(__file__).resolve().parent.parent
MODEL = ROOT / "models" / "ur5e" / "ur5e.rst"
RUNS = 1 if "--quick" in sys.argv else 3


def package_time(folder: Path, platforms) -> float:
    started = time.perf_counter()
    package_model([str(MODEL)], folder / "ur5e.fmu", platforms=platforms)
    return time.perf_counter() - started


def median_time(folder: Path, platforms, runs: int = RUNS) -> float:
    return statistics.median(package_time(folder, platforms) for _ in range(runs))


def main() -> int:
    with tempfile.TemporaryDirectory(prefix="robogen-bench-platforms-") as tmp:
        folder = Path(tmp)
        package_time(folder, BUILT)  # zig's cache warm for the warm rows
        host = median_time(folder, (HOST,))
        print(f"UR5e d-model, package (s)       host only {host:6.2f}")
        warm = median_time(folder, BUILT)
        print(f"  all five platforms, warm          {warm:6.2f}   x{warm / host:5.1f} of host only")
        for platform in BUILT[1:]:
            each = package_time(folder, (HOST, platform))
            print(f"  {HOST.name} + {platform.name:<15}      {each:6.2f}   x{each / host:5.1f}")
        if "--no-cold" in sys.argv:
            return 0
        with tempfile.TemporaryDirectory(prefix="robogen-zig-cold-") as cache:
            before = os.environ.get("ZIG_GLOBAL_CACHE_DIR")
            os.environ["ZIG_GLOBAL_CACHE_DIR"] = cache
            try:
                cold = package_time(folder, BUILT)
            finally:
                if before is None:
                    del os.environ["ZIG_GLOBAL_CACHE_DIR"]
                else:
                    os.environ["ZIG_GLOBAL_CACHE_DIR"] = before
        print(f"  all five platforms, cold (1 run)  {cold:6.2f}   x{cold / host:5.1f} of host only")
    return 0


if __name__ == "__main__":
    sys.exit(main())
