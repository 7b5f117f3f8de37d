"""FMI 3.0 platform tuples: which folder of ``binaries/`` holds a binary for which machine.

A platform tuple is ``<arch>-<sys>`` (FMI 3.0, section 2.5.1): ``x86_64-linux``,
``aarch64-darwin``... Its system fixes the binary's file name suffix and object format (Linux:
``.so``, ELF; Windows: ``.dll``, PE; macOS: ``.dylib``, Mach-O) and its architecture the machine
the binary's code is for. This module knows those facts and nothing about compilers: the C
toolchain (:mod:`robogen.toolchain`) builds for the :data:`BUILT` platforms, the validator
(:mod:`robogen.fmu.validate`) checks any tuple it finds against them.
"""

from __future__ import annotations

from dataclasses import dataclass

from robogen.diagnostics import RobogenError

#: FMI 3.0's architectures and systems.
ARCHITECTURES = ("aarch32", "aarch64", "riscv32", "riscv64", "x86", "x86_64", "ppc32", "ppc64")
SYSTEMS = ("darwin", "linux", "windows")

SUFFIX = {"linux": ".so", "windows": ".dll", "darwin": ".dylib"}
FORMAT = {"linux": "ELF", "windows": "PE", "darwin": "Mach-O"}


@dataclass(frozen=True)
class Platform:
    """One FMI 3.0 platform tuple."""

    arch: str
    system: str

    @property
    def name(self) -> str:
        """The tuple, the name of the platform's folder in ``binaries/``."""
        return f"{self.arch}-{self.system}"

    @property
    def suffix(self) -> str:
        return SUFFIX[self.system]

    @property
    def format(self) -> str:
        """The object format a shared library of this system has: ELF, PE or Mach-O."""
        return FORMAT[self.system]

    def binary(self, model_identifier: str) -> str:
        """The archive path of the binary of ``model_identifier`` for this platform."""
        return f"binaries/{self.name}/{model_identifier}{self.suffix}"

    def __str__(self) -> str:
        return self.name


def parse_tuple(name: str) -> Platform | None:
    """The platform named by an FMI 3.0 tuple, or None if ``name`` is not one."""
    arch, sep, system = name.rpartition("-")
    if sep and arch in ARCHITECTURES and system in SYSTEMS:
        return Platform(arch, system)
    return None


#: The platforms robogen builds generated FMUs for (``robogen package --platforms all``), the host first.
BUILT: tuple[Platform, ...] = (Platform("x86_64", "linux"), Platform("aarch64", "linux"), Platform("x86_64", "windows"),
                               Platform("x86_64", "darwin"), Platform("aarch64", "darwin"))

#: The platform robogen runs on: its system C compiler builds this platform's binary, and the
#: master loads it. robogen is made for x86_64 Linux; on another machine the system compiler's
#: output would not match this folder, which the validator reports.
HOST: Platform = BUILT[0]


def select(text: str, option: str = "--platforms") -> tuple[Platform, ...]:
    """The platforms a ``--platforms`` value names: ``all`` (every :data:`BUILT` platform) or a
    comma-separated list of tuples, in the order given, each once."""
    names = [n.strip() for n in text.split(",")]
    if names == ["all"]:
        return BUILT
    known = {p.name: p for p in BUILT}
    chosen: list[Platform] = []
    for name in names:
        if name not in known:
            what = "is not an FMI 3.0 platform tuple" if parse_tuple(name) is None else "is not one robogen builds"
            raise RobogenError.at(f"{option} {text}: '{name}' {what} (choose from {', '.join(known)}, or all)", None)
        if known[name] in chosen:
            raise RobogenError.at(f"{option} {text}: '{name}' is named twice", None)
        chosen.append(known[name])
    return tuple(chosen)


__all__ = ["ARCHITECTURES", "SYSTEMS", "Platform", "parse_tuple", "BUILT", "HOST", "select"]
