"""ruff, with the rules of pyproject.toml ([tool.ruff]), finds nothing in the repository.

A test rather than a step of the Makefile: ``make test``, CI and a bare ``python -m pytest`` all
run it, and a finding shows as one failing test with ruff's own located report. Among the rules:
SLF001, no module reads a private member (``x._name``) of an object other than its own.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def _ruff() -> list[str]:
    beside = Path(sys.executable).parent / "ruff"  # installed with the test extra into this environment
    found = str(beside) if beside.is_file() else shutil.which("ruff")
    assert found is not None, "ruff is not installed: `make venv` installs the test extra (pip install -e '.[test]')"
    return [found]


def test_ruff_finds_nothing():
    proc = subprocess.run([*_ruff(), "check", "--no-cache", "--output-format", "concise", "."], cwd=ROOT,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_ruff_reads_the_private_member_rule_from_pyproject(tmp_path):
    # The rule is on: a module reading another object's private member is a finding.
    (tmp_path / "pyproject.toml").write_text((ROOT / "pyproject.toml").read_text())
    (tmp_path / "peek.py").write_text("def peek(other):\n    return other._secret\n")
    proc = subprocess.run([*_ruff(), "check", "--no-cache", "--output-format", "concise", "peek.py"], cwd=tmp_path,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 1 and "SLF001" in proc.stdout, proc.stdout + proc.stderr
