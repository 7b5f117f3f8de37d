"""The exported dynamic symbols of an ELF shared object, read without loading it.

Loading a third-party binary runs its constructors, so the validator parses the ELF file
instead: section headers, the ``.dynsym`` table and its string table. Only defined
(``st_shndx != 0``) global or weak symbols with default or protected visibility count.
"""

from __future__ import annotations

import struct

SHT_DYNSYM = 11
STB_GLOBAL, STB_WEAK = 1, 2
STV_DEFAULT, STV_PROTECTED = 0, 3


class ElfError(Exception):
    pass


def exported_symbols(data: bytes) -> set[str]:
    if data[:4] != b"\x7fELF":
        raise ElfError("not an ELF file")
    if data[4] != 2:
        raise ElfError("not a 64-bit ELF file")
    order = "<" if data[5] == 1 else ">"
    try:
        shoff, = struct.unpack_from(order + "Q", data, 0x28)
        shentsize, shnum, = struct.unpack_from(order + "HH", data, 0x3A)
        sections = []
        for i in range(shnum):
            off = shoff + i * shentsize
            name, stype, flags, addr, offset, size, link, info, align, entsize = struct.unpack_from(order + "IIQQQQIIQQ", data, off)
            sections.append((stype, offset, size, link, entsize))
        names: set[str] = set()
        for stype, offset, size, link, entsize in sections:
            if stype != SHT_DYNSYM or entsize == 0:
                continue
            _, str_off, str_size, _, _ = sections[link]
            strtab = data[str_off:str_off + str_size]
            for j in range(size // entsize):
                st_name, st_info, st_other, st_shndx, _value, _size = struct.unpack_from(order + "IBBHQQ", data, offset + j * entsize)
                if st_shndx == 0 or (st_info >> 4) not in (STB_GLOBAL, STB_WEAK) or (st_other & 3) not in (STV_DEFAULT, STV_PROTECTED):
                    continue
                end = strtab.find(b"\0", st_name)
                names.add(strtab[st_name:end].decode("ascii", "replace"))
        return names
    except (struct.error, IndexError) as exc:
        raise ElfError(f"truncated or malformed ELF file ({exc})") from None
