"""Python-implemented FMUs, extracted and loaded once per process (issue 22).

A Python FMU (``robogen package-py``: its archive holds ``resources/pyfmu.json``) runs in the
process's own interpreter. Once its binary is loaded it stays loaded (cffi's embedded module
cannot be unloaded), and loading the same FMU again from another folder loads another copy of
the binary, which starts its Python side anew: compiles its start-up code, binds its functions,
imports its model. So the master extracts each distinct Python FMU (by the SHA-256 of its
archive) once per process, into a folder removed when the process exits, and loads its binary
once; every run still makes fresh instances of it (fmi3InstantiateCoSimulation: the model's
state lives in the instance), as of any FMU. Campaign workers that run many variants of a system
load each of its Python FMUs once.

The archive is unchanged: what another importer sees is what it saw. C FMUs are extracted per
run, as before (:class:`robogen.cosim.assemble.FmuCache`).
"""

from __future__ import annotations

import atexit
import hashlib
import os
import shutil
import tempfile
import threading
import zipfile
from pathlib import Path

from robogen.cosim.fmi3 import Library
from robogen.fmu.extract import extract_fmu, needed_to_run
from robogen.fmu.modeldesc import ModelDescription, load_model_description

#: the member that marks an archive as a Python-implemented FMU (robogen.pyfmu.build)
MARKER = "resources/pyfmu.json"


class SharedFmus:
    """The Python FMUs of this process: extracted folder and model description by archive
    digest, binaries by path. Thread-safe (a Dask worker may run several tasks at once).

    A forked child (a campaign's run) inherits the registry: the binaries its parent loaded are
    in its memory, the folders are its parent's (removed at the parent's exit, never by the
    child). A folder removed from under the registry (a temporary folder of a campaign's run)
    is extracted again, into a new folder of the process's temporary folder at that time."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._root: Path | None = None
        self._owner = 0
        self._loaded: dict[str, tuple[Path, ModelDescription]] = {}
        self._folders: set[Path] = set()
        self._libraries: dict[str, Library] = {}
        #: what an archive file was when last read: its identity (_identity) -> its digest, or
        #: None for an archive that is not a Python FMU
        self._digests: dict[tuple, str | None] = {}

    def load(self, fmu: Path) -> tuple[Path, ModelDescription] | None:
        """The extracted folder and model description of the Python FMU at ``fmu``, extracted
        at its first use in this process; None when ``fmu`` is not a Python FMU (or not a zip
        archive: the caller's extraction reports that). An archive is read and hashed again
        only when its file changed (path, device, inode, size, modification time)."""
        identity = _identity(fmu)
        if identity is not None and identity in self._digests:
            digest = self._digests[identity]
        else:
            digest = hashlib.sha256(fmu.read_bytes()).hexdigest() if _is_python_fmu(fmu) else None
            if identity is not None:
                self._digests[identity] = digest
        if digest is None:
            return None
        with self._lock:
            entry = self._loaded.get(digest)
            if entry is None or not entry[0].is_dir():
                folder = self._folder() / digest[:16]
                try:
                    extract_fmu(fmu, folder, wanted=needed_to_run)
                    entry = folder, load_model_description(folder, f"{fmu}/modelDescription.xml")
                except BaseException:
                    shutil.rmtree(folder, ignore_errors=True)
                    raise
                self._loaded[digest] = entry
                self._folders.add(folder)
            return entry

    @property
    def root(self) -> Path | None:
        """The folder this process made for its extracted Python FMUs (None before the first,
        and in a forked child that uses its parent's)."""
        return self._root if self._owner == os.getpid() else None

    def holds(self, folder: Path) -> bool:
        """Whether ``folder`` is one of the shared extractions."""
        return folder in self._folders

    def library(self, path: str) -> Library:
        """The binary at ``path`` (in a shared folder), loaded once."""
        with self._lock:
            if path not in self._libraries:
                self._libraries[path] = Library(path)
            return self._libraries[path]

    def _folder(self) -> Path:
        """The folder of extracted Python FMUs: made at the first one (again if it was removed,
        and in a forked child, whose own FMUs go to its own temporary folder: a campaign's run
        folder, removed with the run), removed at the exit of the process that made it."""
        if self._root is None or self._owner != os.getpid() or not self._root.is_dir():
            self._root, self._owner = Path(tempfile.mkdtemp(prefix="robogen-pyfmus-")), os.getpid()
            root, owner = self._root, self._owner
            atexit.register(lambda: os.getpid() == owner and shutil.rmtree(root, ignore_errors=True))
        return self._root

    def after_fork(self) -> None:
        self._lock = threading.Lock()  # another thread may have held it at the fork


def _identity(fmu: Path) -> tuple | None:
    """What tells that a file is unchanged since it was last read: its absolute path, device,
    inode, size and modification time (ns); None when it cannot be read."""
    try:
        st = os.stat(fmu)
    except OSError:
        return None
    return os.path.abspath(fmu), st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns


def _is_python_fmu(fmu: Path) -> bool:
    try:
        with zipfile.ZipFile(fmu) as archive:
            return MARKER in archive.namelist()
    except (OSError, zipfile.BadZipFile):
        return False


#: the one registry of the process
SHARED = SharedFmus()
os.register_at_fork(after_in_child=SHARED.after_fork)
