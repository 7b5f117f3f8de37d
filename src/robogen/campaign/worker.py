"""What a Dask worker does for a campaign: keep the FMUs it received, run each run isolated.

A worker process holds one :class:`_WorkerState`: a private folder (FMUs by content hash, one
folder per run while it executes) and its zygote (:mod:`robogen.campaign.isolate`). The FMU
bytes arrive as Dask data, fetched once per worker per content hash; they are written to the
folder the first time a run needs them. Both go away with the worker: the zygote exits when its
worker's pipe closes and removes the folder, however the worker ended.

The folder is in memory (``/dev/shm``) when the machine has one with room to spare: a run
unpacks its FMUs and removes them again, and on a disk those file-system operations cost about
a fifth of a short UR5e run (docs/scale-out.md).
"""

from __future__ import annotations

import atexit
import os
import shutil
import tempfile
import threading
import time
from pathlib import Path

from robogen.campaign.child import failed, rehearsal, run
from robogen.campaign.isolate import Zygote
from robogen.campaign.plan import Context, RunSpec

_PREFIX = "robogen-campaign-"
_MEMORY = Path("/dev/shm")
_MEMORY_NEEDED = 1 << 30  # bytes free on /dev/shm to use it (containers often give it 64 MiB)


def scratch_root() -> Path:
    """Where the worker's folder goes: /dev/shm when it is there with room, else the temp folder."""
    try:
        stats = os.statvfs(_MEMORY)
        if os.access(_MEMORY, os.W_OK) and stats.f_bavail * stats.f_frsize >= _MEMORY_NEEDED:
            return _MEMORY
    except OSError:
        pass
    return Path(tempfile.gettempdir())


class _WorkerState:
    def __init__(self) -> None:
        _remove_stale_folders()
        self.folder = Path(tempfile.mkdtemp(prefix=f"{_PREFIX}{os.getpid()}-", dir=scratch_root()))
        self.zygote = Zygote(owned=self.folder)
        self.fmus: dict[str, Path] = {}
        self.rehearsed: set[tuple] = set()  # (system, FMUs) combinations the zygote has simulated
        self.proven: dict[tuple, RunSpec] = {}  # combination -> a run of it that succeeded, not yet rehearsed
        atexit.register(self.close)

    def fmu(self, digest: str, data: bytes) -> Path:
        """The local file of the FMU with this content hash (written the first time)."""
        if digest not in self.fmus:
            path = self.folder / f"{digest}.fmu"
            tmp = path.with_suffix(".part")
            tmp.write_bytes(data)
            os.replace(tmp, path)
            self.fmus[digest] = path
        return self.fmus[digest]

    def rehearse(self, context: Context, spec: RunSpec, paths: dict[str, Path]) -> None:
        """The first communication step of a run that just succeeded, in the zygote itself: warms
        it for every later run of these FMUs (see :func:`robogen.campaign.isolate.serve`)."""
        folder = Path(tempfile.mkdtemp(prefix="rehearsal-", dir=self.folder))
        try:
            self.zygote.warm(context.preload, rehearsal, (context, spec, paths, folder, self.folder))
        finally:
            shutil.rmtree(folder, ignore_errors=True)

    def close(self) -> None:
        self.zygote.close()
        shutil.rmtree(self.folder, ignore_errors=True)


def _remove_stale_folders() -> None:
    """Folders left by worker processes that were killed (their process no longer exists)."""
    for folder in scratch_root().glob(f"{_PREFIX}*-*"):
        pid = folder.name[len(_PREFIX):].split("-")[0]
        if pid.isdigit() and not _alive(int(pid)):
            shutil.rmtree(folder, ignore_errors=True)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


_state: _WorkerState | None = None
_state_lock = threading.Lock()


def _here() -> _WorkerState:
    global _state
    with _state_lock:
        if _state is None:
            _state = _WorkerState()
        return _state


def _worker_name() -> str:
    try:
        from distributed import get_worker

        return get_worker().address
    except (ImportError, ValueError):
        return f"pid {os.getpid()}"


def prepare(preload: tuple[str, ...]) -> None:
    """Start this worker's zygote and import ``preload`` in it, before the first run arrives."""
    outcome = _here().zygote.run(preload, 0.0, None, ())
    if outcome.failure is not None:
        raise RuntimeError(outcome.failure)


def execute_run(context: Context, spec: RunSpec, fmus: dict[str, bytes]) -> dict:
    """The Dask task of one run: its row (status, error, end_time, metrics, wall_time, worker;
    ``series`` with keep = "results"). Never raises for a failing run.

    The first run of a combination of FMUs on this worker starts cold. When a second run of it
    arrives and one has succeeded, the first step of that one is rehearsed in the zygote first
    (:meth:`_WorkerState.rehearse`), so that this run and the later ones start warm. Warming
    only after a success keeps a crash or a hang out of the zygote without a simulation of its
    own to prove the FMUs first; warming at the second run spares a worker that gets one run."""
    state = _here()
    paths = {instance: state.fmu(digest, fmus[digest]) for instance, digest in spec.fmus.items()}
    combination = (context.system_text, tuple(sorted(spec.fmus.items())))
    if combination in state.proven:
        state.rehearse(context, state.proven.pop(combination), paths)
        state.rehearsed.add(combination)
    folder = Path(tempfile.mkdtemp(prefix="run-", dir=state.folder))
    started = time.perf_counter()
    try:
        outcome = state.zygote.run(context.preload, context.timeout, run, (context, spec, paths, folder, state.folder))
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    row = outcome.result if outcome.failure is None else failed(outcome.failure)
    row["wall_time"] = time.perf_counter() - started
    row["worker"] = _worker_name()
    if row["status"] != "failed" and combination not in state.rehearsed:
        state.proven.setdefault(combination, spec)
    return row
