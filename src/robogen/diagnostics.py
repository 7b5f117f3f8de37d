"""Source spans, diagnostics, and the one error type robogen raises for bad input.

Every stage reports problems as :class:`Diagnostic` values that carry a :class:`Span`
(file, line, column, end) and optional notes. They are collected and raised together in a
:class:`RobogenError`, which the command line renders like a C compiler::

    models/ur5e/ur5e.rst:42:17: error: unknown event 'moveComplete' (did you mean 'moveCompleted'?)
       42 |     condition $moveComplete \\/ $collision
          |                ^~~~~~~~~~~~
    note: declared here: models/ur5e/ur5e.rst:12:3
"""

from __future__ import annotations

import contextlib
import contextvars
import difflib
import enum
import os
import re
from dataclasses import dataclass, field
from typing import Iterable, Iterator, Mapping, Sequence


@dataclass(frozen=True, order=True)
class Span:
    """A half-open source range. Lines and columns are 1-based; ``end_column`` is exclusive."""

    path: str
    line: int
    column: int
    end_line: int
    end_column: int
    # character offsets into the file, when the parser knows them (not part of equality)
    offset: int = field(default=-1, compare=False, repr=False)
    end_offset: int = field(default=-1, compare=False, repr=False)

    @classmethod
    def point(cls, path: str, line: int = 1, column: int = 1) -> "Span":
        return cls(path, line, column, line, column + 1)

    @classmethod
    def whole_file(cls, path: str) -> "Span":
        return cls(path, 1, 1, 1, 1)

    @classmethod
    def of_path(cls, path: str) -> "Span":
        """A path as a whole, with no text to point into (a folder): line and column 0."""
        return cls(path, 0, 0, 0, 0)

    def __str__(self) -> str:
        return f"{self.path}:{self.line}:{self.column}" if self.line else self.path


class Severity(enum.Enum):
    ERROR = "error"
    WARNING = "warning"
    NOTE = "note"


@dataclass(frozen=True)
class Note:
    message: str
    span: Span | None = None


@dataclass(frozen=True)
class Diagnostic:
    severity: Severity
    message: str
    span: Span | None
    notes: tuple[Note, ...] = ()
    code: str = ""

    @property
    def is_error(self) -> bool:
        return self.severity is Severity.ERROR

    def with_note(self, message: str, span: Span | None = None) -> "Diagnostic":
        return Diagnostic(self.severity, self.message, self.span, self.notes + (Note(message, span),), self.code)

    def render(self, sources: "SourceMap | None" = None) -> str:
        return render(self, sources)


def error(message: str, span: Span | None, *notes: Note, code: str = "") -> Diagnostic:
    return Diagnostic(Severity.ERROR, message, span, tuple(notes), code)


def warning(message: str, span: Span | None, *notes: Note, code: str = "") -> Diagnostic:
    return Diagnostic(Severity.WARNING, message, span, tuple(notes), code)


class RobogenError(Exception):
    """Bad input: one or more located diagnostics. The CLI renders them and exits with 1."""

    def __init__(self, diagnostics: Diagnostic | Sequence[Diagnostic]):
        if isinstance(diagnostics, Diagnostic):
            diagnostics = [diagnostics]
        self.diagnostics: tuple[Diagnostic, ...] = tuple(diagnostics)
        first = self.diagnostics[0] if self.diagnostics else None
        super().__init__(f"{first.span}: {first.message}" if first and first.span else (first.message if first else ""))

    @classmethod
    def at(cls, message: str, span: Span | None, *notes: Note) -> "RobogenError":
        return cls(error(message, span, *notes))


class UsageError(Exception):
    """Wrong use of the command line (exit code 2)."""


# --------------------------------------------------------------------------------------------
# Collecting problems


class DiagnosticSink:
    """Collects diagnostics during a pass; ``raise_if_errors`` reports them all together."""

    def __init__(self) -> None:
        self.items: list[Diagnostic] = []

    def add(self, diagnostic: Diagnostic) -> None:
        self.items.append(diagnostic)

    def error(self, message: str, span: Span | None, *notes: Note, code: str = "") -> None:
        self.items.append(error(message, span, *notes, code=code))

    def warning(self, message: str, span: Span | None, *notes: Note, code: str = "") -> None:
        self.items.append(warning(message, span, *notes, code=code))

    def extend(self, diagnostics: Iterable[Diagnostic]) -> None:
        self.items.extend(diagnostics)

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.items if d.is_error]

    @property
    def warnings(self) -> list[Diagnostic]:
        return [d for d in self.items if d.severity is Severity.WARNING]

    def sorted(self) -> list[Diagnostic]:
        """Diagnostics in source order, each reported once."""
        unique = list(dict.fromkeys(self.items))
        return sorted(unique, key=_sort_key)

    def raise_if_errors(self) -> None:
        if self.errors:
            raise RobogenError(self.sorted())


def _sort_key(d: Diagnostic) -> tuple:
    s = d.span
    # problems without a place in a text (paths on the command line) keep the order they were found in
    return (s.path, s.line, s.column, d.message) if s and s.line else ("", 0, 0, "")


def did_you_mean(name: str, candidates: Iterable[str]) -> str:
    """' (did you mean 'x'?)' for the closest candidate, or ''."""
    close = difflib.get_close_matches(name, sorted(set(candidates)), n=1, cutoff=0.6)
    return f" (did you mean '{close[0]}'?)" if close else ""


# --------------------------------------------------------------------------------------------
# Internal-error context: where the tool was working when something unexpected happened


_location: contextvars.ContextVar[Span | None] = contextvars.ContextVar("robogen_location", default=None)


@contextlib.contextmanager
def working_on(span: Span | None) -> Iterator[None]:
    """Record the model location being processed, for 'internal error' messages."""
    token = _location.set(span)
    try:
        yield
    finally:
        _location.reset(token)


def current_location() -> Span | None:
    return _location.get()


# --------------------------------------------------------------------------------------------
# Rendering


class SourceMap:
    """Text of the files diagnostics point into (read lazily from disk when not registered)."""

    def __init__(self, texts: Mapping[str, str] | None = None) -> None:
        self._lines: dict[str, list[str]] = {}
        for path, text in (texts or {}).items():
            self.add(path, text)

    def add(self, path: str, text: str) -> None:
        self._lines[path] = _lines(text)

    def line(self, path: str, number: int) -> str | None:
        lines = self._lines.get(path)
        if lines is None:
            data = _read_source(path)
            binary = data is not None and b"\x00" in data[:8192]  # an archive, a binary: no excerpt
            lines = _lines(data.decode("utf-8", errors="replace")) if data is not None and not binary else []
            self._lines[path] = lines
        if 1 <= number <= len(lines):
            return lines[number - 1]
        return None


def _read_source(path: str) -> bytes | None:
    """The bytes of ``path``: a file, or a member of a ZIP archive named ``ARCHIVE/MEMBER`` (the
    model description of an FMU, the SSD of an SSP archive); None if neither can be read."""
    try:
        with open(path, "rb") as f:
            return f.read()
    except OSError:
        pass
    import zipfile

    parts = path.split("/")
    for i in range(len(parts) - 1, 0, -1):
        archive = "/".join(parts[:i])
        if os.path.isfile(archive):
            try:
                with zipfile.ZipFile(archive) as z:
                    return z.read("/".join(parts[i:]))
            except (OSError, KeyError, zipfile.BadZipFile):
                return None
    return None


def _lines(text: str) -> list[str]:
    """Lines as the parser numbers them: split at "\n" only (str.splitlines would also split at a
    lone "\r", form feeds and U+2028, and the excerpt would show another line than the one meant)."""
    return [line.removesuffix("\r") for line in text.split("\n")]


def _display(path: str) -> str:
    try:
        rel = os.path.relpath(path)
    except ValueError:
        return path
    return rel if not rel.startswith("../../") else path


def render(diagnostic: Diagnostic, sources: SourceMap | None = None) -> str:
    sources = sources or SourceMap()
    out: list[str] = []
    span = diagnostic.span
    head = f"{diagnostic.severity.value}: {diagnostic.message}"
    if span is None:
        out.append(head)
    else:
        where = f"{_display(span.path)}:{span.line}:{span.column}" if span.line else _display(span.path)
        out.append(f"{where}: {head}")
        out.extend(_excerpt(span, sources))
    for note in diagnostic.notes:
        if note.span is None:
            out.append(f"note: {note.message}")
        else:
            out.append(f"note: {note.message}: {_display(note.span.path)}:{note.span.line}:{note.span.column}")
    return "\n".join(out)


def _excerpt(span: Span, sources: SourceMap) -> list[str]:
    text = sources.line(span.path, span.line)
    if text is None:
        return []
    # Control characters (binary input) would garble the terminal: show them as U+FFFD, one
    # character for one, so the caret stays aligned.
    text = _CONTROL.sub("\ufffd", text)
    expanded = text.expandtabs(4)
    if len(expanded) > 200:
        return []
    # Column positions count characters of the raw line; map them through tab expansion.
    start = _visual_column(text, span.column)
    if span.end_line == span.line and span.end_column > span.column:
        end = _visual_column(text, span.end_column)
    else:
        end = max(start + 1, len(expanded.rstrip()) + 1)
    width = max(1, end - start)
    gutter = f"{span.line:>5}"
    marker = " " * (start - 1) + "^" + "~" * (width - 1)
    return [f"{gutter} | {expanded.rstrip()}", f"{' ' * len(gutter)} | {marker}"]


_CONTROL = re.compile(r"[\x00-\x08\x0b-\x1f\x7f-\x9f]")


def _visual_column(text: str, column: int) -> int:
    visual = 1
    for ch in text[: max(0, column - 1)]:
        visual = ((visual - 1) // 4 + 1) * 4 + 1 if ch == "\t" else visual + 1
    return visual


def render_all(diagnostics: Iterable[Diagnostic], sources: SourceMap | None = None) -> str:
    sources = sources or SourceMap()
    return "\n".join(render(d, sources) for d in diagnostics)


@dataclass
class Summary:
    errors: int = 0
    warnings: int = 0
    files: list[str] = field(default_factory=list)

    def line(self) -> str:
        def plural(n: int, word: str) -> str:
            return f"{n} {word}{'' if n == 1 else 's'}"

        return f"{plural(self.errors, 'error')}, {plural(self.warnings, 'warning')}"
