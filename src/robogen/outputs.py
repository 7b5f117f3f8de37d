"""Where commands write: an output never destroys an input, and never leaves a half-written file.

Every command that writes a file or a folder the user named goes through here:

- :func:`output_file` refuses a file output that is one of the command's inputs (``robogen
  package m.rst -o m.rst``), that names an existing folder, or that lies under an existing file;
- :func:`replacing` writes a file under a unique temporary name in the same folder and renames it
  over the target only when the content is complete, so a failure leaves the previous file (or
  none) in place, and parallel writers never share a temporary file;
- :func:`output_folder` lets a command write into a folder only if it is new, empty, or marked as
  written by robogen before (:data:`MARKER`), so ``robogen compile m.rst -o .`` cannot delete a
  user's files.

Each problem is a :class:`~robogen.diagnostics.RobogenError` naming the option, not a traceback.
"""

from __future__ import annotations

import os
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import Iterable, Iterator

from robogen.diagnostics import RobogenError

#: The file that marks a folder as robogen's output (its content says which command wrote it).
MARKER = ".robogen-output"


def _same(a: Path, b: Path) -> bool:
    try:
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except OSError:
        return False


def _refuse(message: str) -> RobogenError:
    return RobogenError.at(message, None)


def check_not_input(output: Path, inputs: Iterable[str | os.PathLike], option: str = "-o") -> None:
    """Refuse an output path that names one of the inputs (the same file, by any path)."""
    resolved = output.resolve()
    for item in inputs:
        path = Path(item)
        if _same(output, path) or resolved == path.resolve():
            raise _refuse(f"{option} {output} is also an input of this command; refusing to overwrite it")


def output_file(path: str | os.PathLike, *, inputs: Iterable[str | os.PathLike] = (), option: str = "-o") -> Path:
    """Check that ``path`` can be written as a file output, and return it.

    Its folder is created if missing. Refused: an input of the command, an existing folder, a
    path under an existing file.
    """
    out = Path(path)
    check_not_input(out, inputs, option)
    if out.is_dir():
        raise _refuse(f"{option} {out} is a folder; name a file")
    for parent in out.parents:
        if parent.exists():
            if not parent.is_dir():
                raise _refuse(f"{option} {out}: {parent} is a file, not a folder")
            break
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise _refuse(f"{option} {out}: cannot create the folder {out.parent}: {exc.strerror or exc}") from None
    return out


@contextmanager
def replacing(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a fresh temporary path next to ``path``; rename it over ``path`` on success.

    On an exception the temporary file is removed and ``path`` is untouched.
    """
    target = Path(path)
    fd, name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    os.close(fd)
    tmp = Path(name)
    try:
        yield tmp
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, target)
    finally:
        if tmp.exists():
            tmp.unlink()


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_text(path: str | os.PathLike, text: str) -> Path:
    """Write ``text`` to ``path`` through :func:`replacing`."""
    with replacing(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(path)


def output_folder(path: str | os.PathLike, *, command: str, inputs: Iterable[str | os.PathLike] = (),
                  option: str = "-o") -> Path:
    """Check that ``path`` may receive a command's output folder, create it and mark it.

    Allowed: a new folder, an empty one, or one that carries :data:`MARKER` (robogen wrote it).
    """
    out = Path(path)
    check_not_input(out, inputs, option)
    if out.exists() and not out.is_dir():
        raise _refuse(f"{option} {out} is a file; name a folder")
    for item in inputs:
        if out.is_dir() and Path(item).exists() and Path(item).resolve().is_relative_to(out.resolve()):
            raise _refuse(f"{option} {out} holds the input {item}; choose a separate output folder")
    if out.is_dir() and any(out.iterdir()) and not (out / MARKER).is_file():
        raise _refuse(f"{option} {out} is a folder robogen did not write and it is not empty; "
                      f"refusing to write into it (choose a new or empty folder)")
    try:
        out.mkdir(parents=True, exist_ok=True)
        (out / MARKER).write_text(f"written by robogen {command}; robogen may replace what it wrote here\n", encoding="utf-8")
    except OSError as exc:
        raise _refuse(f"{option} {out}: cannot create the folder: {exc.strerror or exc}") from None
    return out


__all__ = ["MARKER", "check_not_input", "output_file", "replacing", "write_text", "output_folder"]
