"""The C toolchain: the one place that knows the compilers, the house flags and how to run them.

Every C build robogen makes goes through here: generated FMUs (:mod:`robogen.codegen.binary`),
Python FMUs' shims (:mod:`robogen.pyfmu.build`), the master's C engine
(:mod:`robogen.cosim.engine`), and the test suite's own FMUs and C programs. It sits below
codegen, pyfmu and cosim and imports none of them.

- The host's compiler (for :data:`robogen.fmu.platforms.HOST`, ``x86_64-linux``) is ``$CC``
  (split like a shell word list, so ``CC="ccache gcc"`` works), else ``cc``.
- Every other platform robogen builds (:data:`robogen.fmu.platforms.BUILT`) is cross-compiled
  with ``zig cc`` from the ``ziglang`` package (``pip install 'robogen[cross]'``), for the target
  :data:`ZIG_TARGETS` names: glibc 2.17 on Linux, macOS 11, Windows through mingw-w64 and the
  UCRT. zig builds each target's C library once and keeps it in its global cache
  (``~/.cache/zig``, or ``$ZIG_GLOBAL_CACHE_DIR``): minutes the first time for Windows, seconds after.
- :data:`CFLAGS` are the house flags for code we write, on every platform: ``-std=c99 -Wall
  -Wextra -Wpedantic -Werror -fvisibility=hidden``. Code we do not write (cffi's generated
  module) gets :data:`FOREIGN_CFLAGS` instead. Headers we do not write (the FMI 3.0 headers)
  are passed as ``system_includes`` (``-isystem``): clang, which zig is, warns about their
  prototype-less callback types, which are the standard's, not ours.
- Cross builds carry no debug information and are stripped (:data:`CROSS_FLAGS`), so no path of
  the build machine ends up in a binary; a Mach-O library names itself ``@rpath/<file>`` instead of the
  path it was written to. With the same zig the same sources give the same bytes.
- ``sanitize=True`` adds :data:`SANITIZE_FLAGS` (AddressSanitizer and UndefinedBehaviorSanitizer),
  on the host only. Such a library loads only into a program that links the sanitizer runtime
  itself (a C test harness), not into a plain Python process.

A failed build raises :class:`~robogen.diagnostics.RobogenError` carrying the command and the
compiler's own output.
"""

from __future__ import annotations

import importlib.util
import os
import shlex
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Iterable, Mapping, Sequence

from robogen.diagnostics import RobogenError, Span
from robogen.fmu.platforms import HOST, Platform

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

#: zig's target for each platform robogen cross-compiles: the oldest C libraries zig offers that
#: today's systems still run (glibc 2.17; macOS 11, the first for Apple silicon), so a binary
#: loads on any current release.
ZIG_TARGETS: dict[str, str] = {
    "aarch64-linux": "aarch64-linux-gnu.2.17",
    "x86_64-windows": "x86_64-windows-gnu",
    "x86_64-darwin": "x86_64-macos.11.0",
    "aarch64-darwin": "aarch64-macos.11.0",
}

#: Flags of every cross build: no debug information (zig's default has it, with the build's
#: paths) and a stripped result (without it a Windows DLL names a PDB whose hash, stamped in the
#: DLL, depends on the temporary folder the build ran in).
CROSS_FLAGS: tuple[str, ...] = ("-g0", "-s")


def compiler(platform: Platform = HOST) -> list[str]:
    """The C compiler command for ``platform``: on the host ``$CC`` if set (a word list), else
    ``cc``; elsewhere ``zig cc`` for its :data:`ZIG_TARGETS` target."""
    if platform != HOST:
        return cross_compiler(platform)
    words = shlex.split(os.environ.get("CC", "") or "cc")
    if not words or shutil.which(words[0]) is None:
        raise RobogenError.at(f"C compiler '{' '.join(words) or 'cc'}' not found (set CC or install gcc)", None)
    return words


def cross_compiler(platform: Platform) -> list[str]:
    """``zig cc -target T`` for ``platform``, run by this Python from the ziglang package."""
    target = ZIG_TARGETS.get(platform.name)
    if target is None:
        raise RobogenError.at(f"robogen builds no binaries for {platform} (it builds "
                              f"{', '.join([HOST.name, *ZIG_TARGETS])})", None)
    if importlib.util.find_spec("ziglang") is None:
        raise RobogenError.at(f"building the {platform} binary needs zig, from the ziglang package, which is not "
                              "installed: pip install 'robogen[cross]'", None)
    return [sys.executable, "-m", "ziglang", "cc", "-target", target]


def platform_flags(platform: Platform, output: Path) -> list[str]:
    """What a shared library of ``platform`` written to ``output`` needs beyond the house flags."""
    if platform == HOST:
        return []
    if platform.format == "Mach-O":  # its install name, else the temporary path it was written to
        return [*CROSS_FLAGS, f"-Wl,-install_name,@rpath/{output.name}"]
    return list(CROSS_FLAGS)


def _failure(command: Sequence[str], returncode: int, output: str, what: str, span_path: Path | None) -> RobogenError:
    span = Span.whole_file(str(span_path)) if span_path is not None else None
    return RobogenError.at(f"compiling {what} failed (exit {returncode}):\n{shlex.join(command)}\n{output.strip()}", span)


def run_compiler(args: Sequence[str], what: str, span_path: Path | None = None, platform: Platform = HOST) -> None:
    """Run the compiler of ``platform`` with ``args``; on failure raise RobogenError with its output."""
    run_compilers([args], what, span_path, platform)


def run_compilers(jobs: Sequence[Sequence[str]], what: str, span_path: Path | None = None,
                  platform: Platform = HOST) -> None:
    """Run several compiler invocations at once (independent translation units), then report
    every failure together."""
    cc = compiler(platform)
    _run([([*cc, *args], what) for args in jobs], span_path)


def _run(commands: Sequence[tuple[Sequence[str], str]], span_path: Path | None) -> None:
    """Start every (command, what it builds) at once, wait for all, report every failure."""
    procs = []
    try:
        for command, what in commands:
            procs.append((command, what, subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                                          text=True)))
    except OSError as exc:
        for _, _, proc in procs:
            proc.kill()
            proc.wait()
        raise RobogenError.at(f"cannot run the C compiler for {what}: {exc}", None) from None
    failures = []
    for command, what, proc in procs:
        output, _ = proc.communicate()
        if proc.returncode != 0:
            failures.append(_failure(command, proc.returncode, output, what, span_path))
    if failures:
        raise RobogenError([d for f in failures for d in f.diagnostics])


def compile_shared(sources: Iterable[Path | str], output: Path | str, *, platform: Platform = HOST,
                   includes: Iterable[Path | str] = (), system_includes: Iterable[Path | str] = (),
                   defines: Iterable[str] = (), flags: Sequence[str] = CFLAGS, libs: Sequence[str] = LIBS,
                   sanitize: bool = False, extra: Iterable[str] = (), what: str | None = None,
                   span_path: Path | None = None) -> Path:
    """Compile and link C ``sources`` into the shared library ``output`` for ``platform`` (its
    folder is created)."""
    return compile_shared_all(sources, {platform: output}, includes=includes, system_includes=system_includes,
                              defines=defines, flags=flags, libs=libs, sanitize=sanitize, extra=extra, what=what,
                              span_path=span_path)[platform]


def compile_shared_all(sources: Iterable[Path | str], outputs: Mapping[Platform, Path | str], *,
                       includes: Iterable[Path | str] = (), system_includes: Iterable[Path | str] = (),
                       defines: Iterable[str] = (), flags: Sequence[str] = CFLAGS, libs: Sequence[str] = LIBS,
                       sanitize: bool = False, extra: Iterable[str] = (), what: str | None = None,
                       span_path: Path | None = None) -> dict[Platform, Path]:
    """Compile the same C ``sources`` into a shared library for each platform of ``outputs``, all
    compilers at once; every failure is reported, each naming its platform."""
    if sanitize and any(p != HOST for p in outputs):
        raise RobogenError.at("sanitizer builds are for the host only", None)
    common = [*flags, *OPTIMISE, *SHARED, *PIC, *(SANITIZE_FLAGS if sanitize else ()), *extra,
              *(f"-D{d}" for d in defines), *include_args(includes), *include_args(system_includes, "-isystem"),
              *map(str, sources)]
    done: dict[Platform, Path] = {}
    commands = []
    for platform, output in outputs.items():
        done[platform] = Path(output).resolve()
        done[platform].parent.mkdir(parents=True, exist_ok=True)
        label = f"{what or done[platform].name}{'' if platform == HOST else f' for {platform}'}"
        commands.append(([*compiler(platform), *common, *platform_flags(platform, done[platform]),
                          "-o", str(done[platform]), *libs], label))
    _run(commands, span_path)
    return done


def compile_program(sources: Iterable[Path | str], output: Path | str, *, platform: Platform = HOST,
                    includes: Iterable[Path | str] = (), system_includes: Iterable[Path | str] = (),
                    defines: Iterable[str] = (), libs: Sequence[str] = (), sanitize: bool = False,
                    extra: Iterable[str] = (), what: str | None = None) -> Path:
    """Compile and link C ``sources`` into the executable ``output`` for ``platform`` with the
    house flags."""
    if sanitize and platform != HOST:
        raise RobogenError.at("sanitizer builds are for the host only", None)
    output = Path(output).resolve()
    output.parent.mkdir(parents=True, exist_ok=True)
    args = [*CFLAGS, *(SANITIZE_FLAGS if sanitize else OPTIMISE), *(CROSS_FLAGS if platform != HOST else ()), *extra,
            *(f"-D{d}" for d in defines), *include_args(includes), *include_args(system_includes, "-isystem"),
            *map(str, sources), "-o", str(output), *libs]
    run_compiler(args, what or output.name, platform=platform)
    return output


def include_args(folders: Iterable[Path | str], flag: str = "-I") -> list[str]:
    """``-I`` (or ``flag``) options, in the order given (the first folder wins)."""
    out: list[str] = []
    for folder in folders:
        out += [flag, str(folder)]
    return out


def exported_symbols(library: Path | str) -> list[str]:
    """The names of the functions and data a shared library exports, sorted
    (:func:`robogen.fmu.binaries.read_binary`)."""
    from robogen.fmu.binaries import BinaryError, read_binary

    try:
        return sorted(read_binary(Path(library).read_bytes()).exports)
    except (OSError, BinaryError) as exc:
        raise RobogenError.at(f"cannot read the exports of {library}: {exc}", None) from None


__all__ = ["CFLAGS", "FOREIGN_CFLAGS", "SANITIZE_FLAGS", "LIBS", "ZIG_TARGETS", "CROSS_FLAGS", "compiler",
           "cross_compiler", "platform_flags", "run_compiler", "run_compilers", "compile_shared", "compile_shared_all",
           "compile_program", "include_args", "exported_symbols"]
