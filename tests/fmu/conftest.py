"""Fixtures for the FMU-reading tests: the master's C test FMUs (built once per session)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

BUILD = Path(__file__).resolve().parent.parent / "cosim" / "fmus" / "build.py"


@pytest.fixture(scope="session")
def fmu_builder():
    spec = importlib.util.spec_from_file_location("robogen_test_fmus_build", BUILD)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="session")
def built(tmp_path_factory, fmu_builder) -> dict[str, Path]:
    return fmu_builder.build_all(tmp_path_factory.mktemp("fmus"), ["ticker", "relay", "trivial"])
