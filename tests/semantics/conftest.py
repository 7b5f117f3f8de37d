"""The shared helpers of tests/models/frontend_testing.py, importable from the tests here."""

from __future__ import annotations

import sys
from pathlib import Path

MODELS = Path(__file__).resolve().parent.parent / "models"
if str(MODELS) not in sys.path:
    sys.path.insert(0, str(MODELS))
