"""Fixtures of the IR's tests: the compiled test models and the drivers that run them on the FMU
and on the reference interpreter live with the code generator's tests (tests/codegen)."""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "codegen"))

from model_builds import builds, built  # noqa: E402, F401 - fixtures
