"""Writing .fmu archives: deterministic ZIP files laid out as FMI 3.0 section 2.5 asks.

Entries are sorted, timestamps fixed and permissions normalised, so the same inputs give a
byte-identical archive. Only deflate is used, paths use forward slashes, no links.
"""

from __future__ import annotations

import os
import zipfile
from pathlib import Path
from typing import Mapping

from robogen.outputs import replacing

FIXED_DATE = (1980, 1, 1, 0, 0, 0)


def write_fmu(target: str | os.PathLike, files: Mapping[str, bytes | str | os.PathLike]) -> Path:
    """Write ``target`` from archive names to contents (bytes, text, or a path to copy).

    Names are archive paths such as ``modelDescription.xml`` or ``binaries/x86_64-linux/m.so``.
    The archive is written under a unique temporary name first, then renamed
    (:func:`robogen.outputs.replacing`), so a failure never leaves a truncated .fmu behind and
    parallel writers of one target never share a file.
    """
    target = Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    with replacing(target) as tmp, zipfile.ZipFile(tmp, "w", compression=zipfile.ZIP_DEFLATED) as z:
        for name in sorted(files):
            _check_name(name)
            content = files[name]
            if isinstance(content, str):
                data = content.encode("utf-8")
            elif isinstance(content, bytes):
                data = content
            else:
                data = Path(content).read_bytes()
            info = zipfile.ZipInfo(name, date_time=FIXED_DATE)
            info.compress_type = zipfile.ZIP_DEFLATED
            executable = name.endswith((".so", ".dll", ".dylib"))
            info.external_attr = (0o100755 if executable else 0o100644) << 16
            info.create_system = 3  # Unix, so the permission bits above are meaningful
            z.writestr(info, data)
    return target


def _check_name(name: str) -> None:
    if not name or name.startswith("/") or "\\" in name or any(p in ("", ".", "..") for p in name.split("/")):
        raise ValueError(f"invalid archive member name {name!r}")
