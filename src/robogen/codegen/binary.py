"""Compile an FMU binary from its C sources (the generated files and the robogen runtime).

An FMU's C sources are one unity translation unit ``<modelIdentifier>.c`` that includes the
generated ``config.h`` and ``model.c`` and the hand-written runtime (``robogen_runtime.h``,
``robogen_machine.h``, which model.c includes, and ``robogen_runtime.c``, which includes its
``robogen_runtime_*.c`` parts; see :func:`runtime_dir` and :func:`runtime_sources`). :func:`compile_fmu_binary` compiles it, through
:mod:`robogen.toolchain`, into the shared object that goes to
``binaries/x86_64-linux/<modelIdentifier>.so``::

    $CC <house flags> -O2 -shared -fPIC -I <source_dir> -I <runtime_dir> -I <fmpy c-code> \\
        <source_dir>/<id>.c -o <id>.so -lm

The include order means a copy of the runtime inside ``source_dir`` (as in an FMU's
``sources/`` folder) wins over the installed one. The binary needs only libc and libm, so no
RPATH is set.
"""

from __future__ import annotations

from pathlib import Path
from typing import Iterable

from robogen import toolchain
from robogen.diagnostics import RobogenError
from robogen.fmu.headers import include_dir


def runtime_dir() -> Path:
    """The folder holding ``robogen_runtime.h``, ``robogen_machine.h`` and ``robogen_runtime.c``."""
    folder = Path(__file__).resolve().parent.parent / "runtime"
    for name in ("robogen_runtime.h", "robogen_machine.h", "robogen_runtime.c"):
        if not (folder / name).is_file():
            raise RobogenError.at(f"the robogen runtime is incomplete: {folder / name} is missing", None)
    return folder


def runtime_sources() -> list[Path]:
    """Every runtime file an FMU's ``sources/`` folder must carry next to the generated files.

    ``model.c`` includes ``robogen_machine.h`` and ``robogen_runtime.c`` includes its parts
    (``robogen_runtime_*.c``) by relative path, so a packager copies all of these, and ``fmpy
    compile`` (or any importer) then needs no include path beyond ``sources/`` and the FMI headers.
    """
    folder = runtime_dir()
    return sorted(p for p in folder.iterdir() if p.name.startswith("robogen_") and p.suffix in (".c", ".h"))


def include_dirs(source_dir: Path) -> list[Path]:
    """The include folders of a unity build: the sources, then the runtime, then fmpy's FMI headers."""
    return [Path(source_dir), runtime_dir(), include_dir()]


def compile_fmu_binary(
    source_dir: Path | str,
    model_identifier: str,
    output_so: Path | str,
    *,
    sanitize: bool = False,
    extra_cflags: Iterable[str] = (),
) -> Path:
    """Compile ``source_dir/<model_identifier>.c`` into the shared object ``output_so``.

    Creates the output folder if needed and returns the path of the library. Raises
    :class:`RobogenError` with the compiler's diagnostics if the build fails.
    """
    source_dir = Path(source_dir).resolve()
    output_so = Path(output_so).resolve()
    unit = source_dir / f"{model_identifier}.c"
    if not model_identifier.isidentifier():
        raise RobogenError.at(f"modelIdentifier '{model_identifier}' is not a C identifier", None)
    if not unit.is_file():
        raise RobogenError.at(f"the FMU's unity source {unit} does not exist", None)
    return toolchain.compile_shared([unit], output_so, includes=include_dirs(source_dir), sanitize=sanitize,
                                    extra=extra_cflags, what=f"FMU '{model_identifier}'", span_path=unit)
