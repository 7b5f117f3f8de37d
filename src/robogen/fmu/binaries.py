"""What an FMU binary is, read without loading it: object format, machine, kind, exported names.

Loading a third-party binary runs its constructors (and a binary for another machine cannot be
loaded at all), so the validator reads the file instead, with LIEF, which parses ELF, PE and
Mach-O. :func:`read_binary` gives a :class:`BinaryInfo`:

- ``format``: ``ELF``, ``PE`` or ``Mach-O`` (the names :mod:`robogen.fmu.platforms` uses);
- ``arch``: the machine as an FMI 3.0 architecture name (``x86_64``, ``aarch64``...), or
  the format's own name for a machine FMI 3.0 does not name;
- ``kind``: ``shared library``, ``executable`` or ``object file``... (an FMU needs the first);
- ``exports``: the names of the functions and data it exports, as C spells them: an ELF file's
  defined global or weak dynamic symbols of default or protected visibility, a PE file's export
  table, a Mach-O file's export trie less the underscore Mach-O puts before every C name.

A Mach-O universal ("fat") file is read as the slice for ``arch`` when one is asked for.
"""

from __future__ import annotations

from dataclasses import dataclass

import lief

lief.logging.disable()  # LIEF reports a malformed file on stderr; the validator reports it itself

#: Names a linker defines in every Mach-O dylib (the image's own header): not code of the FMU.
MACHO_LINKER_NAMES = frozenset({"_mh_dylib_header", "__dso_handle"})

_ELF_ARCH = {"X86_64": "x86_64", "AARCH64": "aarch64", "I386": "x86", "ARM": "aarch32", "PPC": "ppc32", "PPC64": "ppc64"}
_PE_ARCH = {"AMD64": "x86_64", "ARM64": "aarch64", "I386": "x86", "ARMNT": "aarch32", "ARM": "aarch32"}
_MACHO_ARCH = {"X86_64": "x86_64", "ARM64": "aarch64", "X86": "x86", "ARM": "aarch32", "POWERPC": "ppc32", "POWERPC64": "ppc64"}


class BinaryError(Exception):
    """The file is no ELF, PE or Mach-O file, or one LIEF cannot read."""


@dataclass(frozen=True)
class BinaryInfo:
    format: str
    arch: str
    kind: str
    exports: frozenset[str]

    @property
    def shared(self) -> bool:
        return self.kind == "shared library"


def read_binary(data: bytes, arch: str | None = None) -> BinaryInfo:
    """The facts of the binary ``data`` (see the module's text); ``arch`` picks a fat Mach-O's slice."""
    raw = list(data)
    if lief.is_elf(raw):
        return _elf(_parse(lief.ELF.parse, data))
    if lief.is_pe(raw):
        return _pe(_parse(lief.PE.parse, data))
    if lief.is_macho(raw):
        return _macho(_parse(lief.MachO.parse, data), arch)
    raise BinaryError("not an ELF, PE or Mach-O file")


def _parse(parser, data: bytes):
    parsed = parser(data)
    if parsed is None:
        raise BinaryError("truncated or malformed file (LIEF cannot read it)")
    return parsed


def _name(value) -> str:
    return str(value).rsplit(".", 1)[-1]


def _elf(binary) -> BinaryInfo:
    header = binary.header
    machine = _name(header.machine_type)
    arch = _ELF_ARCH.get(machine, machine.lower())
    if machine == "RISCV":
        arch = "riscv64" if _name(header.identity_class) == "ELF64" else "riscv32"
    file_type = _name(header.file_type)
    if file_type == "DYN":  # a position-independent executable is DYN too, flagged PIE (glibc's own test)
        flags = binary.get(lief.ELF.DynamicEntry.TAG.FLAGS_1)
        pie = flags is not None and flags.has(lief.ELF.DynamicEntryFlags.FLAG.PIE)
        kind = "executable" if pie else "shared library"
    else:
        kind = {"EXEC": "executable", "REL": "object file", "CORE": "core dump"}.get(file_type, f"ELF file of type {file_type}")
    exports = frozenset(
        s.name for s in binary.dynamic_symbols
        if s.shndx != 0 and _name(s.binding) in ("GLOBAL", "WEAK") and _name(s.visibility) in ("DEFAULT", "PROTECTED"))
    return BinaryInfo("ELF", arch, kind, exports)


def _pe(binary) -> BinaryInfo:
    machine = _name(binary.header.machine)
    dll = binary.header.has_characteristic(lief.PE.Header.CHARACTERISTICS.DLL)
    export = binary.get_export() if binary.has_exports else None
    names = frozenset(e.name for e in export.entries if e.name) if export is not None else frozenset()
    return BinaryInfo("PE", _PE_ARCH.get(machine, machine.lower()), "shared library" if dll else "executable", names)


def _macho(fat, arch: str | None) -> BinaryInfo:
    slices = [fat.at(i) for i in range(fat.size)]
    chosen = slices[0]
    for binary in slices:
        if arch is not None and _MACHO_ARCH.get(_name(binary.header.cpu_type)) == arch:
            chosen = binary
    machine = _name(chosen.header.cpu_type)
    file_type = _name(chosen.header.file_type)
    kind = {"DYLIB": "shared library", "BUNDLE": "shared library", "EXECUTE": "executable",
            "OBJECT": "object file"}.get(file_type, f"Mach-O file of type {file_type}")
    names = frozenset(s.name[1:] if s.name.startswith("_") else s.name for s in chosen.exported_symbols)
    return BinaryInfo("Mach-O", _MACHO_ARCH.get(machine, machine.lower()), kind, names - MACHO_LINKER_NAMES)


__all__ = ["BinaryError", "BinaryInfo", "read_binary", "MACHO_LINKER_NAMES"]
