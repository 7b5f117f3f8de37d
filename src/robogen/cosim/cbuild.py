"""The master's own C libraries (the engine, the interface adapters): their source put together
from this package's files, compiled once with the system compiler and cached by the hash of that
source under ``$XDG_CACHE_HOME/robogen`` (or ``~/.cache/robogen``; a temporary folder where the
home is read-only)."""

from __future__ import annotations

import hashlib
import os
import re
import tempfile
from pathlib import Path
from typing import Iterable

_INCLUDE = re.compile(r'#include "(\w+\.h)"')


def package_source(files: Iterable[str], read) -> bytes:
    """The files (of this package, ``read(name)`` their text) as one unit, each from its own line 1
    for the compiler's messages, with this package's headers in place of their #include lines (an
    #include of a header that ``read`` does not know is kept: the compiler's include path finds it)."""
    parts = []
    for name in files:
        parts.append(f'#line 1 "{name}"\n')
        for number, line in enumerate(read(name).splitlines(keepends=True), 1):
            included = _INCLUDE.fullmatch(line.strip())
            header = _own(read, included[1]) if included else None
            if header is not None:
                parts += [f'#line 1 "{included[1]}"\n', header, f'#line {number + 1} "{name}"\n']
            else:
                parts.append(line)
    return "".join(parts).encode()


def _own(read, name: str) -> str | None:
    try:
        return read(name)
    except (FileNotFoundError, OSError):
        return None


def cache_folders() -> list[Path]:
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    fallback = Path(tempfile.gettempdir()) / f"robogen-{os.getuid() if hasattr(os, 'getuid') else 'user'}"
    return [Path(base) / "robogen", fallback]


def cached_library(prefix: str, source: bytes, compile_to) -> Path:
    """The library of this source, ``prefix-HASH.so`` in the first cache folder that can hold it,
    built by ``compile_to(c_file, so_file)`` where it is not there yet (the last failure raised)."""
    name = f"{prefix}-{hashlib.sha256(source).hexdigest()[:16]}.so"
    failure: Exception | None = None
    for folder in cache_folders():
        target = folder / name
        if target.is_file():
            return target
        try:
            target.parent.mkdir(parents=True, exist_ok=True)
            with tempfile.TemporaryDirectory(dir=target.parent) as tmp:
                c_file, so = Path(tmp) / f"{prefix}.c", Path(tmp) / f"{prefix}.so"
                c_file.write_bytes(source)
                compile_to(c_file, so)
                os.replace(so, target)  # atomic: concurrent runs never load a half-written file
            return target
        except Exception as exc:  # no compiler, folder not writable, ...
            failure = exc
    raise failure  # type: ignore[misc]
