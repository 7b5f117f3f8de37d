"""A campaign on a cluster started the way a user starts one: `dask scheduler` and two
`dask worker` processes on free local ports; one worker is killed in the middle of a campaign."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pyarrow.parquet as pq
import pytest

from support.campaign import CAMPAIGN, EXTRA_METRICS, CampaignProcess, run_quietly, slow_campaign, write_campaign_folder

PLACEMENT = ["wall_time", "worker"]


def _start(args: list[str], log: Path) -> subprocess.Popen:
    with log.open("w") as out:
        return subprocess.Popen([sys.executable, "-m", *args], stdout=out, stderr=subprocess.STDOUT,
                                start_new_session=True)


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    """(scheduler address, processes): a scheduler and two single-threaded workers with nannies,
    all of them killed (with their process groups) at the end, whatever happened."""
    from distributed import Client

    folder = tmp_path_factory.mktemp("dask-cluster")
    scheduler_file = folder / "scheduler.json"
    processes = [_start(["distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                         "--scheduler-file", str(scheduler_file)], folder / "scheduler.log")]
    try:
        deadline = time.monotonic() + 60
        while not scheduler_file.exists() and time.monotonic() < deadline:
            time.sleep(0.05)
        for i in range(2):
            processes.append(_start(["distributed.cli.dask_worker", "--scheduler-file", str(scheduler_file),
                                     "--host", "127.0.0.1", "--nworkers", "1", "--nthreads", "1", "--no-dashboard",
                                     "--local-directory", str(folder / f"worker-{i}")], folder / f"worker-{i}.log"))
        address = json.loads(scheduler_file.read_text())["address"]
        with Client(address, timeout="30s") as client:
            client.wait_for_workers(2, timeout=60)
        yield address
    finally:  # workers first, politely (their folders go with them), then whatever is left
        for process in reversed(processes):
            _signal_group(process, signal.SIGTERM)
            try:
                process.wait(timeout=15)
            except subprocess.TimeoutExpired:
                pass
            _signal_group(process, signal.SIGKILL)
            process.wait(timeout=30)


def _signal_group(process: subprocess.Popen, number: int) -> None:
    try:
        os.killpg(process.pid, number)
    except ProcessLookupError:
        pass


def test_a_campaign_through_scheduler_matches_the_local_cluster(cluster, two_worker_run, tmp_path, campaign_fmus):
    _, _, local = two_worker_run
    campaign = write_campaign_folder(tmp_path, campaign_fmus, CAMPAIGN, **{"extra_metrics.py": EXTRA_METRICS})
    result = run_quietly(campaign, tmp_path / "out", scheduler=cluster)
    remote = pq.read_table(tmp_path / "out" / "runs.parquet")
    assert result.counts == {"ok": 3, "failed": 3}
    assert remote.drop_columns(PLACEMENT).equals(local.drop_columns(PLACEMENT))




def test_a_worker_killed_mid_campaign_loses_no_run(cluster, tmp_path, campaign_fmus):
    from distributed import Client

    campaign = write_campaign_folder(tmp_path, campaign_fmus, slow_campaign(10, 0.05))
    out = tmp_path / "out"
    journal = out / "journal.jsonl"
    with Client(cluster, timeout="30s") as client:
        pids = client.run(os.getpid)
    with CampaignProcess(str(campaign), "-o", str(out), "--scheduler", cluster) as campaign_process:
        campaign_process.wait_for_journal(journal, 2)
        victim = sorted(pids.values())[0]
        os.kill(victim, signal.SIGKILL)  # a worker process dies with a run in progress (runs take 0.5 s)
        status, err = campaign_process.finish()
    assert status == 0, err
    rows = pq.read_table(out / "runs.parquet").to_pylist()
    assert [(r["status"], r["y"]) for r in rows] == [("ok", g * 1.0) for g in range(1, 11)]
    with Client(cluster, timeout="30s") as client:
        client.wait_for_workers(2, timeout=60)  # the nanny started a new worker process
        assert victim not in client.run(os.getpid).values()
