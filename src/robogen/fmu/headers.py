"""The official FMI 3.0 C headers and XSD schemas, taken from the installed fmpy package.

They are BSD-2-Clause and never copied into this repository: every build points the C compiler
at fmpy's ``c-code`` folder and every XSD check at fmpy's ``schema/fmi3`` folder.
"""

from __future__ import annotations

import importlib.resources
from pathlib import Path

from robogen.diagnostics import RobogenError
from robogen.fmu.platforms import HOST

HEADER_NAMES = ("fmi3Functions.h", "fmi3FunctionTypes.h", "fmi3PlatformTypes.h")
PLATFORM_TUPLE = HOST.name  # the host's folder of binaries/ (robogen.fmu.platforms)


def _fmpy_root() -> Path:
    try:
        return Path(str(importlib.resources.files("fmpy")))
    except ModuleNotFoundError:
        raise RobogenError.at("the fmpy package is not installed; it provides the FMI 3.0 headers and schemas", None) from None


def include_dir() -> Path:
    """The folder holding fmi3Functions.h and friends (the compiler's -I for FMI 3.0)."""
    folder = _fmpy_root() / "c-code"
    missing = [h for h in HEADER_NAMES if not (folder / h).is_file()]
    if missing:
        raise RobogenError.at(f"fmpy at {folder} lacks the FMI 3.0 headers {', '.join(missing)}", None)
    return folder


def schema_dir() -> Path:
    """The folder holding fmi3ModelDescription.xsd and the other FMI 3.0 schemas."""
    folder = _fmpy_root() / "schema" / "fmi3"
    if not (folder / "fmi3ModelDescription.xsd").is_file():
        raise RobogenError.at(f"fmpy at {folder} lacks the FMI 3.0 XSD schemas", None)
    return folder
