"""Building robogen's wheel the way a release would: from a copy of the sources, so that the
build writes nothing into the working tree, with pip and no dependencies."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

from support import ROOT

#: What a source distribution of robogen holds: the package, its grammars, the metadata.
SOURCES = ("src", "grammar", "pyproject.toml", "README.md")


def build_wheel(folder: Path) -> Path:
    """The wheel built from a copy of the sources in ``folder`` (its path)."""
    source = folder / "source"
    ignore = shutil.ignore_patterns("__pycache__", "*.pyc", "*.so", "*.egg-info")
    for name in SOURCES:
        if (ROOT / name).is_dir():
            shutil.copytree(ROOT / name, source / name, ignore=ignore)
        else:
            shutil.copy2(ROOT / name, source / name)
    dist = folder / "dist"
    result = subprocess.run([sys.executable, "-m", "pip", "wheel", str(source), "--no-deps", "--quiet",
                             "--wheel-dir", str(dist)], capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stdout + result.stderr
    (wheel,) = dist.glob("robogen-*.whl")
    return wheel
