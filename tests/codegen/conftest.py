"""Fixtures of the code generator's tests: the test models, compiled and packaged once per session.

``built(name, semantics, trigger="cycle")`` returns the model compiled with those options,
packaged as a validated ``.fmu`` and unzipped for loading (a :class:`codegen_driver.Built`). The
builds run two at a time (the C compiler is a separate process) and are cached for the session.
"""

from __future__ import annotations

import threading
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from codegen_driver import Built, build
from robogen.ir.lower import Options

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
MODELS = HERE / "models"
UR5E = ROOT / "models" / "ur5e" / "ur5e.rst"


@dataclass(frozen=True)
class TestModel:
    name: str
    path: Path
    max_steps: int = 1000
    # payload choices for the random scenarios (FMI name -> values), to keep run-time errors rare
    choices: dict[str, list] = field(default_factory=dict)


NONZERO = [-7, -3, -2, -1, 1, 2, 3, 5, 9]

TEST_MODELS = {
    m.name: m
    for m in (
        TestModel("ur5e", UR5E),
        TestModel("composite", MODELS / "composite.rst"),
        TestModel("data", MODELS / "data.rst", choices={
            "divisor.value": NONZERO * 4 + [0],
            "pick.value": [1, 2, 3, 1, 2, 3, 1, 2, 3, 0, 7, 4],
        }),
        TestModel("ops", MODELS / "ops.rst"),
        TestModel("pipeline", MODELS / "pipeline.rst"),
        TestModel("arith", MODELS / "arith.rst", max_steps=40, choices={
            "b.value": NONZERO * 3 + [0, 2**63 - 1, -(2**63)],
            "n.value": [0, 1, 2, 3, 4, 5, 6, 2**64 - 1, 7, 7],
            "x.value": [-2.5, -1.0, -0.5, 0.0, 0.25, 0.5, 1.0, 1.5, 1e300, -1e300, 3.0],
        }),
        TestModel("beacon", MODELS / "beacon.rst"),
        TestModel("timers", MODELS / "timers.rct"),
        TestModel("inputs", MODELS / "inputs.rct"),
        TestModel("relay", MODELS / "relay.rct"),
    )
}
OWN_MODELS = [n for n in TEST_MODELS if n != "ur5e"]
SEMANTICS = ("exhaustive", "stepwise")


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
                options = Options(semantics=semantics, trigger=trigger, max_steps=model.max_steps)
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
