"""Fixtures for the platform tests: the UR5e platform and controller FMUs packaged once per
session, and the C host of tests/pyfmu compiled once per session."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT / "tests" / "pyfmu") not in sys.path:
    sys.path.insert(0, str(ROOT / "tests" / "pyfmu"))  # pyfmu_testing: the fmpy and C-host helpers

import pyfmu_testing  # noqa: E402

from robogen.pyfmu.build import package  # noqa: E402

PLAN = ROOT / "models" / "ur5e" / "plan.toml"


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
    return pyfmu_testing.compile_host(tmp_path_factory.mktemp("host"))
