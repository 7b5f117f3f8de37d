"""Fixtures for the master's tests: robogen's own C test FMUs, built once per session."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

FMUS_DIR = Path(__file__).resolve().parent / "fmus"


def _builder():
    spec = importlib.util.spec_from_file_location("robogen_test_fmus_build", FMUS_DIR / "build.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="session")
def fmu_builder():
    return _builder()


@pytest.fixture(scope="session")
def fmus(tmp_path_factory, fmu_builder) -> dict[str, Path]:
    """name -> path of every test FMU (ball, stair, ticker, relay, zeno, failer, trivial)."""
    return fmu_builder.build_all(tmp_path_factory.mktemp("fmus"))


@pytest.fixture
def write_system(tmp_path, fmus):
    """write_system(text) -> path of a system TOML in tmp_path where '{name}' is replaced by that FMU's path."""

    def write(text: str, name: str = "system.toml") -> Path:
        for key, path in fmus.items():
            text = text.replace("{" + key + "}", str(path))
        p = tmp_path / name
        p.write_text(text)
        return p

    return write
