"""Source positions for a TOML document that ``tomllib`` has already accepted.

``tomllib`` returns plain dicts without positions, so this module walks the same text once
more and records where each key and each array element starts, keyed by its path
(``("instances", "ball", "fmu")``, ``("connections", 3)``). It relies on the text being valid
TOML and only tracks structure: table headers, array-of-table headers, ``key = value`` pairs,
inline tables and arrays (nested arbitrarily), strings of all four kinds, comments.
"""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

from robogen.diagnostics import RobogenError, Span

_BARE = re.compile(r"[A-Za-z0-9_-]+")
KeyPath = tuple  # a key's path in the document: ("instances", "ball", "fmu"), ("connections", 3)


def read_toml(path: Path, what: str) -> tuple[str, dict]:
    """The text and the data of the TOML file ``path`` (a ``what``: "system file", ...); a file
    that cannot be read, is not UTF-8 or not TOML is an error at its place."""
    display = str(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise RobogenError.at(f"cannot read {what}: {exc.strerror}", Span.whole_file(display)) from None
    except UnicodeDecodeError:
        raise RobogenError.at(f"{what} is not UTF-8 text", Span.whole_file(display)) from None
    try:
        return text, tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        m = re.search(r"\(at line (\d+), column (\d+)\)", str(exc))
        msg = re.sub(r"\s*\(at line \d+, column \d+\)", "", str(exc))
        span = Span.point(display, int(m.group(1)), int(m.group(2))) if m else Span.whole_file(display)
        raise RobogenError.at(f"invalid TOML: {msg}", span) from None


class PathSpans:
    """Spans by key path; a path not recorded has its longest recorded prefix's, else ``fallback``'s.
    What a system's spans answer, whichever file the system was read from."""

    def __init__(self, fallback: Span):
        self.fallback = fallback
        self.spans: dict[KeyPath, Span] = {}

    def span(self, *path) -> Span:
        """The span of ``path``, or of its longest recorded prefix, or the fallback (the whole file)."""
        p = tuple(path)
        while p:
            if p in self.spans:
                return self.spans[p]
            p = p[:-1]
        return self.fallback


class SpanIndex(PathSpans):
    def __init__(self, text: str, path: str):
        super().__init__(Span.whole_file(path))
        self.text, self.path = text, path
        self._aot_count: dict[KeyPath, int] = {}
        self.i = 0
        self._line_starts = [0] + [m.end() for m in re.finditer("\n", text)]
        try:
            self._document()
        except (IndexError, ValueError):  # best effort: keep what was found
            pass

    # -- scanning ----------------------------------------------------------------------------
    def _pos(self, i: int, length: int = 1) -> Span:
        import bisect

        line = bisect.bisect_right(self._line_starts, i)
        col = i - self._line_starts[line - 1] + 1
        return Span(self.path, line, col, line, col + max(length, 1))

    def _skip_ws(self, newlines: bool) -> None:
        t = self.text
        while self.i < len(t):
            c = t[self.i]
            if c in " \t\r" or (newlines and c == "\n"):
                self.i += 1
            elif c == "#":
                while self.i < len(t) and t[self.i] != "\n":
                    self.i += 1
            else:
                return

    def _key_part(self) -> tuple[str, int, int]:
        t, start = self.text, self.i
        if t[self.i] in "\"'":
            value = self._string()
            return value, start, self.i - start
        m = _BARE.match(t, self.i)
        if not m:
            raise ValueError("key expected")
        self.i = m.end()
        return m.group(0), start, self.i - start

    def _dotted_key(self) -> list[tuple[str, int, int]]:
        parts = [self._key_part()]
        while True:
            self._skip_ws(False)
            if self.i < len(self.text) and self.text[self.i] == ".":
                self.i += 1
                self._skip_ws(False)
                parts.append(self._key_part())
            else:
                return parts

    def _string(self) -> str:
        t, q = self.text, self.text[self.i]
        if t.startswith(q * 3, self.i):
            end = t.index(q * 3, self.i + 3)
            while t.startswith(q, end + 3):  # up to two quotes may close the string
                end += 1
            raw = t[self.i + 3:end]
            self.i = end + 3
            return raw
        start, j = self.i, self.i + 1
        while t[j] != q:
            j += 2 if (q == '"' and t[j] == "\\") else 1
        raw = t[start + 1:j]
        self.i = j + 1
        if q == '"' and "\\" in raw:
            import tomllib

            try:
                return tomllib.loads(f"x = {t[start:j + 1]}")["x"]
            except tomllib.TOMLDecodeError:
                return raw
        return raw

    def _document(self) -> None:
        t = self.text
        table: KeyPath = ()
        while True:
            self._skip_ws(True)
            if self.i >= len(t):
                return
            if t[self.i] == "[":
                aot = t.startswith("[[", self.i)
                start = self.i
                self.i += 2 if aot else 1
                self._skip_ws(False)
                parts = self._dotted_key()
                self._skip_ws(False)
                self.i += 2 if aot else 1
                table = tuple(p[0] for p in parts)
                if aot:
                    n = self._aot_count.get(table, 0)
                    self._aot_count[table] = n + 1
                    self.spans.setdefault(table, self._pos(start, self.i - start))
                    table = table + (n,)
                self.spans[table] = self._pos(start, self.i - start)
            else:
                self._pair(table)

    def _pair(self, prefix: KeyPath) -> None:
        parts = self._dotted_key()
        path = prefix + tuple(p[0] for p in parts)
        _, start, length = parts[-1]
        self.spans[path] = self._pos(parts[0][1], start + length - parts[0][1])
        self._skip_ws(False)
        self.i += 1  # '='
        self._skip_ws(False)
        self._value(path)

    def _value(self, path: KeyPath) -> None:
        t = self.text
        c = t[self.i]
        if c == "[":
            self.i += 1
            n = 0
            while True:
                self._skip_ws(True)
                if t[self.i] == "]":
                    self.i += 1
                    return
                if t[self.i] == ",":
                    self.i += 1
                    continue
                start = self.i
                self._value(path + (n,))
                self.spans.setdefault(path + (n,), self._pos(start, self.i - start))
                n += 1
        elif c == "{":
            self.i += 1
            while True:
                self._skip_ws(True)
                if t[self.i] == "}":
                    self.i += 1
                    return
                if t[self.i] == ",":
                    self.i += 1
                    continue
                self._pair(path)
        elif c in "\"'":
            start = self.i
            self._string()
            if path and isinstance(path[-1], int):
                self.spans[path] = self._pos(start, self.i - start)
        else:
            m = re.compile(r"[^\s,\]}#]+").match(t, self.i)
            self.i = m.end() if m else self.i + 1
