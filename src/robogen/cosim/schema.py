"""The schema the engine and Python share, taken from ``engine.h`` (its one definition).

cffi reads the header (:data:`ffi`): the layout of ``rg_plan`` and ``rg_engine``, the types of
the functions an instance is called through, and every enumeration, which this module turns into
Python enumerations (:class:`Kind`, :class:`Store`, :class:`ColumnKind`, :class:`End`,
:class:`By`): there is no second copy of any of them in Python.
"""

from __future__ import annotations

import importlib.resources
from enum import IntEnum

import cffi

from robogen.cosim.fmi3 import C_TYPES

#: The header of the plan and the engine.
HEADER = "engine.h"


def package_file(name: str) -> str:
    """A file of the engine's C source (this package's data)."""
    return (importlib.resources.files("robogen.cosim") / name).read_text(encoding="utf-8")


ffi = cffi.FFI()
ffi.cdef(package_file(HEADER))


def _enum(name: str, c_enum: str, prefix: str) -> type[IntEnum]:
    """The header's ``enum c_enum`` as a Python IntEnum, its members named without ``prefix``."""
    members = sorted(ffi.typeof(c_enum).relements.items(), key=lambda item: item[1])
    return IntEnum(name, {k.removeprefix(prefix): v for k, v in members})


#: How a value is held in C (enum rg_kind: K_F64 ... K_BINARY).
Kind = _enum("Kind", "enum rg_kind", "K_")
#: How the engine stores rows (enum rg_store).
Store = _enum("Store", "enum rg_store", "STORE_")
#: What a recorded column holds (enum rg_column).
ColumnKind = _enum("ColumnKind", "enum rg_column", "COL_")
#: Why rg_engine_run returned (enum rg_end).
End = _enum("End", "enum rg_end", "END_")
#: The call that asked to terminate (enum rg_by).
By = _enum("By", "enum rg_by", "BY_")

#: The signed integer kinds (a slot read back as int64).
SIGNED = frozenset(k for k in Kind if k.name.startswith("I"))
#: How Python reads a slot back, per kind: as a double, a signed or an unsigned 64-bit integer
#: (Strings and Binaries: the offset of their copy in the arena).
SLOT_FORMAT = {k: "d" if k in (Kind.F64, Kind.F32) else "q" if k in SIGNED or k == Kind.BOOL else "Q" for k in Kind}
_BY_C_TYPE = {"double": Kind.F64, "float": Kind.F32, "int64_t": Kind.I64, "uint64_t": Kind.U64, "int32_t": Kind.I32,
              "uint32_t": Kind.U32, "int16_t": Kind.I16, "uint16_t": Kind.U16, "int8_t": Kind.I8, "uint8_t": Kind.U8,
              "bool": Kind.BOOL, "const char*": Kind.STRING, "const uint8_t*": Kind.BINARY}


def kind(fmi_type: str) -> Kind:
    """How the engine holds a value of this FMI type (its C type, robogen.cosim.fmi3.C_TYPES)."""
    return _BY_C_TYPE[C_TYPES[fmi_type]]
