"""The C toolchain: the one place that knows the compiler, the house flags and how to run them.

Every C build robogen makes goes through here: generated FMUs (:mod:`robogen.codegen.binary`),
Python FMUs' shims (:mod:`robogen.pyfmu.build`), the master's C engine
(:mod:`robogen.cosim.engine`), and the test suite's own FMUs and C programs. It sits below
codegen, pyfmu and cosim and imports none of them.

- The compiler is ``$CC`` (split like a shell word list, so ``CC="ccache gcc"`` works), else ``cc``.
- :data:`CFLAGS` are the house flags for code we write: ``-std=c99 -Wall -Wextra -Wpedantic
  -Werror -fvisibility=hidden``. Code we do not write (cffi's generated module) gets
  :data:`FOREIGN_CFLAGS` instead.
- ``sanitize=True`` adds :data:`SANITIZE_FLAGS` (AddressSanitizer and UndefinedBehaviorSanitizer).
  Such a library loads only into a program that links the sanitizer runtime itself (a C test
  harness), not into a plain Python process.
- The FMI 3.0 headers always come from the installed fmpy (:func:`robogen.fmu.headers.include_dir`).

A failed build raises :class:`~robogen.diagnostics.RobogenError` carrying the command and the
compiler's own output.
"""

from __future__ import annotations

import os
import shlex
import shutil
import subprocess
from pathlib import Path
from typing import Iterable, Sequence

from robogen.diagnostics import RobogenError, Span

#: The house warning and language flags: every FMU and every C program of ours is built with them.
CFLAGS: tuple[str, ...] = ("-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-fvisibility=hidden")

#: Flags for C that robogen does not write (cffi's generated module): not ours to lint.
FOREIGN_CFLAGS: tuple[str, ...] = ("-fvisibility=hidden", "-w")

#: Code generation of a shared object.
OPTIMISE: tuple[str, ...] = ("-O2",)
PIC: tuple[str, ...] = ("-fPIC",)
SHARED: tuple[str, ...] = ("-shared",)

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

#: Libraries every FMU may link (models may use <math.h>).
LIBS: tuple[str, ...] = ("-lm",)


def compiler() -> list[str]:
    """The C compiler command: ``$CC`` if set (a word list), else ``cc``."""
    words = shlex.split(os.environ.get("CC", "") or "cc")
    if not words or shutil.which(words[0]) is None:
        raise RobogenError.at(f"C compiler '{' '.join(words) or 'cc'}' not found (set CC or install gcc)", None)
    return words


def _failure(command: Sequence[str], returncode: int, output: str, what: str, span_path: Path | None) -> RobogenError:
    span = Span.whole_file(str(span_path)) if span_path is not None else None
    return RobogenError.at(f"compiling {what} failed (exit {returncode}):\n{shlex.join(command)}\n{output.strip()}", span)


def run_compiler(args: Sequence[str], what: str, span_path: Path | None = None) -> None:
    """Run the compiler with ``args``; on failure raise RobogenError with its output."""
    run_compilers([args], what, span_path)


def run_compilers(jobs: Sequence[Sequence[str]], what: str, span_path: Path | None = None) -> None:
    """Run several compiler invocations at once (independent translation units), then report
    every failure together."""
    cc = compiler()
    commands = [[*cc, *args] for args in jobs]
    procs = []
    try:
        for command in commands:
            procs.append((command, subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)))
    except OSError as exc:
        for _, proc in procs:
            proc.kill()
            proc.wait()
        raise RobogenError.at(f"cannot run the C compiler for {what}: {exc}", None) from None
    failures = []
    for command, proc in procs:
        output, _ = proc.communicate()
        if proc.returncode != 0:
            failures.append(_failure(command, proc.returncode, output, what, span_path))
    if failures:
        raise RobogenError([d for f in failures for d in f.diagnostics])


def compile_shared(sources: Iterable[Path | str], output: Path | str, *, includes: Iterable[Path | str] = (),
                   defines: Iterable[str] = (), flags: Sequence[str] = CFLAGS, libs: Sequence[str] = LIBS,
                   sanitize: bool = False, extra: Iterable[str] = (), what: str | None = None,
                   span_path: Path | None = None) -> Path:
    """Compile and link C ``sources`` into the shared object ``output`` (its folder is created)."""
    output = Path(output).resolve()
    output.parent.mkdir(parents=True, exist_ok=True)
    args = [*flags, *OPTIMISE, *SHARED, *PIC, *(SANITIZE_FLAGS if sanitize else ()), *extra,
            *(f"-D{d}" for d in defines), *include_args(includes), *map(str, sources), "-o", str(output), *libs]
    run_compiler(args, what or output.name, span_path)
    return output


def compile_program(sources: Iterable[Path | str], output: Path | str, *, includes: Iterable[Path | str] = (),
                    defines: Iterable[str] = (), libs: Sequence[str] = (), sanitize: bool = False,
                    extra: Iterable[str] = (), what: str | None = None) -> Path:
    """Compile and link C ``sources`` into the executable ``output`` with the house flags."""
    output = Path(output).resolve()
    output.parent.mkdir(parents=True, exist_ok=True)
    args = [*CFLAGS, *(SANITIZE_FLAGS if sanitize else OPTIMISE), *extra, *(f"-D{d}" for d in defines),
            *include_args(includes), *map(str, sources), "-o", str(output), *libs]
    run_compiler(args, what or output.name)
    return output


def include_args(folders: Iterable[Path | str]) -> list[str]:
    """``-I`` flags, in the order given (the first folder wins)."""
    out: list[str] = []
    for folder in folders:
        out += ["-I", str(folder)]
    return out


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


__all__ = ["CFLAGS", "FOREIGN_CFLAGS", "SANITIZE_FLAGS", "LIBS", "compiler", "run_compiler", "run_compilers",
           "compile_shared", "compile_program", "include_args", "exported_symbols"]
