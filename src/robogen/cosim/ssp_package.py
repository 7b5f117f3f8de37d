"""The files of one SSP: an ``.ssp`` archive unpacked into a folder of the run, or the folder of
an ``.ssd`` file; the URIs of its components and parameter files resolved inside it.

An archive is untrusted input like an FMU and is unpacked by the same code
(:func:`robogen.fmu.extract.extract_fmu`: no absolute path, no ``..``, no link, sizes capped), so
a hostile member is refused before anything is written. A URI in an SSD is resolved against the
SSD's folder and must stay inside the package: a relative reference without scheme, query,
fragment or ``..`` (the standard does not require more, and allows refusing it); a file it names
that is missing is an error at the attribute that names it. Spans into a file of an archive name
it as ``ARCHIVE.ssp/PATH`` (as FMU errors name ``X.fmu/modelDescription.xml``).
"""

from __future__ import annotations

import posixpath
import zipfile
from pathlib import Path
from urllib.parse import unquote, urlsplit

from robogen.diagnostics import DiagnosticSink, Note, RobogenError, Span
from robogen.fmu.extract import extract_fmu

DEFAULT_SSD = "SystemStructure.ssd"


class Package:
    """An SSP's files: ``root`` (the unpacked archive, or the .ssd's folder) and its SSD."""

    def __init__(self, path: Path, folder: Path):
        self.path = path
        self.archive = path.suffix.lower() == ".ssp"
        if not path.exists():
            raise RobogenError.at(f"system file not found: {path}", None)
        if self.archive:
            if not path.is_file():
                raise RobogenError.at("an .ssp file is a ZIP archive; to run an unpacked SSP, give its .ssd file",
                                      Span.whole_file(str(path)))
            self.root = extract_fmu(path, folder).resolve()
            self.ssd = self.root / DEFAULT_SSD
            if not self.ssd.is_file():
                names = sorted(p.name for p in self.root.iterdir() if p.suffix == ".ssd")
                raise RobogenError.at(f"the archive has no {DEFAULT_SSD} at its root", Span.whole_file(str(path)),
                                      *([Note(f"it has {', '.join(names)}: robogen runs the default variant, "
                                              f"{DEFAULT_SSD}")] if names else []))
        else:
            self.root = path.resolve().parent
            self.ssd = path.resolve()

    def display(self, file: Path) -> str:
        """How spans name ``file`` of the package."""
        if not self.archive:
            return str(file) if file != self.ssd else str(self.path)
        return f"{self.path}/{file.relative_to(self.root).as_posix()}"

    def resolve(self, uri: str, span: Span, sink: DiagnosticSink, base: Path | None = None, what: str = "file") -> Path | None:
        """The file the relative URI ``uri`` names, against ``base`` (a folder of the package;
        default the SSD's); None, with the problem in ``sink``, where it is not in the package."""
        relative = self.relative(uri, span, sink)
        if relative is None:
            return None
        base = base if base is not None else self.ssd.parent
        joined = posixpath.normpath(posixpath.join((base.relative_to(self.root)).as_posix(), relative))
        if joined == ".." or joined.startswith("../"):
            sink.error(f"'{uri}' leads out of the SSP: a source must stay inside it", span)
            return None
        file = self.root / joined
        if not file.is_file():
            inside = f" in {self.path}" if self.archive else ""
            sink.error(f"{what} not found{inside}: {joined}", span, *self._nearby(joined))
            return None
        return file

    def relative(self, uri: str, span: Span, sink: DiagnosticSink) -> str | None:
        """``uri`` as a relative path (percent-decoded), or None with the problem in ``sink``."""
        parts = urlsplit(uri)
        if parts.scheme == "file" and not parts.netloc and not parts.path.startswith("/"):
            parts = urlsplit(parts.path)
        if parts.scheme or parts.netloc or parts.path.startswith("/") or "\\" in uri:
            sink.error(f"'{uri}' is not a relative reference: robogen resolves sources inside the SSP only "
                       "(e.g. resources/model.fmu)", span)
            return None
        if parts.query or parts.fragment:
            sink.error(f"'{uri}' has a query or fragment, which robogen does not resolve", span)
            return None
        path = unquote(parts.path)
        if not path or any(p == ".." for p in path.split("/")):
            sink.error(f"'{uri}' leads out of the SSP: a source must stay inside it", span)
            return None
        return path

    def _nearby(self, joined: str) -> list[Note]:
        folder = (self.root / joined).parent
        if not folder.is_dir():
            return []
        names = sorted(p.name for p in folder.iterdir() if p.is_file())[:8]
        return [Note(f"{folder.relative_to(self.root).as_posix() or '.'}/ holds: {', '.join(names)}")] if names else []


def read_member(archive: Path, uri: str, span: Span, sink: DiagnosticSink, package: Package) -> tuple[bytes, str] | None:
    """The file ``uri`` names inside the ZIP archive ``archive`` (a component's FMU, for
    ``sourceBase="component"``) and how spans name it; None with the problem in ``sink``."""
    relative = package.relative(uri, span, sink)
    if relative is None:
        return None
    member = posixpath.normpath(relative)
    try:
        with zipfile.ZipFile(archive) as z:
            data = z.read(member)
    except KeyError:
        sink.error(f"{package.display(archive)} has no member {member}", span)
        return None
    except (OSError, zipfile.BadZipFile) as exc:
        sink.error(f"cannot read {package.display(archive)}: {exc}", span)
        return None
    return data, f"{package.display(archive)}/{member}"
