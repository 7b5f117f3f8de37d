"""Fixtures for the platform tests: the UR5e platform and controller FMUs packaged once per
session, and the C host of tests/pyfmu compiled once per session."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

from robogen.pyfmu.build import package

ROOT = Path(__file__).resolve().parents[2]
PLAN = ROOT / "models" / "ur5e" / "plan.toml"


def _load_testing():
    name = "robogen_pyfmu_testing"  # unique: other test folders have their own helpers
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, ROOT / "tests" / "pyfmu" / "pyfmu_testing.py")
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]


testing = _load_testing()


@pytest.fixture(scope="session")
def platform_fmu(tmp_path_factory) -> Path:
    return package("robogen.platforms.ur5e:UR5ePlatform", tmp_path_factory.mktemp("platform") / "ur5e_platform.fmu",
                   ["sample_period=0.5"]).path


@pytest.fixture(scope="session")
def controller_fmu(tmp_path_factory) -> Path:
    return package("robogen.platforms.controller:PlanController",
                   tmp_path_factory.mktemp("controller") / "ur5e_controller.fmu", [f"plan={PLAN}"]).path


@pytest.fixture(scope="session")
def host(tmp_path_factory) -> Path:
    return testing.compile_host(tmp_path_factory.mktemp("host"))
