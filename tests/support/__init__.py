"""What the test folders share: where the repository's files are, and helpers importable as
``support.<module>`` (pyproject's pytest ``pythonpath`` puts tests/ on the path once).

- :mod:`support.frontend`: the model corpus, AST walks and comparable diagnostics (syntax, semantics);
- :mod:`support.pyfmu`: driving FMUs through fmpy, and the C host (pyfmu, platforms);
- :mod:`support.harness`: the C programs on tests/harness/misuse_harness.h (runtime, pyfmu);
- :mod:`support.wheel`: building robogen's wheel from a copy of the sources;
- :mod:`support.campaign`: campaign folders and campaign processes (campaign);
- :mod:`support.ssp`: SSP archives checked against the SSP 2.0 schemas (cosim, examples).
"""

from __future__ import annotations

import os
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
#: ../shared beside the repository (ROBOGEN_SHARED names it elsewhere, e.g. for a git worktree)
SHARED = Path(os.environ.get("ROBOGEN_SHARED") or ROOT.parent / "shared")
REFERENCE_MODELS = SHARED / "reference-models"
