"""Executing a campaign's runs on Dask: a local cluster by default, any cluster by its address.

- Without ``--scheduler``, a ``distributed.LocalCluster`` of N worker processes with one thread
  each (FMUs are not thread-safe; a process per core is the unit of parallelism), on 127.0.0.1
  only. With ``--scheduler tcp://host:8786``, the client connects to a running cluster (started
  with ``dask scheduler`` / ``dask worker``, or by a Dask deployment project) and changes nothing
  on it.
- The campaign's :class:`~robogen.campaign.plan.Context` and each distinct FMU are scattered to
  the cluster once; every run is one task referring to them, so Dask moves an FMU to a worker the
  first time one of its runs lands there, and never again.
- A task never fails because its run failed (that is a row with status "failed"). A task fails
  when its worker is lost: the local cluster reports that at once (``allowed-failures`` 0) and
  the run is submitted again, at most ``retries`` times; a cluster started by the user applies its
  own ``distributed.scheduler.allowed-failures`` first. A run still without a result is "lost".
- Dask's dashboard (bokeh, a dependency of robogen) is served on 127.0.0.1 by a local cluster;
  its address is printed, with that of the page showing the campaign's progress
  (:mod:`robogen.campaign.dashboard`), which the terminal's progress line also shows.
"""

from __future__ import annotations

import importlib.util
import logging
import os
import sys
import time
from contextlib import contextmanager
from typing import Callable, Iterator
from urllib.parse import urljoin

from robogen.campaign.plan import CampaignPlan, Run
from robogen.campaign.worker import execute_run, prepare
from robogen.diagnostics import RobogenError

#: The local cluster's settings. A lost worker is reported at once (the client retries the run).
#: The rest take Dask's periodic bookkeeping off the cores the runs need: on a 2-core machine
#: running two simulations, the defaults cost the client (scheduler and nannies included) and the
#: two workers ~19 % of a core between them, these ~8 % (docs/scale-out.md). The worker's
#: profiler samples the thread that runs tasks every 10 ms, and that thread only waits for the
#: zygote; the event-loop tick (20 ms) only measures how late the loop is; memory and system
#: monitors sampled each second rather than 10 and 2 times a second.
LOCAL_CLUSTER_CONFIG = {
    "distributed.scheduler.allowed-failures": 0,
    "distributed.worker.profile.enabled": False,
    "distributed.admin.tick.interval": "1s",
    "distributed.worker.memory.monitor-interval": "1s",
    "distributed.admin.system-monitor.interval": "2s",
}


@contextmanager
def connect(workers: int | None, scheduler: str | None, echo: Callable[[str], None]) -> Iterator[object]:
    """A Dask client: to ``scheduler`` if given, else to a new local cluster of ``workers``."""
    import dask
    from distributed import Client, LocalCluster

    if scheduler:
        try:
            client = Client(scheduler, timeout="20s")
        except (OSError, TimeoutError) as exc:
            raise RobogenError.at(f"cannot reach the Dask scheduler at {scheduler}: {exc}", None) from None
        cluster = None
    else:
        n = workers or os.cpu_count() or 1
        with dask.config.set(LOCAL_CLUSTER_CONFIG):
            cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, host="127.0.0.1",
                                   scheduler_port=0, dashboard_address="127.0.0.1:0",
                                   silence_logs=logging.ERROR)
        client = Client(cluster)
    try:
        workers_now = client.nthreads()
        where = scheduler or f"a local cluster ({len(workers_now)} worker processes, 1 thread each)"
        echo(f"Dask: {where}; dashboard: {dashboard(client)}")
        yield client
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def dashboard(client) -> str:
    """The dashboard's address and that of robogen's progress page, or why there is none (its
    pages need the bokeh package)."""
    if "dashboard" not in client.scheduler_info().get("services", {}):
        return "off (the scheduler serves none)"
    if importlib.util.find_spec("bokeh") is None:
        return f"off ({client.dashboard_link} needs the bokeh package here: pip install 'bokeh>=3.1.0')"
    from robogen.campaign.dashboard import add_page

    try:
        path = client.run_on_scheduler(add_page)
    except Exception as exc:  # a scheduler elsewhere without robogen, or one that refuses: Dask's pages only
        return f"{client.dashboard_link} (robogen's progress page: off, the scheduler cannot serve it: {type(exc).__name__}: {exc})"
    return f"{client.dashboard_link} (the campaign's progress: {urljoin(client.dashboard_link, path.lstrip('/'))})"


class Progress:
    """The campaign's progress: done / failed / running, runs per second, time left. Drawn as one
    line on a terminal (``enabled``), and handed to ``publish`` (Dask's dashboard:
    :mod:`robogen.campaign.dashboard`) at most once a second and at the end."""

    def __init__(self, total: int, enabled: bool, stream=sys.stderr, title: str = "",
                 publish: Callable[[dict], None] | None = None) -> None:
        self.total, self.enabled, self.stream = total, enabled, stream
        self.title, self.publish = title, publish
        self.started = time.monotonic()
        self.done = self.failed = self.running = 0
        self.drawn = self.published = 0.0

    @property
    def watched(self) -> bool:
        """Whether anyone looks at the progress (a terminal, the dashboard)."""
        return self.enabled or self.publish is not None

    def state(self, finished: bool = False) -> dict:
        """The progress as numbers (JSON): runs total, done, failed, running; runs per second,
        seconds elapsed, time left (m:ss, or None while unknown)."""
        elapsed = max(time.monotonic() - self.started, 1e-9)
        rate = self.done / elapsed
        left = (self.total - self.done) / rate if rate > 0 else None
        eta = None if left is None else f"{int(left // 60)}:{int(left % 60):02d}"
        return {"title": self.title, "total": self.total, "done": self.done, "failed": self.failed,
                "running": self.running, "rate": rate, "elapsed": elapsed, "eta": eta, "finished": finished}

    def update(self, force: bool = False, finished: bool = False) -> None:
        now = time.monotonic()
        if self.publish is not None and (force or now - self.published >= 1.0):
            self.published = now
            self.publish(self.state(finished))
        if not self.enabled or (not force and now - self.drawn < 0.2):
            return
        self.drawn = now
        state = self.state(finished)
        width = 24
        filled = int(width * self.done / self.total) if self.total else width
        bar = "#" * filled + "." * (width - filled)
        self.stream.write(f"\r[{bar}] {self.done}/{self.total} done, {self.failed} failed, {self.running} running, "
                          f"{state['rate']:.1f} runs/s, ETA {state['eta'] or '--:--'}  ")
        self.stream.flush()

    def close(self) -> None:
        self.update(force=True, finished=True)
        if self.enabled:
            self.stream.write("\n")
            self.stream.flush()


def execute(plan: CampaignPlan, todo: list[Run], client, *, retries: int, record: Callable[[Run, dict], None],
            progress: Progress) -> dict[str, str]:
    """Run ``todo`` (one per key) on the cluster; ``record(run, row)`` each result as it arrives.
    Returns key -> reason for the runs that could not be completed (lost)."""
    from distributed import as_completed

    try:  # warm every worker's zygote now rather than in its first run (a worker that joins later warms then)
        client.run(prepare, plan.context.preload)
    except RuntimeError as exc:
        raise RobogenError.at(f"a worker cannot prepare for the campaign: {exc}", plan.campaign.span("preload")) from None
    progress.started = time.monotonic()
    progress.update(force=True)
    context = client.scatter(plan.context, hash=False)
    digests = sorted({d for run in todo for d in run.spec.fmus.values()})
    shipped = dict(zip(digests, client.scatter([plan.fmu_files[d].read_bytes() for d in digests], hash=False)))
    attempts: dict[str, int] = {}
    pending: dict[str, Run] = {}

    def submit(run: Run):
        attempt = attempts.get(run.spec.key, 0)
        attempts[run.spec.key] = attempt + 1
        fmus = {d: shipped[d] for d in set(run.spec.fmus.values())}
        future = client.submit(execute_run, context, run.spec, fmus, key=f"robogen-run-{run.spec.key[:20]}-{attempt}",
                               pure=False)
        pending[future.key] = run
        return future

    lost: dict[str, str] = {}
    queue = as_completed([submit(run) for run in todo])
    processing_seen = 0.0
    for future in queue:
        run = pending.pop(future.key)
        row = future.result() if future.status == "finished" else None
        if row is not None:
            record(run, row)
            progress.done += 1
            progress.failed += row["status"] == "failed"
        elif attempts[run.spec.key] <= retries:
            queue.add(submit(run))
        else:
            lost[run.spec.key] = f"lost: no result after {attempts[run.spec.key]} attempts ({_reason(future)})"
            progress.done += 1
            progress.failed += 1
        future.release()
        if progress.watched and time.monotonic() - processing_seen > 0.5:
            processing_seen = time.monotonic()
            nthreads = client.nthreads()
            progress.running = sum(min(len(keys), nthreads.get(w, 1)) for w, keys in client.processing().items())
        progress.update()
    return lost


def _reason(future) -> str:
    try:
        exc = future.exception()
    except Exception as err:  # a cancelled future has no exception to give
        return f"{type(err).__name__}"
    return f"{type(exc).__name__}: {exc}"
