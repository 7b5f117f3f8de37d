"""Compile an FMU's binaries from its C sources (the generated files and the robogen runtime).

An FMU's C sources are one unity translation unit ``<modelIdentifier>.c`` that includes the
generated ``config.h`` and ``model.c`` and the hand-written runtime (``robogen_runtime.h``,
``robogen_machine.h``, which model.c includes, and ``robogen_runtime.c``, which includes its
``robogen_runtime_*.c`` parts; see :func:`runtime_dir` and :func:`runtime_sources`).
:func:`compile_fmu_binaries` compiles it, through :mod:`robogen.toolchain`, into the shared
library of each platform asked for, ``binaries/<tuple>/<modelIdentifier>.{so,dll,dylib}``; on the
host (:func:`compile_fmu_binary`)::

    $CC <house flags> -O2 -shared -fPIC -I <source_dir> -I <runtime_dir> -isystem <fmpy c-code> \\
        <source_dir>/<id>.c -o <id>.so -lm

The include order means a copy of the runtime inside ``source_dir`` (as in an FMU's
``sources/`` folder) wins over the installed one. The binary needs only the C library and its
maths, so no RPATH is set. :func:`build_binaries` goes from the FMU's files in memory to its
binaries' bytes: the sources are written to a temporary folder only for the compilers to read.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Iterable, Mapping, Sequence

from robogen import toolchain
from robogen.diagnostics import RobogenError
from robogen.fmu.headers import include_dir
from robogen.fmu.platforms import HOST, Platform


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
    """The include folders of a unity build: the sources, then the runtime (fmpy's FMI headers
    come after them, as system headers)."""
    return [Path(source_dir), runtime_dir()]


def compile_fmu_binary(
    source_dir: Path | str,
    model_identifier: str,
    output_so: Path | str,
    *,
    sanitize: bool = False,
    extra_cflags: Iterable[str] = (),
) -> Path:
    """Compile ``source_dir/<model_identifier>.c`` into the host's shared library ``output_so``.

    Creates the output folder if needed and returns the path of the library. Raises
    :class:`RobogenError` with the compiler's diagnostics if the build fails.
    """
    return compile_fmu_binaries(source_dir, model_identifier, {HOST: Path(output_so)}, sanitize=sanitize,
                                extra_cflags=extra_cflags)[HOST]


def compile_fmu_binaries(source_dir: Path | str, model_identifier: str, outputs: Mapping[Platform, Path], *,
                         sanitize: bool = False, extra_cflags: Iterable[str] = ()) -> dict[Platform, Path]:
    """Compile ``source_dir/<model_identifier>.c`` into the shared library of each platform of
    ``outputs`` (platform -> path), all at once."""
    source_dir = Path(source_dir).resolve()
    unit = source_dir / f"{model_identifier}.c"
    if not model_identifier.isidentifier():
        raise RobogenError.at(f"modelIdentifier '{model_identifier}' is not a C identifier", None)
    if not unit.is_file():
        raise RobogenError.at(f"the FMU's unity source {unit} does not exist", None)
    return toolchain.compile_shared_all([unit], outputs, includes=include_dirs(source_dir),
                                        system_includes=[include_dir()], sanitize=sanitize, extra=extra_cflags,
                                        what=f"FMU '{model_identifier}'", span_path=unit)


def build_binaries(sources: Mapping[str, str | bytes | os.PathLike], model_identifier: str,
                   platforms: Sequence[Platform]) -> dict[str, bytes]:
    """The FMU's binaries for ``platforms``, archive path -> bytes, compiled from the files of its
    ``sources/`` folder (name inside it -> text, bytes or a path to copy)."""
    with tempfile.TemporaryDirectory(prefix="robogen-build-") as tmp:
        folder = Path(tmp) / "sources"
        folder.mkdir()
        for name, content in sources.items():
            path = folder / name
            path.parent.mkdir(parents=True, exist_ok=True)
            if isinstance(content, str):
                path.write_text(content, encoding="utf-8")
            else:
                path.write_bytes(content if isinstance(content, bytes) else Path(content).read_bytes())
        outputs = {p: Path(tmp) / p.name / f"{model_identifier}{p.suffix}" for p in platforms}
        built = compile_fmu_binaries(folder, model_identifier, outputs)
        return {p.binary(model_identifier): built[p].read_bytes() for p in platforms}
