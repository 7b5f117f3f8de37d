"""Benchmark of `robogen campaign` on this machine, against peers measured in the same run.

32 UR5e runs (the reachability campaign of examples/ur5e/campaign.toml on 32 cells: X 0, 5, 10, 15
x Y 0, 6, 12, 15, 18, 20, 22, 23 at Z = 1; each a 5 s co-simulation of the three FMUs with one
move command), built from scratch into a temporary folder. Prints (never asserted anywhere):

  1. throughput: the campaign on a local cluster of 2 workers against 1 worker (from the workers
     being ready to the last result; cluster start-up apart, printed too). Target: >= 1.7x on
     2 cores.
  2. per-run overhead: the median time per run inside the 1-worker campaign (its wall-time column:
     fork of the warm zygote, derived FMU and system file, simulation, metrics, result back) and
     the campaign's whole execution per run (Dask dispatch and the journal included), against the
     same runs done
       a. by a plain `robogen simulate SYSTEM.toml` each (a new process per run, as a user would),
       b. by `simulate_system()` in this (warm) process, the bare cost of the simulation,
       c. the same with the FMUs unpacked where a campaign's run unpacks them (/dev/shm when the
          machine has it): what remains is the cost of the isolation and of Dask.
     Target: <= 10 % over (a).

    python bench/bench_campaign.py [--quick]     (--quick: 8 runs for the overhead peers)
"""

from __future__ import annotations

import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from robogen.campaign.worker import scratch_root

ROOT = Path(__file__).resolve().parent.parent
QUICK = "--quick" in sys.argv
REPEATS = 1 if QUICK else 3  # campaigns of each size; the median is printed
PEER_EVERY = 4 if QUICK else 1  # the peers redo every run of the campaign, or every 4th
PRELOAD = '["robogen.platforms.ur5e", "robogen.platforms.controller"]'


def robogen(*args: str) -> None:
    subprocess.run([sys.executable, "-m", "robogen", *args], check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)


def build(folder: Path) -> Path:
    """The three FMUs and a system file using them; returns the campaign file."""
    models = ROOT / "models" / "ur5e"
    robogen("package", str(models / "ur5e.rst"), "--time-unit", "0.5", "-o", str(folder / "dmodel.fmu"))
    robogen("package-py", "robogen.platforms.ur5e:UR5ePlatform", "--set", "sample_period=0.5",
            "-o", str(folder / "platform.fmu"))
    robogen("package-py", "robogen.platforms.controller:PlanController", "--set", f"plan={models / 'plan.toml'}",
            "-o", str(folder / "controller.fmu"))
    system = (models / "system.toml").read_text(encoding="utf-8").replace("../../build/ur5e/", "")
    (folder / "system.toml").write_text(system, encoding="utf-8")
    shutil.copy(ROOT / "examples" / "ur5e" / "one-command-plan.toml", folder)
    shutil.copy(ROOT / "examples" / "ur5e" / "campaign_metrics.py", folder)
    campaign = folder / "campaign.toml"
    campaign.write_text(f"""title = "bench: 32 UR5e runs"
system = "system.toml"
stop = 5.0
preload = {PRELOAD}
[grid]
X = [0, 5, 10, 15]
Y = [0, 6, 12, 15, 18, 20, 22, 23]
Z = [1]
[files]
"controller.resources/plan.toml" = {{ template = "one-command-plan.toml" }}
[metrics]
reach = "campaign_metrics:reach"
settle_time = {{ first_tick = "platform.moveCompleted", since = "controller.moveDiscreteCommand" }}
""", encoding="utf-8")
    return campaign


def campaign_run(campaign: Path, out: Path, workers: int):
    """The campaign on a local cluster of ``workers``: (result, seconds end to end, runs table,
    when each run's result reached the client, in seconds from the execution's start)."""
    import pyarrow.parquet as pq

    from robogen.campaign import engine, run_campaign

    arrived: dict[str, float] = {}
    original = engine.execute

    def timed(plan, todo, client, *, retries, record, progress):
        def stamped(run, row):
            arrived[run.id] = time.monotonic()
            record(run, row)

        try:
            return original(plan, todo, client, retries=retries, record=stamped, progress=progress)
        finally:
            for key in arrived:
                arrived[key] -= progress.started

    engine.execute = timed
    try:
        t0 = time.perf_counter()
        result = run_campaign(campaign, out, workers=workers, progress=False, echo=lambda line: None)
        total = time.perf_counter() - t0
    finally:
        engine.execute = original
    table = pq.read_table(out / "runs.parquet")
    assert result.counts == {"ok": 32}, result.counts
    return result, total, table, arrived


def breakdown(result, table, arrived: dict[str, float]) -> list[str]:
    """Where each worker's share of the execution went: its runs (their wall_time: fork to the
    result back in the worker), the wait for its first result beyond that run's own time
    (scatter, dispatch), the warming of its zygote before its second run (with one dispatch),
    the dispatch between its later runs, and its idle tail after its last result."""
    lines = []
    rows = sorted(zip(table.column("worker").to_pylist(), table.column("id").to_pylist(),
                      table.column("wall_time").to_pylist()), key=lambda r: arrived[r[1]])
    for n, worker in enumerate(sorted({r[0] for r in rows}), 1):
        times = [(arrived[i], wall) for w, i, wall in rows if w == worker]
        gaps = [t - before - wall for (before, _), (t, wall) in zip(times, times[1:])]
        later = gaps[1:]
        lines.append(f"   worker {n}: {len(times)} runs {sum(w for _, w in times):5.2f} s; first result "
                     f"+{times[0][0] - times[0][1]:.2f} s; warming before the second {gaps[0] if gaps else 0:.2f} s; "
                     f"dispatch between the others {sum(later):.2f} s "
                     f"({1000 * statistics.median(later) if later else 0:.0f} ms median); "
                     f"tail {result.execution - times[-1][0]:.2f} s")
    return lines


def peer_systems(campaign: Path, folder: Path) -> dict[str, Path]:
    """Run id -> the derived system file of that run (every PEER_EVERY-th), as a worker writes it."""
    from robogen.campaign.child import derived_fmu, derived_system
    from robogen.campaign.plan import make_plan
    from robogen.campaign.spec import load_campaign

    plan = make_plan(load_campaign(campaign))
    systems = {}
    for run in plan.runs[::PEER_EVERY]:
        run_folder = folder / run.id
        run_folder.mkdir(parents=True)
        fmus = {i: plan.fmu_files[d].resolve() for i, d in run.spec.fmus.items()}
        for instance, replaced in run.spec.resources.items():
            fmus[instance] = derived_fmu(fmus[instance], replaced, run_folder / f"{instance}.fmu")
        path = run_folder / "system.toml"
        path.write_text(derived_system(plan.context, fmus, run.spec.start), encoding="utf-8")
        systems[run.id] = path
    return systems


def time_cli(systems: list[Path]) -> list[float]:
    times = []
    for system in systems:
        t0 = time.perf_counter()
        robogen("simulate", str(system), "--stop", "5", "-o", os.devnull, "--no-progress")
        times.append(time.perf_counter() - t0)
    return times


def time_in_process(systems: list[Path], scratch: Path | None = None) -> list[float]:
    """simulate_system() of each system in this process; with ``scratch``, the master unpacks
    the FMUs there (as a campaign's run does, in the worker's folder)."""
    from robogen.cosim import simulate_system

    saved = tempfile.tempdir
    tempfile.tempdir = str(scratch) if scratch else saved
    try:
        simulate_system(systems[0], stop=5.0, keep_rows=True)  # imports and first-use costs
        times = []
        for system in systems:
            t0 = time.perf_counter()
            simulate_system(system, stop=5.0, keep_rows=True)
            times.append(time.perf_counter() - t0)
        return times
    finally:
        tempfile.tempdir = saved


def main() -> int:
    with tempfile.TemporaryDirectory(prefix="robogen-bench-campaign-") as tmp:
        folder = Path(tmp)
        t0 = time.perf_counter()
        campaign = build(folder)
        print(f"built 3 FMUs and the 32-run campaign in {time.perf_counter() - t0:.1f} s; load average "
              f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
        ones, twos = [], []
        for i in range(REPEATS):  # alternated, so that a change of the machine's load hits both alike
            ones.append(campaign_run(campaign, folder / f"one-{i}", 1))
            twos.append(campaign_run(campaign, folder / f"two-{i}", 2))
        one, one_total, table1, arrived1 = sorted(ones, key=lambda r: r[0].execution)[len(ones) // 2]
        two, two_total, table2, arrived2 = sorted(twos, key=lambda r: r[0].execution)[len(twos) // 2]
        same = table1.drop_columns(["wall_time", "worker"]).equals(table2.drop_columns(["wall_time", "worker"]))
        print(f"1. throughput, 32 runs, median of {REPEATS} (workers ready -> last result; end to end with cluster "
              "start in brackets)")
        print(f"   1 worker : {one.execution:6.2f} s  ({one_total:.2f} s)  {32 / one.execution:.2f} runs/s")
        print(f"   2 workers: {two.execution:6.2f} s  ({two_total:.2f} s)  {32 / two.execution:.2f} runs/s")
        print(f"   speedup 2 vs 1 worker: {one.execution / two.execution:.2f}x (target >= 1.7x); "
              f"end to end {one_total / two_total:.2f}x; tables identical apart from wall_time/worker: {same}")
        slower = statistics.median(table2.column("wall_time").to_pylist()) / statistics.median(table1.column("wall_time").to_pylist())
        print(f"   a run takes {slower:.2f}x as long on a worker when two run at once (load average now "
              f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)")
        print("   where the execution went (the median campaigns):")
        print("\n".join(["   1 worker:"] + breakdown(one, table1, arrived1) + ["   2 workers:"] + breakdown(two, table2, arrived2)))
        systems = peer_systems(campaign, folder / "peers")
        walls = dict(zip(table1.column("id").to_pylist(), table1.column("wall_time").to_pylist()))
        per_run = statistics.median(walls[i] for i in systems)
        dispatch = per_run * one.execution / sum(walls.values())  # the worker's time scaled by the whole execution's
        cli = statistics.median(time_cli(list(systems.values())))
        warm = statistics.median(time_in_process(list(systems.values())))
        scratch = Path(tempfile.mkdtemp(dir=scratch_root()))
        try:
            warm_scratch = statistics.median(time_in_process(list(systems.values()), scratch))
        finally:
            shutil.rmtree(scratch, ignore_errors=True)
        print(f"2. per run, medians over the same {len(systems)} runs")
        print(f"   campaign, 1 worker: {per_run:.3f} s per run on the worker, {dispatch:.3f} s per run of the whole execution")
        print(f"   a. plain `robogen simulate` (a process per run): {cli:.3f} s")
        print(f"   b. simulate_system() in a warm process:          {warm:.3f} s")
        print(f"   c. the same, FMUs unpacked in {scratch_root()} as the campaign's runs are: {warm_scratch:.3f} s")
        print(f"   overhead vs (a): {100 * (dispatch / cli - 1):+.1f} % (target <= +10 %); "
              f"vs (b): {100 * (dispatch / warm - 1):+.1f} %; vs (c), the isolation and the campaign machinery alone: "
              f"{100 * (dispatch / warm_scratch - 1):+.1f} %")
    return 0


if __name__ == "__main__":
    sys.exit(main())
