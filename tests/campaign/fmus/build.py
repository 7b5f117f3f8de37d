"""Build the campaign tests' own FMUs: ``crasher`` (this folder) and the master's ``ticker``.

``crasher.c`` uses the test-FMU runtime of tests/cosim/fmus (framework.h) and that folder's
model-description writer, so the two kinds of test FMUs are built the same way.

    python tests/campaign/fmus/build.py OUTDIR
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
COSIM_FMUS = HERE.parents[1] / "cosim" / "fmus"
def cosim_builder():
    """tests/cosim/fmus/build.py as a module."""
    spec = importlib.util.spec_from_file_location("robogen_test_fmus_build", COSIM_FMUS / "build.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules.setdefault(spec.name, module)
    spec.loader.exec_module(module)
    return module


def build_crasher(outdir: Path) -> Path:
    cosim = cosim_builder()
    spec = dict(vars=[
        cosim.var("y", 1, "Float64", "output", "continuous"),
        cosim.var("gain", 2, "Float64", "parameter", "fixed", start="1.0"),
        cosim.var("crash_time", 3, "Float64", "parameter", "fixed", start="-1"),
        cosim.var("hang_time", 4, "Float64", "parameter", "fixed", start="-1"),
        cosim.var("delay", 5, "Float64", "parameter", "fixed", start="0"),
    ])
    return cosim.build("crasher", Path(outdir), spec=spec, source=HERE / "crasher.c")


def build_all(outdir: Path) -> dict[str, Path]:
    return {"crasher": build_crasher(outdir), "ticker": cosim_builder().build("ticker", Path(outdir))}


if __name__ == "__main__":
    for path in build_all(Path(sys.argv[1])).values():
        print(path)
