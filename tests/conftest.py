"""Shared fixtures. Tests that read ../shared run only when that folder exists."""

from __future__ import annotations

from pathlib import Path

import pytest

from support import ROOT, SHARED


def pytest_collection_modifyitems(config, items):
    if SHARED.is_dir():
        return
    skip = pytest.mark.skip(reason="../shared is not present beside the repository")
    for item in items:
        if "shared" in item.keywords:
            item.add_marker(skip)


@pytest.fixture
def repo_root() -> Path:
    return ROOT
