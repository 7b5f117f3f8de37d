"""Build the campaign tests' own FMUs: ``crasher`` (this folder) and the master's ``ticker``.

``crasher.c`` uses the test-FMU runtime of tests/cosim/fmus (framework.h) and that folder's
model-description writer, so the two kinds of test FMUs are built the same way.

    python tests/campaign/fmus/build.py OUTDIR
"""

from __future__ import annotations

import importlib.util
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
COSIM_FMUS = HERE.parents[1] / "cosim" / "fmus"
V = tuple
CRASHER = dict(vars=[
    V(("y", 1, "Float64", "output", "continuous", {})),
    V(("gain", 2, "Float64", "parameter", "fixed", {"start": "1.0"})),
    V(("crash_time", 3, "Float64", "parameter", "fixed", {"start": "-1"})),
    V(("hang_time", 4, "Float64", "parameter", "fixed", {"start": "-1"})),
    V(("delay", 5, "Float64", "parameter", "fixed", {"start": "0"})),
])


def cosim_builder():
    """tests/cosim/fmus/build.py as a module."""
    spec = importlib.util.spec_from_file_location("robogen_test_fmus_build", COSIM_FMUS / "build.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules.setdefault(spec.name, module)
    spec.loader.exec_module(module)
    return module


def build_crasher(outdir: Path) -> Path:
    from robogen import toolchain
    from robogen.fmu.archive import write_fmu
    from robogen.fmu.headers import include_dir

    cosim = cosim_builder()
    with tempfile.TemporaryDirectory() as tmp:
        so = Path(tmp) / "crasher.so"
        toolchain.compile_shared([HERE / "crasher.c"], so, includes=[include_dir(), COSIM_FMUS],
                                 defines=[f'MODEL_TOKEN="{cosim.token("crasher")}"'], what="test FMU crasher")
        return write_fmu(Path(outdir) / "crasher.fmu", {
            "modelDescription.xml": cosim.model_description("crasher", CRASHER),
            "binaries/x86_64-linux/crasher.so": so.read_bytes(),
            "sources/crasher.c": (HERE / "crasher.c").read_bytes(),
        })


def build_all(outdir: Path) -> dict[str, Path]:
    return {"crasher": build_crasher(outdir), "ticker": cosim_builder().build("ticker", Path(outdir))}


if __name__ == "__main__":
    for path in build_all(Path(sys.argv[1])).values():
        print(path)
