"""XML read into a small tree whose every element and attribute knows its line and column.

``lxml`` gives an element's line but not its column, and nothing for attributes; the SSP front
end reports problems at the element or attribute that causes them, so it reads its files with
the standard library's expat parser (namespaces resolved) into :class:`Element` nodes that carry
their :class:`~robogen.diagnostics.Span`. A document type declaration is refused (SSP files have
none; it is where entity expansion attacks live), and so is text that is not well-formed XML,
at the line and column expat reports.
"""

from __future__ import annotations

import bisect
import re
from dataclasses import dataclass, field
from xml.parsers import expat

from robogen.diagnostics import RobogenError, Span

_SEP = "\x01"  # between a namespace and a local name in expat's names


@dataclass(eq=False)
class Element:
    """One element: its namespace URI ("" for none), local name, attributes (local names; a
    namespaced attribute as ``{uri}name``), children, text, and where it and its attributes are."""

    ns: str
    tag: str
    attrib: dict[str, str]
    span: Span
    attr_spans: dict[str, Span] = field(default_factory=dict)
    children: list[Element] = field(default_factory=list)
    text: str = ""
    parent: Element | None = field(default=None, repr=False)

    def at(self, attr: str | None = None) -> Span:
        """Where the attribute ``attr`` is written (the element if absent or None)."""
        return self.attr_spans.get(attr, self.span) if attr else self.span

    def get(self, attr: str, default: str | None = None) -> str | None:
        return self.attrib.get(attr, default)

    def find(self, ns: str, tag: str) -> Element | None:
        return next((c for c in self.children if c.ns == ns and c.tag == tag), None)

    def findall(self, ns: str, tag: str) -> list[Element]:
        return [c for c in self.children if c.ns == ns and c.tag == tag]

    def path(self, ns: str, *tags: str) -> list[Element]:
        """The descendants reached by ``tags`` (each in namespace ``ns``), one level per tag."""
        found = [self]
        for tag in tags:
            found = [c for e in found for c in e.findall(ns, tag)]
        return found


def parse(data: bytes, display: str, assume: dict[str, str] | None = None) -> tuple[Element, list[str]]:
    """The root element of the XML document ``data`` (``display`` names it in spans), and the
    prefixes of ``assume`` (prefix -> namespace) it had to assume: a document that uses one of
    them without declaring it is read as if its root declared it (some tools write such files)."""
    try:
        return _Builder(data, display).root, []
    except _Unbound as exc:
        unbound = exc.error
    declared = set(re.findall(rb"xmlns:([\w.-]+)\s*=", data))
    used = {m.decode() for m in re.findall(rb"</?([\w.-]+):", data)} - {d.decode() for d in declared}
    missing = sorted(p for p in used if p in (assume or {}))
    if not missing:
        raise unbound
    start = re.search(rb"<(?![?!])", data)
    end = _tag_end(data, start.start()) - 1
    end -= 1 if data[end - 1:end] == b"/" else 0
    extra = "".join(f' xmlns:{p}="{assume[p]}"' for p in missing).encode()
    return _Builder(data[:end] + extra + data[end:], display).root, missing


class _Builder:
    def __init__(self, data: bytes, display: str):
        self.data, self.display = data, display
        self.line_starts = [0] + [m.end() for m in re.finditer(b"\n", data)]
        self.stack: list[Element] = []
        self.root: Element | None = None  # type: ignore[assignment]
        parser = expat.ParserCreate(namespace_separator=_SEP)
        parser.buffer_text = True
        parser.StartElementHandler = self.start
        parser.EndElementHandler = self.end
        parser.CharacterDataHandler = self.chars
        parser.StartDoctypeDeclHandler = self.doctype
        self.parser = parser
        try:
            parser.Parse(data, True)
        except expat.ExpatError as exc:
            span = Span.point(display, exc.lineno, exc.offset + 1)
            error = RobogenError.at(f"not well-formed XML: {expat.ErrorString(exc.code)}", span)
            if exc.code == expat.errors.codes[expat.errors.XML_ERROR_UNBOUND_PREFIX]:
                raise _Unbound(error) from None
            raise error from None
        except _Refused as exc:
            raise RobogenError.at(str(exc), exc.span) from None

    def position(self, offset: int, length: int = 1) -> Span:
        line = bisect.bisect_right(self.line_starts, offset)
        start = self.line_starts[line - 1]
        column = len(self.data[start:offset].decode("utf-8", "replace")) + 1
        return Span(self.display, line, column, line, column + max(length, 1))

    def doctype(self, *_args) -> None:
        at = self.parser.CurrentByteIndex
        start = self.data.rfind(b"<!DOCTYPE", 0, at + 1)
        raise _Refused("a document type declaration (<!DOCTYPE ...>) is not allowed in an SSP file",
                       self.position(start if start >= 0 else at, len("<!DOCTYPE")))

    def start(self, name: str, attrs: dict[str, str]) -> None:
        ns, tag = _split(name)
        offset = self.parser.CurrentByteIndex
        end = _tag_end(self.data, offset)
        raw = self.data[offset:end]
        head = re.match(rb"<[^\s/>]*", raw)
        element = Element(ns, tag, {}, self.position(offset, len(head.group(0)) if head else 1))
        for key, value in attrs.items():
            ans, local = _split(key)
            name_ = f"{{{ans}}}{local}" if ans else local
            element.attrib[name_] = value
            match = re.search(rb"(?<![\w:.-])((?:[\w.-]+:)?" + re.escape(local.encode()) + rb")\s*=", raw)
            if match:
                element.attr_spans[name_] = self.position(offset + match.start(1), len(match.group(1)))
        if self.stack:
            element.parent = self.stack[-1]
            self.stack[-1].children.append(element)
        else:
            self.root = element
        self.stack.append(element)

    def end(self, _name: str) -> None:
        self.stack.pop()

    def chars(self, text: str) -> None:
        if self.stack:
            self.stack[-1].text += text


class _Unbound(Exception):
    """A prefix used without its namespace declaration: ``error`` says where."""

    def __init__(self, error: RobogenError):
        super().__init__(str(error))
        self.error = error


class _Refused(Exception):
    def __init__(self, message: str, span: Span):
        super().__init__(message)
        self.span = span


def _split(name: str) -> tuple[str, str]:
    ns, sep, local = name.partition(_SEP)
    return (ns, local) if sep else ("", name)


def _tag_end(data: bytes, offset: int) -> int:
    """The offset just after the start tag that begins at ``offset`` (quotes respected)."""
    quote = None
    for i in range(offset, len(data)):
        c = data[i:i + 1]
        if quote:
            if c == quote:
                quote = None
        elif c in (b'"', b"'"):
            quote = c
        elif c == b">":
            return i + 1
    return len(data)
