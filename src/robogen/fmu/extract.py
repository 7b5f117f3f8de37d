"""Safe unpacking of third-party .fmu archives.

An FMU is untrusted input. Before anything is written, every member is checked: no absolute
path, no drive letter, no ``..`` component, no backslash, no symbolic link or device file (the
Unix mode bits in the ZIP's external attributes), no encryption, only store or deflate. The
member count and the total unpacked size are capped, and the bytes actually written are counted
(a ZIP header can lie about sizes). Files are created with ``O_EXCL`` below the destination
folder only, so nothing is ever written outside it. A member that the ZIP directory lists twice
(as some zip writers do, CMake's among them) is accepted when both copies hold the same bytes and
refused when they differ. The master extracts only what it runs an FMU from (:func:`needed_to_run`:
the description, ``binaries/`` and ``resources/``), not the sources or documentation.
"""

from __future__ import annotations

import hashlib
import os
import stat
import tempfile
import zipfile
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from robogen.diagnostics import RobogenError, Span, error

MAX_MEMBERS = 10_000
MAX_UNPACKED_BYTES = 2 * 1024**3  # 2 GiB
_CHUNK = 1 << 20


@dataclass(frozen=True)
class Limits:
    max_members: int = MAX_MEMBERS
    max_bytes: int = MAX_UNPACKED_BYTES


def member_problem(info: zipfile.ZipInfo) -> str | None:
    """Why ``info`` must not be extracted, or None when it is safe."""
    name = info.filename
    if not name:
        return "empty member name"
    if "\\" in name:
        return "member name contains a backslash"
    if name.startswith("/") or (len(name) > 1 and name[1] == ":"):
        return "member has an absolute path"
    parts = name.rstrip("/").split("/")
    if any(p == ".." for p in parts):
        return "member path contains '..'"
    if any(p in ("", ".") for p in parts):
        return "member path has an empty or '.' component"
    if "\x00" in name:
        return "member name contains a NUL byte"
    mode = info.external_attr >> 16
    if info.create_system == 3 and mode:
        if stat.S_ISLNK(mode):
            return "member is a symbolic link"
        if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) or stat.S_ISFIFO(mode) or stat.S_ISSOCK(mode):
            return "member is a device file, FIFO or socket"
    if info.flag_bits & 0x1:
        return "member is encrypted"
    if info.compress_type not in (zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED):
        return f"member uses compression method {info.compress_type} (FMI allows store and deflate only)"
    return None


def check_archive(path: str | Path, limits: Limits = Limits()) -> list:
    """Diagnostics for every unsafe member of the archive at ``path`` (empty when safe)."""
    display = str(path)
    problems = []
    try:
        with zipfile.ZipFile(path) as z:
            infos = z.infolist()
    except (OSError, zipfile.BadZipFile) as exc:
        return [error(f"not a readable ZIP archive: {exc}", Span.whole_file(display))]
    if len(infos) > limits.max_members:
        problems.append(error(f"archive has {len(infos)} members, more than the limit of {limits.max_members}", Span.whole_file(display)))
    total = sum(i.file_size for i in infos)
    if total > limits.max_bytes:
        problems.append(error(f"archive unpacks to {total} bytes, more than the limit of {limits.max_bytes}", Span.whole_file(display)))
    for info in infos:
        why = member_problem(info)
        if why:
            problems.append(error(f"unsafe archive member '{info.filename}': {why}", Span.whole_file(display)))
    return problems


#: The members an importer runs an FMU from: its description, binaries and resources (not its
#: sources, documentation, icons or extra files).
RUN_FOLDERS = ("binaries/", "resources/")


def needed_to_run(name: str) -> bool:
    """Whether an importer that runs the FMU needs the archive member ``name``."""
    return name == "modelDescription.xml" or name.startswith(RUN_FOLDERS)


def extract_fmu(path: str | Path, destination: str | Path | None = None, limits: Limits = Limits(),
                wanted: Callable[[str], bool] | None = None) -> Path:
    """Unpack the FMU at ``path`` into ``destination`` (a new temporary folder when None): every
    member, or those ``wanted`` accepts (all are checked; see :func:`needed_to_run`).

    Raises RobogenError naming the archive and the offending member; on failure the partially
    written destination is left for the caller to remove (it only holds checked members).
    """
    path = Path(path)
    display = str(path)
    if not path.is_file():
        raise RobogenError.at("FMU file not found", Span.whole_file(display))
    problems = check_archive(path, limits)
    if problems:
        raise RobogenError(problems)
    dest = Path(destination) if destination is not None else Path(tempfile.mkdtemp(prefix="robogen-fmu-"))
    dest.mkdir(parents=True, exist_ok=True)
    root = dest.resolve()
    written = 0
    with zipfile.ZipFile(path) as z:
        for info in z.infolist():
            if wanted is not None and not wanted(info.filename):
                continue
            target = root.joinpath(*info.filename.rstrip("/").split("/"))
            if root not in target.resolve().parents and target.resolve() != root:
                raise RobogenError.at(f"unsafe archive member '{info.filename}': resolves outside the extraction folder", Span.whole_file(display))
            if info.is_dir():
                target.mkdir(parents=True, exist_ok=True)
                continue
            target.parent.mkdir(parents=True, exist_ok=True)
            if root not in target.parent.resolve().parents and target.parent.resolve() != root:
                raise RobogenError.at(f"unsafe archive member '{info.filename}': its folder resolves outside the extraction folder", Span.whole_file(display))
            executable = bool((info.external_attr >> 16) & 0o111)
            flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0)
            try:
                fd = os.open(target, flags, 0o755 if executable else 0o644)
            except FileExistsError:
                written += _same_copy(z, info, target, limits.max_bytes - written, display)
                continue
            with os.fdopen(fd, "wb") as out, z.open(info) as src:
                written += _copy(src, out.write, limits.max_bytes - written, limits.max_bytes, display)
    return dest


def _copy(src, sink, room: int, limit: int, display: str) -> int:
    """The member's bytes to ``sink``, at most ``room`` of them; how many."""
    count = 0
    while True:
        chunk = src.read(_CHUNK)
        if not chunk:
            return count
        count += len(chunk)
        if count > room:
            raise RobogenError.at(f"archive unpacks to more than the limit of {limit} bytes", Span.whole_file(display))
        sink(chunk)


def _same_copy(z: zipfile.ZipFile, info: zipfile.ZipInfo, target: Path, room: int, display: str) -> int:
    """A member listed again: accepted if its bytes are those already extracted (how many), else refused."""
    again, first = hashlib.sha256(), hashlib.sha256()
    with z.open(info) as src:
        count = _copy(src, again.update, room, room, display)
    with open(target, "rb") as written:
        for chunk in iter(lambda: written.read(_CHUNK), b""):
            first.update(chunk)
    if again.digest() != first.digest():
        raise RobogenError.at(f"archive member '{info.filename}' appears twice with different contents", Span.whole_file(display))
    return count
