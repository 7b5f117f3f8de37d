"""Benchmark of robogen's co-simulation master against its peers, run in the same process (fmpy)
or the same run (ECOS, in a process of its own).

Prints medians and ratios (never asserted anywhere), then the table of the targets of issue 12
(kept in docs/benchmarks.md with the machine it ran on):
  1. one FMI call (fmi3GetFloat64 of one value): robogen's cffi binding vs fmpy's FMU3Slave;
     and what noting each call for a crash report costs (robogen.cosim.crash)
  2. 1,000,000 communication steps of a trivial FMU: robogen.cosim vs fmpy.simulate_fmu
     (both record the one output at every step, in memory; event mode on in both); the memory a
     row of robogen's results takes (its arrays' bytes per row, and tracemalloc's count of what
     the run keeps and of its peak, per row) against the length of the row's CSV line
  3. the cost of one event iteration (a stair FMU with a time event at every step vs none), and
     of its flush when the rows go to a CSV file
  4. 1, 10, 100 and 1,000 chained FMUs, 1,000,000 FMU-steps each: the cost of one FMU-step
     (flat: linear growth is the target)
  5. isolation (robogen.cosim.proxy): one call through a worker process vs in process, a whole
     run isolated vs in process; the start of the crash watcher
  6. ECOS (bench extra, bench/ecos_peer.py): 100 chained trivial FMUs, 10,000 steps, every
     output to a CSV file and without recording; robogen in process, ECOS's program in its own;
     robogen also runs ECOS's SSP file of the chain, which must give its TOML twin's rows

    python bench/bench_master.py [--quick] [--only N,...]     (--only 2: figure 2 alone)
"""

from __future__ import annotations

import gc
import importlib.util
import os
import statistics
import sys
import tempfile
import time
import tracemalloc
from pathlib import Path

import fmpy
from fmpy.fmi3 import FMU3Slave

from robogen.cosim import simulate_system
from robogen.cosim.crash import watch_run
from robogen.cosim.fmi3 import Binding, CallNotes, Library, ffi, vr_array
from robogen.cosim.proxy import ProxyBinding
from robogen.cosim.recorder import Recorder

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ecos_peer import MIN_STEPS, Ecos, chain_ssp, chain_system  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
QUICK = "--quick" in sys.argv
#: The figures to run (--only 2,3): all by default.
ONLY = {int(n) for n in sys.argv[sys.argv.index("--only") + 1].split(",")} if "--only" in sys.argv else None
REPEAT = 3
#: The rows of the closing table: (figure, robogen, peer, ratio, target).
TABLE: list[tuple[str, str, str, str, str]] = []


def load_builder():
    spec = importlib.util.spec_from_file_location("robogen_test_fmus_build", ROOT / "tests" / "cosim" / "fmus" / "build.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def median_time(fn, repeat=REPEAT) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def system(folder: Path, name: str, text: str) -> Path:
    path = folder / f"{name}.toml"
    path.write_text(text)
    return path


def bench_calls(fmus: dict[str, Path], folder: Path) -> None:
    n = 20_000 if QUICK else 200_000
    unzipped = fmpy.extract(str(fmus["trivial"]), str(folder / "trivial-x"))
    md = fmpy.read_model_description(unzipped)
    so = str(Path(unzipped) / "binaries" / "x86_64-linux" / "trivial.so")
    # robogen
    inst = Binding(Library(so), "r")
    inst.fmi3InstantiateCoSimulation(md.instantiationToken, None, eventModeUsed=False)
    inst.fmi3EnterInitializationMode(None, 0.0, None)
    vrs, vals = vr_array([2]), ffi.new("double[1]")

    def ours():
        get = inst.fmi3GetFloat64
        for _ in range(n):
            get(vrs, 1, vals)

    # fmpy
    slave = FMU3Slave(guid=md.instantiationToken, unzipDirectory=unzipped, modelIdentifier="trivial", instanceName="f")
    slave.instantiate()
    slave.enterInitializationMode()

    def theirs():
        get = slave.getFloat64
        for _ in range(n):
            get([2])

    notes, code = CallNotes(), 7

    def noting():  # the store each call makes before it calls the FMU
        call = notes.call
        for _ in range(n):
            call[0] = code

    def empty():
        for _ in range(n):
            pass

    a, b = median_time(ours), median_time(theirs)
    note = median_time(noting) - median_time(empty)
    print(f"1. one fmi3GetFloat64 call: robogen {1e6 * a / n:.3f} us, fmpy FMU3Slave.getFloat64 {1e6 * b / n:.3f} us "
          f"-> robogen {b / a:.1f}x faster; noting the call for a crash report: {1e9 * note / n:.0f} ns "
          f"({100 * note / a:.1f}% of the call; in the engine one store)")
    inst.fmi3FreeInstance()
    slave.terminate()
    slave.freeInstance()


def bench_steps(fmus: dict[str, Path], folder: Path) -> None:
    steps = 100_000 if QUICK else 1_000_000
    h = 1.0 / steps
    path = system(folder, "trivial", f'[experiment]\nstop = 1.0\nstep = {h!r}\n[instances.t]\nfmu = "{fmus["trivial"]}"\n'
                                     '[record]\nvariables = ["t.y"]\n')
    results = {}

    def ours():
        results["ours"] = simulate_system(path)

    def theirs():
        results["theirs"] = fmpy.simulate_fmu(str(fmus["trivial"]), stop_time=1.0, output_interval=h, output=["y"],
                                              use_event_mode=True, early_return_allowed=False)

    def python_loop():  # the master's reference loop (as on a machine without a C compiler)
        saved = os.environ.get("ROBOGEN_REFERENCE_LOOP")
        os.environ["ROBOGEN_REFERENCE_LOOP"] = "1"
        try:
            results["python"] = simulate_system(path)
        finally:
            if saved is None:
                del os.environ["ROBOGEN_REFERENCE_LOOP"]
            else:
                os.environ["ROBOGEN_REFERENCE_LOOP"] = saved

    a, b, c = median_time(ours), median_time(theirs), median_time(python_loop)
    assert len(results["ours"].rows) >= steps and len(results["theirs"]) >= steps
    assert results["ours"].rows == results["python"].rows
    assert results["python"].stats.loop == "Python"
    print(f"2. {steps} steps of a trivial FMU: robogen ({results['ours'].stats.loop} engine) {a:.3f} s ({1e6 * a / steps:.2f} us/step), "
          f"fmpy.simulate_fmu {b:.3f} s ({1e6 * b / steps:.2f} us/step) -> robogen {b / a:.2f}x faster (target >= 30x); "
          f"robogen's Python loop {c:.3f} s ({1e6 * c / steps:.2f} us/step, {b / c:.2f}x fmpy)")
    TABLE.append((f"one trivial FMU, {steps:,} steps", f"{a:.2f} s", f"fmpy.simulate_fmu {b:.2f} s", f"{b / a:.1f}x faster",
                  ">= 30x"))
    bench_row_memory(path, folder, results["ours"])


def bench_row_memory(path: Path, folder: Path, result) -> None:
    """The memory of a row of results: the table's arrays, and what tracemalloc counts (the
    results kept after the run, and the peak during it, less what was allocated before), per row,
    against the length of the same row's line in the CSV file."""
    rows = len(result.table)
    arrays = result.table.nbytes / rows
    del result
    gc.collect()
    tracemalloc.start()
    before = tracemalloc.get_traced_memory()[0]
    kept = simulate_system(path)
    after, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    del kept
    csv = folder / "trivial.csv"
    simulate_system(path, output=csv, keep_rows=False)
    with open(csv, "rb") as f:
        f.readline()  # the header
        line = (csv.stat().st_size - f.tell()) / rows
    csv.unlink()
    print(f"   memory per row of results ({rows:,} rows: time, superdense, t.y): arrays {arrays:.1f} bytes, "
          f"tracemalloc {(after - before) / rows:.1f} bytes kept, peak {(peak - before) / rows:.1f} bytes; "
          f"its CSV line {line:.1f} bytes (target: no larger than the CSV line)")
    TABLE.append(("memory per row of results (one trivial FMU)", f"{(after - before) / rows:.1f} bytes (peak {(peak - before) / rows:.1f})",
                  f"CSV line {line:.1f} bytes", f"{line / ((after - before) / rows):.2f}x smaller", "<= the CSV line"))


def bench_events(fmus: dict[str, Path], folder: Path) -> None:
    """The stair FMU with a time event (nextEventTime) at every step against the same FMU whose
    first event comes after the stop time, rows kept in memory: the difference per event iteration.
    The plain step is the quiet run's time less that of a 10-step run (loading and instantiating),
    per step. Also: the same with the rows going nowhere (the loop's own cost), to a CSV file
    (flushed after every event iteration), and the Python loop (ROBOGEN_REFERENCE_LOOP=1)."""
    steps = 2_000 if QUICK else 20_000
    template = '[experiment]\nstop = {stop}\nstep = 0.1\n[instances.s]\nfmu = "{fmu}"\nstart = {{ period = {period} }}\n'
    every = system(folder, "stair-events", template.format(stop=steps * 0.1, fmu=fmus["stair"], period=0.1))
    never = system(folder, "stair-quiet", template.format(stop=steps * 0.1, fmu=fmus["stair"], period=10 * steps * 0.1))
    short = system(folder, "stair-short", template.format(stop=10 * 0.1, fmu=fmus["stair"], period=10 * steps * 0.1))
    figures = {}
    for label, kwargs, python in (("kept", {}, False), ("nowhere", {"keep_rows": False}, False),
                                  ("CSV", {"keep_rows": False, "output": folder / "events.csv"}, False),
                                  ("Python loop", {}, True)):
        runs = {}
        saved = os.environ.pop("ROBOGEN_REFERENCE_LOOP", None)
        if python:
            os.environ["ROBOGEN_REFERENCE_LOOP"] = "1"
        try:
            a = median_time(lambda: runs.__setitem__("a", simulate_system(every, **kwargs)), repeat=5)
            b = median_time(lambda: runs.__setitem__("b", simulate_system(never, **kwargs)), repeat=5)
            b0 = median_time(lambda: simulate_system(short, **kwargs), repeat=5)
        finally:
            os.environ.pop("ROBOGEN_REFERENCE_LOOP", None)
            if saved is not None:
                os.environ["ROBOGEN_REFERENCE_LOOP"] = saved
        assert runs["a"].stats.loop == ("Python" if python else "C") or python
        n_events = runs["a"].stats.event_iterations - runs["b"].stats.event_iterations
        figures[label] = ((a - b) / n_events, (b - b0) / (steps - 10), n_events)
    event, plain, n_events = figures["kept"]
    others = "; ".join(f"{label}: {1e6 * e:.2f} us over {1e6 * p:.2f} us" for label, (e, p, _n) in figures.items() if label != "kept")
    flush = _flush_cost(folder / "flushes.csv")
    print(f"3. one event iteration (Enter Event Mode, one instant, update, record 2 rows, Enter Step Mode), rows kept: "
          f"{1e6 * event:.2f} us over a plain step ({n_events} event iterations; {1e6 * plain:.2f} us per plain step, "
          f"the cost of 10 steps subtracted); rows {others}; a flush of the CSV file (2 rows): {1e6 * flush:.1f} us")
    TABLE.append(("one event iteration over a plain step (C FMU)", f"{1e6 * event:.2f} us",
                  f"plain step {1e6 * plain:.2f} us", f"Python loop: {1e6 * figures['Python loop'][0]:.1f} us over "
                  f"{1e6 * figures['Python loop'][1]:.1f} us", "<= 3 us"))


def _flush_cost(path: Path) -> float:
    """Seconds per flush of two freshly written rows (what the master adds to an event iteration)."""
    n = 2_000 if QUICK else 20_000
    row = [0.5, 0, 1.25, 3, True]

    def rows(flushing: bool):
        recorder = Recorder(["a", "b", "c"], path, None, keep_rows=False)
        for _ in range(n):
            recorder.append_row(row)
            recorder.append_row(row)
            if flushing:
                recorder.flush()
        recorder.close()

    return (median_time(lambda: rows(True), repeat=5) - median_time(lambda: rows(False), repeat=5)) / n


def bench_scaling(fmus: dict[str, Path], folder: Path) -> None:
    """The cost of one FMU-step of a chain of n trivial FMUs, rows to a CSV file: the time of as
    many steps as make the same number of FMU-steps for every n, less that of 10 steps (loading
    and instantiating the FMUs), per step and FMU."""
    fmu_steps = 100_000 if QUICK else 1_000_000
    per_fmu_step = {}
    for n in (1, 10, 100, 1000):
        steps, runs = max(fmu_steps // n, 500), {}
        for count in (10, steps):
            path = system(folder, f"chain{n}-{count}", chain_system(fmus["trivial"], n, count * 0.01, 0.01))
            runs[count] = median_time(lambda: simulate_system(path, keep_rows=False, output=folder / f"chain{n}.csv"))
        per_fmu_step[n] = (runs[steps] - runs[10]) / ((steps - 10) * n)
    base = per_fmu_step[10]
    line = ", ".join(f"{n} FMUs {1e6 * c:.3f} us ({c / base:.2f}x)" for n, c in per_fmu_step.items())
    print(f"4. one FMU-step of a chain of trivial FMUs ({fmu_steps:,} FMU-steps or 500 steps, CSV to disk, the cost of 10 steps "
          f"subtracted; x: against 10 FMUs): {line}")
    TABLE.append(("cost per FMU-step, 1 / 10 / 100 / 1,000 chained FMUs (CSV)",
                  " / ".join(f"{1e6 * c:.3f}" for c in per_fmu_step.values()) + " us",
                  "", f"1,000 vs 10: {per_fmu_step[1000] / base:.2f}x", "linear (flat per FMU-step)"))


def bench_isolation(fmus: dict[str, Path], folder: Path) -> None:
    n = 2_000 if QUICK else 20_000
    unzipped = fmpy.extract(str(fmus["trivial"]), str(folder / "trivial-i"))
    md = fmpy.read_model_description(unzipped)
    so = str(Path(unzipped) / "binaries" / "x86_64-linux" / "trivial.so")
    here, there = Binding(Library(so), "here"), ProxyBinding(so, "there")
    for b in (here, there):
        b.fmi3InstantiateCoSimulation(md.instantiationToken, None)
        b.fmi3EnterInitializationMode(None, 0.0, None)
    vrs = [2]

    def calls(binding):
        get = binding.get_values
        for _ in range(n):
            get("Float64", vrs)

    a, b = median_time(lambda: calls(here)), median_time(lambda: calls(there))
    for x in (here, there):
        x.fmi3FreeInstance()
    there.close()
    steps = 2_000 if QUICK else 20_000
    path = system(folder, "isolated", f'[experiment]\nstop = {steps * 0.001}\nstep = 0.001\n'
                                      f'[instances.t]\nfmu = "{fmus["trivial"]}"\n')
    general = median_time(lambda: simulate_system(path, trace=lambda line: None))  # in process, general loop
    isolated = median_time(lambda: simulate_system(path, isolate=True))
    start = median_time(lambda: watch_run(True).close())
    print(f"5. isolation: one fmi3GetFloat64 through a worker process {1e6 * b / n:.1f} us vs {1e6 * a / n:.2f} us "
          f"in process ({b / a:.0f}x); {steps} steps of a trivial FMU isolated {isolated:.3f} s "
          f"({1e6 * isolated / steps:.1f} us/step) vs {general:.3f} s in process in the same (general) loop "
          f"({isolated / general:.1f}x); the crash watcher starts and stops in {1e3 * start:.1f} ms")


def bench_ecos(fmus: dict[str, Path], folder: Path) -> None:
    n, steps, h = 100, (1_000 if QUICK else 10_000), 0.01
    ssp = chain_ssp(fmus["trivial"], n, folder / "chain.ssp")
    paths = {count: system(folder, f"ecos-chain-{count}", chain_system(fmus["trivial"], n, count * h, h))
             for count in (MIN_STEPS, steps)}
    # robogen reads the SSP 1.0 file ECOS runs (docs/ssp.md): the same rows as from its TOML twin
    same = simulate_system(ssp, stop=MIN_STEPS * h, step=h).rows == simulate_system(paths[MIN_STEPS]).rows
    assert same, "robogen's run of chain.ssp differs from its run of the TOML twin"
    print("6. robogen simulate chain.ssp (the SSP 1.0 file ECOS runs): rows identical to its TOML twin's")
    ecos = Ecos.find(folder)
    if isinstance(ecos, str):
        print(f"6. ECOS: not measured: {ecos}")
        return
    results = {}

    def ours(count: int, csv: bool) -> float:
        out = folder / "robogen-chain.csv" if csv else None
        t0 = time.perf_counter()
        results["ours"] = simulate_system(paths[count], output=out, keep_rows=False)
        return time.perf_counter() - t0

    def theirs(count: int, csv: bool) -> tuple[float, float]:
        run = folder / "ecos-run"
        return (ecos.simulate(ssp, count * h, h, csv, run), ecos.simulate(ssp, count * h, h, csv, run, parallel=False))

    times, modes = {}, {}
    for csv in (True, False):
        medians = {}
        for count in (MIN_STEPS, steps):  # interleaved, so that the machine's load falls on both alike
            runs = [(ours(count, csv), *theirs(count, csv)) for _ in range(REPEAT)]
            medians[count] = [statistics.median(run[i] for run in runs) for i in range(3)]
        # ECOS's faster mode over the whole run is the peer: on a shared machine its threads may wait for a core
        mode = 1 if medians[steps][1] <= medians[steps][2] else 2
        modes[csv] = "parallel" if mode == 1 else "--noParallel"
        for count in (MIN_STEPS, steps):
            times[csv, count] = (medians[count][0], medians[count][mode])
        assert results["ours"].stats.loop == "C" and results["ours"].stats.steps == steps
    fmu_steps = n * (steps - MIN_STEPS)
    for csv, label in ((True, "every output to CSV"), (False, "no recording")):
        (r, e), (r0, e0) = times[csv, steps], times[csv, MIN_STEPS]
        r_step, e_step = (r - r0) / fmu_steps, (e - e0) / fmu_steps
        print(f"6. ECOS ({ecos.version()}), {n} chained trivial FMUs, {steps} steps, {label}: robogen {r:.3f} s, "
              f"ECOS ({modes[csv]}) {e:.3f} s -> robogen {e / r:.2f}x ECOS's speed; per FMU-step (the cost of {MIN_STEPS} steps "
              f"subtracted) robogen {1e6 * r_step:.3f} us, ECOS {1e6 * e_step:.3f} us ({e_step / r_step:.2f}x)")
        target = ">= 1.0x ECOS's speed" if csv else "within 2x of ECOS's time (>= 0.5x its speed)"
        TABLE.append((f"{n} chained trivial FMUs, {steps:,} steps, {label}", f"{r:.2f} s ({1e6 * r_step:.3f} us/FMU-step)",
                      f"ECOS {e:.2f} s ({1e6 * e_step:.3f} us/FMU-step)", f"{e / r:.2f}x ECOS's speed", target))


def print_table() -> None:
    cpu = next((line.split(":", 1)[1].strip() for line in Path("/proc/cpuinfo").read_text().splitlines()
                if line.startswith("model name")), "?") if Path("/proc/cpuinfo").exists() else "?"
    print(f"\nmachine: {os.cpu_count()} CPUs ({cpu}); load average {os.getloadavg()[0]:.1f} at the end; medians of {REPEAT}")
    print("| figure | robogen | peer | ratio | target |\n| --- | --- | --- | --- | --- |")
    for row in TABLE:
        print("| " + " | ".join(row) + " |")


def main() -> None:
    builder = load_builder()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        fmus = builder.build_all(folder / "fmus", ["trivial", "stair"])
        print(f"robogen master benchmark ({'quick' if QUICK else 'full'}; medians of {REPEAT} runs; fmpy {fmpy.__version__})")
        for n, bench in enumerate((bench_calls, bench_steps, bench_events, bench_scaling, bench_isolation, bench_ecos), 1):
            if ONLY is None or n in ONLY:
                bench(fmus, folder)
        print_table()


if __name__ == "__main__":
    main()
