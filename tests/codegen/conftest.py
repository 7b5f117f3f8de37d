"""Fixtures of the code generator's tests: the test models, compiled and packaged once per session.

``built(name, semantics, trigger="cycle")`` returns the model compiled with those options,
packaged as a validated ``.fmu`` and unzipped for loading (a :class:`codegen_driver.Built`). The
builds run two at a time (the C compiler is a separate process) and are cached for the session.
"""

from __future__ import annotations

import threading
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

from codegen_driver import Built, build
from codegen_models import SEMANTICS, TEST_MODELS
from robogen.ir.lower import LoweringOptions


class Builds:
    """Session cache of built FMUs, keyed (model, semantics, trigger)."""

    def __init__(self, folder: Path):
        self.folder = folder
        self.pool = ThreadPoolExecutor(max_workers=2)
        self.futures: dict[tuple[str, str, str], object] = {}
        self.lock = threading.Lock()

    def submit(self, name: str, semantics: str, trigger: str = "cycle"):
        key = (name, semantics, trigger)
        with self.lock:
            if key not in self.futures:
                model = TEST_MODELS[name]
                options = LoweringOptions(semantics=semantics, trigger=trigger, max_steps=model.max_steps,
                                  settings=dict(model.settings))
                work = self.folder / f"{name}-{semantics}-{trigger}"
                self.futures[key] = self.pool.submit(build, [model.path], work, options=options)
            return self.futures[key]

    def get(self, name: str, semantics: str, trigger: str = "cycle") -> Built:
        return self.submit(name, semantics, trigger).result()  # type: ignore[attr-defined]


@pytest.fixture(scope="session")
def builds(tmp_path_factory) -> Builds:
    cache = Builds(tmp_path_factory.mktemp("codegen"))
    for name in TEST_MODELS:  # start every build now: they run while the first tests wait
        for semantics in SEMANTICS:
            cache.submit(name, semantics)
    yield cache
    cache.pool.shutdown(wait=True)


@pytest.fixture(scope="session")
def built(builds):
    return builds.get
