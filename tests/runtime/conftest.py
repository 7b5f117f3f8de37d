"""Fixtures of the runtime tests: the hand-written test FMUs, built once per session.

``models/counter`` and ``models/plain`` are what the code generator would emit for two tiny
models (config.h, model.c, the unity file and modelDescription.xml). They are compiled with
robogen.codegen.binary into unzipped-FMU folders under a temporary directory (binaries are never
committed): ``<dir>/modelDescription.xml`` and ``<dir>/binaries/x86_64-linux/<id>.so``, the
layout fmpy's FMU3Slave loads.
"""

from __future__ import annotations

import shutil
from dataclasses import dataclass
from pathlib import Path

import pytest
from fmpy import read_model_description
from fmpy.fmi3 import FMU3Slave
from fmpy.model_description import ModelDescription

from robogen.codegen import binary
from robogen.fmu.headers import PLATFORM_TUPLE

MODELS = Path(__file__).resolve().parent / "models"


@dataclass(frozen=True)
class BuiltFmu:
    """An unzipped test FMU: its folder, library and parsed model description."""

    name: str
    unzip_dir: Path
    library: Path
    model_description: ModelDescription

    def vr(self, name: str) -> int:
        """The value reference of the variable called ``name``."""
        for variable in self.model_description.modelVariables:
            if variable.name == name:
                return variable.valueReference
        raise KeyError(name)


def build_test_fmu(name: str, folder: Path, *, sanitize: bool = False) -> BuiltFmu:
    source = MODELS / name
    folder.mkdir(parents=True, exist_ok=True)
    shutil.copy(source / "modelDescription.xml", folder / "modelDescription.xml")
    (folder / "resources").mkdir(exist_ok=True)
    library = binary.compile_fmu_binary(
        source, name, folder / "binaries" / PLATFORM_TUPLE / f"{name}.so", sanitize=sanitize
    )
    return BuiltFmu(name, folder, library, read_model_description(str(folder / "modelDescription.xml")))


@pytest.fixture(scope="session")
def counter_fmu(tmp_path_factory) -> BuiltFmu:
    return build_test_fmu("counter", tmp_path_factory.mktemp("fmu") / "counter")


@pytest.fixture(scope="session")
def plain_fmu(tmp_path_factory) -> BuiltFmu:
    return build_test_fmu("plain", tmp_path_factory.mktemp("fmu") / "plain")


@pytest.fixture(scope="session")
def sanitized_fmus(tmp_path_factory) -> tuple[BuiltFmu, BuiltFmu]:
    """counter and plain built with AddressSanitizer + UBSan (loadable only by a sanitized program)."""
    folder = tmp_path_factory.mktemp("sanitized")
    return (
        build_test_fmu("counter", folder / "counter", sanitize=True),
        build_test_fmu("plain", folder / "plain", sanitize=True),
    )


class LogCollector:
    """A logMessage callback that keeps every message as (status, category, text)."""

    def __init__(self) -> None:
        self.messages: list[tuple[int, str, str]] = []

    def __call__(self, environment, status, category, message) -> None:
        self.messages.append((int(status), category.decode(), message.decode()))

    def texts(self, category: str | None = None) -> list[str]:
        return [text for _, cat, text in self.messages if category is None or cat == category]

    def clear(self) -> None:
        self.messages.clear()


@pytest.fixture
def open_slave():
    """open_slave(fmu, **instantiate_kwargs) -> (FMU3Slave, LogCollector); freed after the test."""
    opened: list[FMU3Slave] = []

    def make(fmu: BuiltFmu, *, logging_on: bool = True, event_mode_used: bool = True, early_return_allowed: bool = False):
        log = LogCollector()
        slave = FMU3Slave(
            guid=fmu.model_description.guid,
            unzipDirectory=str(fmu.unzip_dir),
            modelIdentifier=fmu.model_description.coSimulation.modelIdentifier,
            instanceName=f"{fmu.name}{len(opened)}",
        )
        slave.instantiate(
            loggingOn=logging_on,
            eventModeUsed=event_mode_used,
            earlyReturnAllowed=early_return_allowed,
            logMessage=log,
        )
        opened.append(slave)
        return slave, log

    yield make
    for slave in opened:
        slave.freeInstance()
