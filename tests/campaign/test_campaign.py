"""Campaigns on a local Dask cluster: results, crashes, determinism, resuming."""

from __future__ import annotations

import signal
import subprocess
import sys

import pyarrow.parquet as pq

from support.campaign import CAMPAIGN, EXTRA_METRICS, CampaignProcess, run_quietly, slow_campaign, write_campaign_folder

PLACEMENT = ["wall_time", "worker"]


def test_every_run_has_its_row_with_metrics_computed_by_hand(two_worker_run):
    _, result, runs = two_worker_run
    assert result.counts == {"ok": 3, "failed": 3} and result.executed == 6
    rows = runs.to_pylist()
    assert [(r["run"], r["crasher.gain"], r["crasher.crash_time"]) for r in rows] == [
        (0, 1.0, -1.0), (1, 1.0, 1.0), (2, 2.0, -1.0), (3, 2.0, 1.0), (4, 3.0, -1.0), (5, 3.0, 1.0)]
    for r in rows[0::2]:  # y = gain * t over [0, 2] s; the ticker ticks at 0, 0.25, ..., 2.0
        assert (r["status"], r["error"], r["end_time"]) == ("ok", "", 2.0)
        assert (r["y"], r["y_at_1"], r["ticks"], r["half_y"]) == (2 * r["crasher.gain"], r["crasher.gain"], 9, r["crasher.gain"])
    for r in rows[1::2]:  # the FMU writes through a null pointer in the step that reaches t = 1 s
        assert r["status"] == "failed"
        assert r["error"] == "crashed: the run's process was killed by SIGSEGV (Segmentation fault)"
        assert r["y"] is None and r["end_time"] is None
    assert runs.column_names == ["run", "id", "crasher.gain", "crasher.crash_time", "y", "y_at_1", "ticks", "half_y",
                                 "status", "error", "end_time", "wall_time", "worker"]
    assert len({r["worker"] for r in rows}) == 2  # both workers took runs


def test_files_written_beside_the_table(two_worker_run):
    _, result, runs = two_worker_run
    folder = result.folder
    csv_lines = (folder / "runs.csv").read_text().splitlines()
    assert len(csv_lines) == 7 and csv_lines[0].startswith('"run","id","crasher.gain"')
    summary = (folder / "summary.md").read_text()
    assert "6 runs, 3 ok, 3 failed" in summary and "![summary figure](summary.png)" in summary
    assert "killed by SIGSEGV" in summary
    assert (folder / "summary.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    kept = sorted(p.stem for p in (folder / "results").glob("*.parquet"))  # keep = "results": the ok runs
    assert kept == sorted(r["id"] for r in runs.to_pylist() if r["status"] == "ok")
    series = pq.read_table(folder / "results" / f"{kept[0]}.parquet")
    assert series.column_names[:2] == ["time", "superdense"] and "crasher.y" in series.column_names


def test_one_worker_gives_the_same_table(two_worker_run, tmp_path, campaign_fmus):
    _, _, two = two_worker_run
    campaign = write_campaign_folder(tmp_path, campaign_fmus, CAMPAIGN, **{"extra_metrics.py": EXTRA_METRICS})
    run_quietly(campaign, tmp_path / "out", workers=1)
    one = pq.read_table(tmp_path / "out" / "runs.parquet")
    assert one.drop_columns(PLACEMENT).equals(two.drop_columns(PLACEMENT))
    assert len(set(one.column("worker").to_pylist())) == 1




def test_an_interrupted_campaign_runs_only_what_was_missing(tmp_path, campaign_fmus):
    campaign = write_campaign_folder(tmp_path, campaign_fmus, slow_campaign(12, 0.03))
    out = tmp_path / "out"
    journal = out / "journal.jsonl"
    arguments = [str(campaign), "-o", str(out), "--workers", "1"]
    with CampaignProcess(*arguments) as campaign_process:
        campaign_process.wait_for_journal(journal, 3)
        campaign_process.process.send_signal(signal.SIGINT)  # Ctrl-C, to the campaign's client only
        status, err = campaign_process.finish()
    assert status == 130, err
    done = len(journal.read_text().splitlines())
    assert 3 <= done < 12, err
    assert "run the same command again to continue" in err

    again = subprocess.run([sys.executable, "-m", "robogen", "campaign", *arguments], capture_output=True, text=True,
                           timeout=120)
    assert again.returncode == 0, again.stderr
    assert f"{done} already done, {12 - done} to run" in again.stderr
    rows = pq.read_table(out / "runs.parquet").to_pylist()
    assert [(r["status"], r["y"]) for r in rows] == [("ok", g * 1.0) for g in range(1, 13)]
    assert len(journal.read_text().splitlines()) == 12
