"""Dask's dashboard on a campaign's local cluster, and the campaign's progress shown there."""

from __future__ import annotations

import io
import json
import re
import threading
import urllib.error
import urllib.request

import pytest

from robogen.campaign import run_campaign
from robogen.campaign.dashboard import page
from robogen.campaign.engine import Progress
from support.campaign import slow_campaign, write_campaign_folder

pytest.importorskip("bokeh", reason="Dask's dashboard needs bokeh (a dependency of robogen)")

ADDRESSES = re.compile(r"dashboard: (http://127\.0\.0\.1:\d+/status) \(the campaign's progress: (http://127\.0\.0\.1:\d+/robogen)\)")


def _get(url: str) -> tuple[int, str]:
    with urllib.request.urlopen(url, timeout=30) as answer:
        return answer.status, answer.read().decode("utf-8")


def test_a_campaign_serves_the_dashboard_and_its_progress_on_localhost(tmp_path, campaign_fmus):
    # 4 runs on one worker, each 10 steps of 0.1 s of wall time: the campaign takes 4 s at least.
    campaign = write_campaign_folder(tmp_path, campaign_fmus, slow_campaign(4, 0.1))
    seen: dict = {"states": []}
    done = threading.Event()

    def watch(progress_url: str) -> None:  # the campaign's progress, as a browser would poll it
        while not done.is_set():
            try:
                seen["states"].append(json.loads(_get(progress_url + ".json")[1]))
                if "html" not in seen and seen["states"][-1] is not None:
                    seen["html"] = _get(progress_url)
            except (OSError, urllib.error.URLError):  # the cluster closes as the campaign ends
                return
            done.wait(0.1)

    def echo(line: str) -> None:
        found = ADDRESSES.search(line)
        if found:
            seen["dashboard"] = _get(found[1])
            seen["thread"] = threading.Thread(target=watch, args=(found[2],))
            seen["thread"].start()

    try:
        result = run_campaign(campaign, tmp_path / "out", workers=1, progress=False, echo=echo)
    finally:
        done.set()
        if "thread" in seen:
            seen["thread"].join()
    assert result.counts == {"ok": 4}
    status, dashboard = seen["dashboard"]  # Dask's status page, with bokeh served from the dashboard itself
    assert status == 200 and "static/js/bokeh.min.js" in dashboard and "cdn.bokeh.org" not in dashboard
    states = [s for s in seen["states"] if s is not None]
    assert states and all(s["total"] == 4 and s["title"] == "campaign" for s in states)
    done_counts = [s["done"] for s in states]
    assert done_counts == sorted(done_counts) and done_counts[0] < 4 and max(done_counts) >= 1
    status, html = seen["html"]
    assert status == 200 and "/ 4 runs done" in html and 'http-equiv="refresh"' in html


def test_the_terminal_and_the_dashboard_show_the_same_progress():
    published: list[dict] = []
    terminal = io.StringIO()
    progress = Progress(6, True, stream=terminal, title="grid <1>", publish=published.append)
    progress.done, progress.failed, progress.running = 3, 1, 2
    progress.update(force=True)
    progress.close()
    assert [(s["done"], s["failed"], s["running"], s["finished"]) for s in published] == [(3, 1, 2, False), (3, 1, 2, True)]
    assert "3/6 done, 1 failed, 2 running" in terminal.getvalue()
    html = page(published[-1])
    assert "<h1>grid &lt;1&gt;</h1>" in html and "3 / 6 runs done (50 %), 1 failed, 2 running" in html and "(finished)" in html
    assert "No campaign has started" in page(None)
