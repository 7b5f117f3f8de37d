"""Every shrunk failure the model fuzzer found (tests/fuzz/regressions) now has the property it
broke."""

from __future__ import annotations

from pathlib import Path

import pytest

from robogen.fuzz import regressions

HERE = Path(__file__).resolve().parent
FIXED = sorted((HERE / "regressions").glob("*.r*"))


@pytest.mark.parametrize("path", FIXED, ids=[p.stem for p in FIXED])
def test_a_fixed_failure_stays_fixed(path, tmp_path):
    r = regressions.read(path)
    failure = regressions.check(r, tmp_path)
    assert failure is None, f"{path.name} breaks property {failure.prop} again ({failure.kind}):\n{failure.message}"


def test_the_regression_files_name_their_property_and_seed():
    for path in FIXED:
        r = regressions.read(path)
        assert r.prop in ("print", "check", "package", "differential", "sanitize") and r.seed, path
    assert FIXED  # (the test above is parametrized by them: none found would pass it vacuously)
