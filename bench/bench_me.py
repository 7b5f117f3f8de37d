"""Benchmark of a Model Exchange FMU integrated by robogen's master (CVode through SUNDIALS' C API,
in the adapter: robogen.cosim.interfaces) against fmpy.simulate_fmu (the same CVode, driven from
Python), in the same run, at the same tolerance.

The FMU: the Van der Pol oscillator (tests/cosim/fmus/vdp.c, FMI 2.0 Model Exchange, mu = 1),
100 s, relative tolerance 1e-6 in both, the states recorded every 0.1 s (1,001 rows) and every
0.01 s (10,001 rows; fmpy's output interval is its communication step, as robogen's step is).
Prints, per output interval, the median of REPEAT runs of each (the whole run: loading the FMU,
setting up, integrating, recording), the ratio (the target of issue 19: at least 5), and how far apart
the results are: the largest difference between the two, and each one's largest distance from a
run at rtol 1e-10 (the results must agree within 1e-3, the bound tests/cosim/test_interfaces.py
states for CVode at rtol 1e-6).

    python bench/bench_me.py
"""

from __future__ import annotations

import importlib.util
import statistics
import sys
import tempfile
import time
from pathlib import Path

import fmpy

from robogen.cosim import simulate_system

ROOT = Path(__file__).resolve().parent.parent
REPEAT = 7
STOP, RTOL, MU = 100.0, 1e-6, 1.0


def builder():
    spec = importlib.util.spec_from_file_location("robogen_test_fmus_others", ROOT / "tests" / "cosim" / "fmus" / "others.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def median_time(fn) -> tuple[float, object]:
    times, result = [], None
    for _ in range(REPEAT):
        start = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times), result


def compare(fmu: Path, tmp: Path, step: float, mu: float = MU) -> None:
    system = tmp / f"vdp-{step:g}.toml"
    system.write_text(f'[experiment]\nstop = {STOP}\nstep = {step}\ntolerance = {RTOL}\n[instances.p]\nfmu = "{fmu}"\n'
                      f"start = {{ mu = {mu!r} }}\n")
    tight = tmp / f"tight-{step:g}.toml"
    tight.write_text(system.read_text().replace(f"tolerance = {RTOL}", "tolerance = 1e-10"))
    ours_time, ours = median_time(lambda: simulate_system(system))
    peer_time, peer = median_time(lambda: fmpy.simulate_fmu(str(fmu), stop_time=STOP, output_interval=step,
                                                              relative_tolerance=RTOL, solver="CVode", validate=False,
                                                              start_values={"mu": mu}))
    exact = {round(r[0], 9): r[2:] for r in simulate_system(tight).rows}
    mine = {round(r[0], 9): r[2:] for r in ours.rows}
    theirs = {round(float(r["time"]), 9): (float(r["x0"]), float(r["x1"])) for r in peer}
    common = sorted(set(mine) & set(theirs) & set(exact))
    apart = max(abs(a - b) for t in common for a, b in zip(mine[t], theirs[t]))
    ours_error = max(abs(a - b) for t in common for a, b in zip(mine[t], exact[t]))
    peer_error = max(abs(a - b) for t in common for a, b in zip(theirs[t], exact[t]))
    print(f"Van der Pol, mu = {mu:g}, FMI 2.0 Model Exchange, {STOP:g} s every {step:g} s, {len(common)} points compared, "
          f"CVode rtol {RTOL:g}, median of {REPEAT}")
    print(f"  robogen (CVode in C, the adapter)   {ours_time * 1e3:8.1f} ms   ({ours.stats.loop} loop)")
    print(f"  fmpy.simulate_fmu (CVode)           {peer_time * 1e3:8.1f} ms")
    print(f"  ratio fmpy / robogen                {peer_time / ours_time:8.1f}x   (target: >= 5)")
    print(f"  largest difference robogen - fmpy   {apart:.2e}   (within 1e-3: {'yes' if apart <= 1e-3 else 'NO'})")
    print(f"  largest error against rtol 1e-10    robogen {ours_error:.2e}, fmpy {peer_error:.2e}")


def main() -> int:
    with tempfile.TemporaryDirectory() as tmp:
        fmu = builder().build("vdp2", Path(tmp))
        for step in (0.1, 0.01):
            compare(fmu, Path(tmp), step)
    return 0


if __name__ == "__main__":
    sys.exit(main())
