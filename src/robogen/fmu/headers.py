"""The official FMI 3.0 and 2.0 C headers and FMI 3.0 XSD schemas, taken from the installed fmpy package.

They are BSD-2-Clause and never copied into this repository: every build points the C compiler
at fmpy's ``c-code`` folder (the FMI 3.0 headers for robogen's FMUs; both versions' for the
master's interface adapters, robogen.cosim.interfaces) and every XSD check at fmpy's
``schema/fmi3`` folder.
"""

from __future__ import annotations

import importlib.resources
from pathlib import Path

from robogen.diagnostics import RobogenError
from robogen.fmu.platforms import HOST

HEADER_NAMES = ("fmi3Functions.h", "fmi3FunctionTypes.h", "fmi3PlatformTypes.h")
FMI2_HEADER_NAMES = ("fmi2Functions.h", "fmi2FunctionTypes.h", "fmi2TypesPlatform.h")
PLATFORM_TUPLE = HOST.name  # the host's folder of binaries/ (robogen.fmu.platforms)
#: FMI 2.0's name of the same platform (its binaries/ folder).
FMI2_PLATFORM = "linux64"


def _fmpy_root() -> Path:
    try:
        return Path(str(importlib.resources.files("fmpy")))
    except ModuleNotFoundError:
        raise RobogenError.at("the fmpy package is not installed; it provides the FMI 3.0 headers and schemas", None) from None


def include_dir(fmi2: bool = False) -> Path:
    """The folder holding fmi3Functions.h and friends (the compiler's -I for FMI 3.0; ``fmi2``: it
    must hold FMI 2.0's headers too)."""
    folder = _fmpy_root() / "c-code"
    missing = [h for h in HEADER_NAMES + (FMI2_HEADER_NAMES if fmi2 else ()) if not (folder / h).is_file()]
    if missing:
        raise RobogenError.at(f"fmpy at {folder} lacks the FMI headers {', '.join(missing)}", None)
    return folder


def sundials_libraries() -> tuple[Path, Path]:
    """SUNDIALS' core and CVode shared libraries as fmpy ships them for this platform (the master
    integrates Model Exchange FMUs with CVode through their C API)."""
    folder = _fmpy_root() / "sundials" / PLATFORM_TUPLE
    core, cvode = folder / "sundials_core.so", folder / "sundials_cvode.so"
    if not (core.is_file() and cvode.is_file()):
        raise RobogenError.at(f"fmpy at {folder.parent} lacks SUNDIALS' libraries for {PLATFORM_TUPLE} "
                              "(sundials_core.so, sundials_cvode.so): CVode is not available", None)
    return core, cvode


def schema_dir() -> Path:
    """The folder holding fmi3ModelDescription.xsd and the other FMI 3.0 schemas."""
    folder = _fmpy_root() / "schema" / "fmi3"
    if not (folder / "fmi3ModelDescription.xsd").is_file():
        raise RobogenError.at(f"fmpy at {folder} lacks the FMI 3.0 XSD schemas", None)
    return folder
