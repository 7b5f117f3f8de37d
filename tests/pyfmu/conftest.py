"""Fixtures for the Python-FMU tests: the fixture models packaged once per session, and the C
host compiled once per session."""

from __future__ import annotations

from pathlib import Path

import pytest

from robogen.pyfmu.build import package
from support.pyfmu import compile_host


@pytest.fixture(scope="session")
def fmus(tmp_path_factory) -> dict[str, Path]:
    out = tmp_path_factory.mktemp("pyfmus")
    built = {}
    for name, spec, settings in [
        ("counter", "pyfmu_fixture_models:Counter", []),
        ("counter_fast", "pyfmu_fixture_models:Counter", ["period=0.25"]),
        ("two_instants", "pyfmu_fixture_models:TwoInstants", []),
        ("broken_setup", "pyfmu_fixture_models:BrokenSetup", []),
        ("uses_numpy", "pyfmu_fixture_models:UsesNumpy", []),
    ]:
        built[name] = package(spec, out / f"{name}.fmu", settings, model_identifier=name).path
    return built


@pytest.fixture(scope="session")
def host(tmp_path_factory) -> Path:
    return compile_host(tmp_path_factory.mktemp("host"))
