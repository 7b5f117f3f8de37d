"""Fixtures of the cross-platform tests: the UR5e d-model packaged once for every platform robogen
builds, and the trace host built for the platforms that can run here.

These builds are the only cross builds of the suite, so zig builds each platform's C library once
per machine (the first Windows build takes minutes; zig keeps it in its global cache, outside the
repository, for every later run). Without the ziglang package (pip install 'robogen[cross]') the
tests of this folder skip, saying so.
"""

from __future__ import annotations

import importlib.util
import zipfile
from dataclasses import dataclass
from pathlib import Path

import pytest

from robogen.cli import main
from robogen.codegen.api import lower_paths
from robogen.ir import model as ir
from robogen.ir.lower import LoweringOptions

from support.codegen_models import UR5E
from support.trace_host import build_host

CROSS = importlib.util.find_spec("ziglang") is not None


@dataclass
class Packaged:
    """The UR5e d-model packaged for every platform: the archive, unzipped, and its IR."""

    archive: Path
    folder: Path
    fmu: ir.Fmu
    identifier: str

    def binary(self, platform) -> Path:
        return self.folder / platform.binary(self.identifier)


@pytest.fixture(scope="session")
def ur5e_everywhere(tmp_path_factory) -> Packaged:
    if not CROSS:
        pytest.skip("the ziglang package is not installed (pip install 'robogen[cross]'; make test installs it)")
    work = tmp_path_factory.mktemp("everywhere")
    archive = work / "ur5e.fmu"
    assert main(["package", str(UR5E), "--platforms", "all", "-o", str(archive)]) == 0
    folder = work / "unzipped"
    with zipfile.ZipFile(archive) as z:
        z.extractall(folder)
    fmu, _ = lower_paths([UR5E], options=LoweringOptions())
    return Packaged(archive, folder, fmu, fmu.model_identifier)


@pytest.fixture(scope="session")
def trace_hosts(tmp_path_factory, ur5e_everywhere):
    """The trace host of each platform robogen runs binaries of here (built on demand)."""
    folder = tmp_path_factory.mktemp("hosts")
    built: dict = {}

    def host(platform) -> Path:
        if platform not in built:
            built[platform] = build_host(platform, folder)
        return built[platform]

    return host


@pytest.fixture(scope="session")
def wine_prefix(tmp_path_factory):
    """wine's configuration folder for this session (created by the first run, ~30 s); its
    wineserver is told to end with the session."""
    prefix = tmp_path_factory.mktemp("wine")
    yield prefix
    from support.trace_host import end_wineserver

    end_wineserver(prefix)

