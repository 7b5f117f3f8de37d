"""Fixtures of the tests that run compiled models (tests/codegen, tests/ir): the test models,
compiled and packaged once per session.

``built(name, semantics, trigger="cycle")`` returns the model compiled with those options,
packaged as a validated ``.fmu`` and unzipped for loading (a :class:`codegen_driver.Built`). The
builds run two at a time (the C compiler is a separate process) and are cached for the session:
the conftest of each folder that uses them imports these fixtures, and both share one cache.
Run in one process, the session starts every build at once so that they overlap the first tests;
under pytest-xdist each worker builds only what its tests ask for (the workers are the overlap).
"""

from __future__ import annotations

import os
import threading
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

from support.codegen_driver import Built, build
from support.codegen_models import SEMANTICS, TEST_MODELS
from robogen.ir.lower import LoweringOptions


class Builds:
    """Session cache of built FMUs, keyed (model, semantics, trigger)."""

    def __init__(self, folder: Path):
        self.folder = folder
        self.pool = ThreadPoolExecutor(max_workers=1 if _XDIST else 2)
        self.futures: dict[tuple[str, str, str], object] = {}
        self.lock = threading.Lock()

    def submit(self, name: str, semantics: str, trigger: str = "cycle"):
        key = (name, semantics, trigger)
        with self.lock:
            if key not in self.futures:
                model = TEST_MODELS[name]
                options = LoweringOptions(semantics=semantics, trigger=trigger, max_steps=model.max_steps,
                                          settings=dict(model.settings), capacity=model.capacity,
                                          capacities=model.capacities)
                work = self.folder / f"{name}-{semantics}-{trigger}"
                self.futures[key] = self.pool.submit(build, [model.path], work, options=options)
            return self.futures[key]

    def get(self, name: str, semantics: str, trigger: str = "cycle") -> Built:
        return self.submit(name, semantics, trigger).result()  # type: ignore[attr-defined]


_XDIST = "PYTEST_XDIST_WORKER" in os.environ
_session: list[Builds] = []  # the one cache of the session, whichever folder's tests ask first


@pytest.fixture(scope="session")
def builds(tmp_path_factory) -> Builds:
    if _session:
        yield _session[0]
        return
    cache = Builds(tmp_path_factory.mktemp("codegen"))
    _session.append(cache)
    for name in () if _XDIST else TEST_MODELS:  # start every build now: they run while the first tests wait
        for semantics in SEMANTICS:
            cache.submit(name, semantics)
    yield cache
    cache.pool.shutdown(wait=True)


@pytest.fixture(scope="session")
def built(builds):
    return builds.get
