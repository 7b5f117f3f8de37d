"""Every shrunk failure the model fuzzer found (tests/fuzz/regressions) now has the property it
broke; the failures in code another branch of issue 23 owns (tests/fuzz/pending) still fail, as
expected until that branch is merged (strict: once one passes, move it to regressions)."""

from __future__ import annotations

from pathlib import Path

import pytest

from robogen.fuzz import regressions

HERE = Path(__file__).resolve().parent
FIXED = sorted((HERE / "regressions").glob("*.r*"))
PENDING = sorted((HERE / "pending").glob("*.r*"))


@pytest.mark.parametrize("path", FIXED, ids=[p.stem for p in FIXED])
def test_a_fixed_failure_stays_fixed(path, tmp_path):
    r = regressions.read(path)
    failure = regressions.check(r, tmp_path)
    assert failure is None, f"{path.name} breaks property {failure.prop} again ({failure.kind}):\n{failure.message}"


@pytest.mark.parametrize("path", PENDING, ids=[p.stem for p in PENDING])
def test_a_pending_failure_still_fails_until_its_branch_is_merged(path, tmp_path):
    r = regressions.read(path)
    failure = regressions.check(r, tmp_path)
    if failure is None:
        pytest.fail(f"{path.name} passes now: move it to tests/fuzz/regressions")
    assert (failure.prop, failure.kind) == (r.prop, r.kind), failure.message


def test_the_regression_files_name_their_property_and_seed():
    for path in FIXED + PENDING:
        r = regressions.read(path)
        assert r.prop in ("print", "check", "package", "differential", "sanitize") and r.seed, path
