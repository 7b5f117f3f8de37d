"""Fixtures of the campaign tests: the test FMUs (built once per session) and campaign folders."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

from support.campaign import CAMPAIGN, EXTRA_METRICS, SYSTEM, run_quietly, write_campaign_folder

HERE = Path(__file__).resolve().parent


@pytest.fixture(scope="session")
def two_worker_run(tmp_path_factory, campaign_fmus):
    """The test campaign on a local cluster of two workers: (campaign file, result, runs table)."""
    import pyarrow.parquet as pq

    folder = tmp_path_factory.mktemp("two-workers")
    campaign = write_campaign_folder(folder, campaign_fmus, CAMPAIGN, **{"extra_metrics.py": EXTRA_METRICS})
    result = run_quietly(campaign, folder / "out", workers=2)
    return campaign, result, pq.read_table(folder / "out" / "runs.parquet")


def _builder():
    spec = importlib.util.spec_from_file_location("robogen_campaign_test_fmus", HERE / "fmus" / "build.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="session")
def campaign_fmus(tmp_path_factory) -> dict[str, Path]:
    return _builder().build_all(tmp_path_factory.mktemp("campaign-fmus"))


@pytest.fixture
def campaign_dir(tmp_path, campaign_fmus):
    """write(campaign_text, system_text=SYSTEM, **files) -> the campaign file, in a folder that also
    holds crasher.fmu, ticker.fmu, system.toml and the given files (name -> text)."""

    def write(text: str, system: str = SYSTEM, **files: str) -> Path:
        return write_campaign_folder(tmp_path, campaign_fmus, text, system, **files)

    return write
