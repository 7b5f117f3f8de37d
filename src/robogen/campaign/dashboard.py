"""robogen's progress on Dask's dashboard, beside Dask's own pages.

Dask's dashboard (bokeh, served by the scheduler) shows tasks: its task stream names every run
``robogen-run`` (the runs' keys, :func:`robogen.campaign.engine.execute`), but its progress bars
count only the tasks the scheduler still holds, and a finished run's task is released as soon as
its row is recorded. So the campaign's own progress (runs done out of the campaign's, failed,
running, runs per second, time left: the terminal's line) is published to the scheduler as
metadata (:func:`publisher`, at most once a second and at the end) and shown by a page the
scheduler's web server serves at :data:`PAGE` (:func:`add_page`, run on the scheduler): HTML
that reloads itself every second, and the same figures as JSON at ``PAGE + ".json"``. Nothing is
fetched from the network: the page is plain HTML, and bokeh serves Dask's pages from its own
files.
"""

from __future__ import annotations

import html
import json
from typing import Callable

#: The page's path on the dashboard's server.
PAGE = "/robogen"
#: Where the progress is kept in the scheduler's metadata.
KEY = ["robogen", "progress"]
_ADDED = ["robogen", "page"]


def add_page(dask_scheduler) -> str:
    """Serve the progress page on this scheduler's web server (once); its path. Run on the
    scheduler (``client.run_on_scheduler``)."""
    from tornado import web

    class ProgressPage(web.RequestHandler):
        def get(self, suffix: str) -> None:
            state = dask_scheduler.get_metadata(KEY, default=None)
            if suffix == ".json":
                self.set_header("Content-Type", "application/json")
                self.write(json.dumps(state))
            else:
                self.set_header("Content-Type", "text/html; charset=utf-8")
                self.write(page(state))

    if not dask_scheduler.get_metadata(_ADDED, default=False):
        dask_scheduler.http_application.add_handlers(".*$", [(PAGE + r"(\.json)?", ProgressPage)])
        dask_scheduler.set_metadata(_ADDED, True)
    return PAGE


def publisher(client) -> Callable[[dict], None]:
    """Publishes a progress state (:meth:`robogen.campaign.engine.Progress.state`) to the scheduler."""

    def publish(state: dict) -> None:
        client.set_metadata(KEY, state)

    return publish


def page(state: dict | None) -> str:
    """The progress page's HTML for a state (None: no campaign has started yet)."""
    if state is None:
        body = "<p>No campaign has started on this cluster yet.</p>"
        title = "robogen"
    else:
        title = html.escape(state["title"])
        total = max(state["total"], 1)
        percent = 100.0 * state["done"] / total
        eta = state["eta"] if state["eta"] is not None else "--:--"
        body = (f"<h1>{title}</h1>"
                f'<div style="width:40em;border:1px solid #444"><div style="width:{percent:.1f}%;background:#45bf6f">&nbsp;</div></div>'
                f"<p>{state['done']} / {state['total']} runs done ({percent:.0f} %), {state['failed']} failed, "
                f"{state['running']} running; {state['rate']:.2f} runs/s, {state['elapsed']:.0f} s elapsed, ETA {eta}"
                f"{' (finished)' if state['finished'] else ''}</p>")
    return (f'<!DOCTYPE html>\n<html><head><meta charset="utf-8"><meta http-equiv="refresh" content="1">'
            f"<title>{title}: progress</title></head>"
            f'<body style="font-family:sans-serif">{body}<p><a href="status">Dask\'s dashboard</a></p></body></html>\n')
