"""Fixtures for the platform tests: the UR5e platform and controller FMUs packaged once per
session, and the C host of tests/pyfmu compiled once per session."""

from __future__ import annotations

from pathlib import Path

import pytest

from robogen.pyfmu.build import package
from support import ROOT
from support.pyfmu import compile_host

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
    return compile_host(tmp_path_factory.mktemp("host"))
