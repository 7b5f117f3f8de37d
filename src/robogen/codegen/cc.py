"""The one place that compiles an FMU binary from its C sources.

An FMU's C sources are one unity translation unit ``<modelIdentifier>.c`` that includes the
generated ``config.h`` and ``model.c`` and the hand-written runtime (``robogen_runtime.h`` and
``robogen_runtime.c``, which includes its ``robogen_runtime_*.c`` parts; see :func:`runtime_dir`
and :func:`runtime_sources`). This module compiles it into the shared object
that goes to ``binaries/x86_64-linux/<modelIdentifier>.so``::

    cc -std=c99 -Wall -Wextra -Wpedantic -Werror -fvisibility=hidden -O2 -shared -fPIC \\
       -I <source_dir> -I <runtime_dir> -I <fmpy c-code> <source_dir>/<id>.c -o <id>.so -lm

The include order means a copy of the runtime inside ``source_dir`` (as in an FMU's
``sources/`` folder) wins over the installed one. The FMI headers always come from the installed
fmpy (:func:`robogen.fmu.headers.include_dir`); they are never copied. The binary needs only libc
and libm, so no RPATH is set.

``sanitize=True`` adds AddressSanitizer and UndefinedBehaviorSanitizer. Such a library can only
be loaded by a program that links the sanitizer runtime itself (a C test harness), not by a plain
Python process.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path
from typing import Iterable, Sequence

from robogen.diagnostics import RobogenError, Span
from robogen.fmu.headers import include_dir

#: The house warning and language flags every FMU (and every C test program) is built with.
CFLAGS: tuple[str, ...] = ("-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-fvisibility=hidden")

#: Flags that make a shared object out of the unity translation unit.
SHARED_FLAGS: tuple[str, ...] = ("-O2", "-shared", "-fPIC")

#: Sanitizer flags for test builds: stop at the first finding, keep stack traces readable.
#: float-cast-overflow (a real too large for the integer it is converted to) is not part of
#: GCC's "undefined" group.
SANITIZE_FLAGS: tuple[str, ...] = (
    "-fsanitize=address,undefined",
    "-fsanitize=float-cast-overflow",
    "-fno-sanitize-recover=all",
    "-fno-omit-frame-pointer",
    "-g",
)

#: Libraries every FMU may link (the model may use <math.h>).
LIBS: tuple[str, ...] = ("-lm",)


def runtime_dir() -> Path:
    """The folder holding ``robogen_runtime.h`` and ``robogen_runtime.c``."""
    folder = Path(__file__).resolve().parent.parent / "runtime"
    for name in ("robogen_runtime.h", "robogen_runtime.c"):
        if not (folder / name).is_file():
            raise RobogenError.at(f"the robogen runtime is incomplete: {folder / name} is missing", None)
    return folder


def runtime_sources() -> list[Path]:
    """Every runtime file an FMU's ``sources/`` folder must carry next to the generated files.

    ``robogen_runtime.c`` includes its parts (``robogen_runtime_*.c``) by relative path, so a
    packager copies all of these, and ``fmpy compile`` (or any importer) then needs no include
    path beyond ``sources/`` and the FMI headers.
    """
    folder = runtime_dir()
    return sorted(p for p in folder.iterdir() if p.name.startswith("robogen_runtime") and p.suffix in (".c", ".h"))


def compiler() -> str:
    """The C compiler: ``$CC`` if set, else ``cc``."""
    name = os.environ.get("CC", "cc")
    if shutil.which(name) is None:
        raise RobogenError.at(f"C compiler '{name}' not found (set CC or install gcc)", None)
    return name


def include_flags(source_dir: Path) -> list[str]:
    """``-I`` flags of a unity build: the sources, then the runtime, then fmpy's FMI headers."""
    return ["-I", str(source_dir), "-I", str(runtime_dir()), "-I", str(include_dir())]


def run_compiler(args: Sequence[str], what: str, span_path: Path | None = None) -> None:
    """Run the compiler; on failure raise RobogenError carrying the compiler's own output."""
    command = [compiler(), *args]
    try:
        result = subprocess.run(command, capture_output=True, text=True, check=False)
    except OSError as error:
        raise RobogenError.at(f"cannot run the C compiler for {what}: {error}", None) from None
    if result.returncode != 0:
        output = (result.stderr + result.stdout).strip()
        span = Span.whole_file(str(span_path)) if span_path is not None else None
        raise RobogenError.at(
            f"compiling {what} failed (exit {result.returncode}):\n{' '.join(command)}\n{output}", span
        )


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
    output_so.parent.mkdir(parents=True, exist_ok=True)
    args = [
        *CFLAGS,
        *SHARED_FLAGS,
        *(SANITIZE_FLAGS if sanitize else ()),
        *extra_cflags,
        *include_flags(source_dir),
        str(unit),
        "-o",
        str(output_so),
        *LIBS,
    ]
    run_compiler(args, f"FMU '{model_identifier}'", unit)
    return output_so


def exported_symbols(so_path: Path | str) -> list[str]:
    """The names of the functions and data a shared object exports (``nm -D --defined-only``)."""
    nm = shutil.which("nm")
    if nm is None:
        raise RobogenError.at("'nm' (binutils) is needed to list a library's exported symbols", None)
    result = subprocess.run([nm, "-D", "--defined-only", str(so_path)], capture_output=True, text=True, check=False)
    if result.returncode != 0:
        raise RobogenError.at(f"nm failed on {so_path}: {result.stderr.strip()}", None)
    names = []
    for line in result.stdout.splitlines():
        fields = line.split()
        # "<address> <type> <name>"; global (upper-case type) symbols only
        if len(fields) == 3 and fields[1].isupper():
            names.append(fields[2])
    return sorted(names)
