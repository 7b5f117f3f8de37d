"""The transformer's foundation: spans computed from token offsets, reserved-word checks, and
the nesting depth of recursive constructs (see :data:`MAX_NESTING`); and the small positioned
values that rule callbacks pass to each other before they become AST nodes."""

from __future__ import annotations

import re
from bisect import bisect_right
from typing import Callable

from lark import Token, Transformer

from robogen.diagnostics import Diagnostic, Span, error
from robogen.syntax import ast

# How deeply expressions, statements, types and states may nest (real models stay below 20).
# Only real nesting counts: parentheses, operands inside operands, calls inside calls, nested
# conditionals and states. A flat chain of one precedence level or several (`a + b - c`,
# `p /\ q /\ r`, `x + y > 3 /\ ok`) is one level however long: it is left-nested in the AST,
# and every stage walks such a chain along its left operands in a loop (ast.chain), not by
# recursion.
MAX_NESTING = 100


class Positioned:
    """Helper values passed between callbacks that are not AST nodes but keep a position."""

    __slots__ = ("pos",)


class Package(Positioned):
    __slots__ = ("name",)

    def __init__(self, name: ast.Name):
        self.name = name
        self.pos = node_pos(name)


class Flag(Positioned):
    __slots__ = ("what",)

    def __init__(self, what: str, pos=None):
        self.what = what
        self.pos = pos


class Clause(Positioned):
    __slots__ = ("key", "value")

    def __init__(self, key: str, value, pos=None):
        self.key = key
        self.value = value
        self.pos = pos


class SuchThat(Positioned):
    __slots__ = ("expr",)

    def __init__(self, expr):
        self.expr = expr
        self.pos = node_pos(expr)


class Body(Positioned):
    __slots__ = ("expr",)

    def __init__(self, expr):
        self.expr = expr
        self.pos = node_pos(expr)


_new = object.__new__
_set = object.__setattr__


def make_span(path: str, line: int, column: int, end_line: int, end_column: int, offset: int, end_offset: int) -> Span:
    """``Span(path, line, column, end_line, end_column, offset, end_offset)``, the same object
    made without the frozen dataclass's seven ``__setattr__`` calls (the parser makes one for
    nearly every token)."""
    span = _new(Span)
    _set(span, "__dict__", {"path": path, "line": line, "column": column, "end_line": end_line,
                            "end_column": end_column, "offset": offset, "end_offset": end_offset})  # fmt: skip
    return span


if "__slots__" in Span.__dict__:  # pragma: no cover - a Span without __dict__ is made the plain way
    make_span = Span  # noqa: F811


def first_child(method):
    """Marks a callback that returns its only child unchanged: a driver may keep the child
    without calling it (see :mod:`robogen.syntax.fastparse`)."""
    method.first_child = True
    return method


def node_pos(x) -> tuple[int, int] | None:
    return span_pos(getattr(x, "span", None))


def span_pos(span: Span | None) -> tuple[int, int] | None:
    if span is not None and span.offset >= 0:
        return (span.offset, span.end_offset)
    return None


def pos(x) -> tuple[int, int] | None:
    """(start, end) character offsets of a callback child, if it has any."""
    if isinstance(x, Token):
        return (x.start_pos, x.end_pos) if x.start_pos is not None else None
    if isinstance(x, ast.Node):
        span = x.span
        return (span.offset, span.end_offset) if span is not None and span.offset >= 0 else None
    if isinstance(x, Positioned):
        return x.pos
    if isinstance(x, (tuple, list)) and x:
        a, b = pos(x[0]), pos(x[-1])
        if a and b:
            return (a[0], b[1])
    return None


def _edge(x, at_end: bool) -> tuple[int, int, int] | None:
    """(offset, line, column) where callback child ``x`` starts (or ends), if it has a position;
    line and column are 0 where only the offset is known."""
    if type(x) is Token:
        if x.start_pos is None:
            return None
        return (x.end_pos, x.end_line, x.end_column) if at_end else (x.start_pos, x.line, x.column)
    if isinstance(x, ast.Node):
        span = x.span
        if span is None or span.offset < 0:
            return None
        return (span.end_offset, span.end_line, span.end_column) if at_end else (span.offset, span.line, span.column)
    p = pos(x)
    if not p:
        return None
    return (p[1] if at_end else p[0], 0, 0)


class SpanBuilder(Transformer):
    """Builds AST nodes bottom-up, with spans computed from the children's positions.

    Lark drops the anonymous keyword and punctuation tokens, so a rule's span starts at its
    first kept child; where the grammar guarantees a token before or after (a leading keyword,
    a closing parenthesis), ``_span(children, left=..., right=...)`` grows the span over it.
    Reserved words used as names are reported, not raised, so all such problems are listed.
    """

    def __init__(self, language: str, reserved: Callable[[], frozenset[str]]):
        super().__init__(visit_tokens=False)
        self.language = language
        self._reserved = reserved  # the language's keywords, asked for once the parser exists
        self._keywords: frozenset[str] | None = None
        self.begin("<string>", "")

    def begin(self, path: str, text: str) -> None:
        self.path = path
        self.text = text
        self.problems: list[Diagnostic] = []
        self.notices: list[Diagnostic] = []  # warnings about the text (obsolete forms), kept in the File
        self._line_starts = [0] + [m.end() for m in re.finditer("\n", text)]
        # nesting depth of the nodes of recursive constructs, by id (see _nest)
        self._depth: dict[int, int] = {}
        self._chains: set[int] = set()  # the binary nodes built by an operator's callback (not parenthesised)
        self._alive: list = []  # keeps those nodes alive, so that their ids stay unique
        self._too_deep = False

    def end(self) -> list[Diagnostic]:
        # in source order (callbacks run at reductions, an enclosing construct after its parts)
        problems = sorted(self.problems, key=lambda d: (d.span.line, d.span.column) if d.span else (0, 0))
        self.begin("<string>", "")
        return problems

    @property
    def keywords(self) -> frozenset[str]:
        if self._keywords is None:
            self._keywords = self._reserved()
        return self._keywords

    def _nest(self, node, c):
        """Record how deeply ``node`` nests constructs of its own kind (expressions, statements,
        types, states), from the depths of its children. Later stages follow real nesting by
        recursion, so a file nested deeper than MAX_NESTING is rejected here, with its
        location, rather than overflowing the interpreter's stack somewhere downstream."""
        depth = self._depth
        d = 0
        for x in c:
            if type(x) is tuple:
                for y in x:
                    if type(y) is tuple:
                        for z in y:
                            v = depth.get(id(z), 0)
                            d = v if v > d else d
                    else:
                        v = depth.get(id(y), 0)
                        d = v if v > d else d
            else:
                v = depth.get(id(x), 0)
                d = v if v > d else d
        if d >= MAX_NESTING:
            return self._record(node, d + 1, c)
        depth[id(node)] = d + 1  # _record, inline
        self._alive.append(node)
        return node

    def _record(self, node, d: int, c):
        """Keep ``node``'s depth ``d``; the first node deeper than MAX_NESTING is reported."""
        self._depth[id(node)] = d
        self._alive.append(node)
        if d > MAX_NESTING and not self._too_deep:
            self._too_deep = True
            self.problems.append(
                error(
                    f"nested too deeply: robogen accepts at most {MAX_NESTING} levels of nested expressions, "
                    "statements, types or states",
                    getattr(node, "span", None) or self._span(c),
                )
            )
        return node

    def _nest_operand(self, node, left, right):
        """Record the depth of a binary node: its right operand nests one level deeper, its left
        operand too unless it is itself an unparenthesised binary node, which the node only
        continues (so that ``a + b + ... + z`` has the depth of one sum)."""
        depth = self._depth
        d_left = depth.get(id(left), 0) + (0 if id(left) in self._chains else 1)
        d_right = depth.get(id(right), 0) + 1
        self._chains.add(id(node))
        d = d_left if d_left > d_right else d_right
        if d > MAX_NESTING:
            return self._record(node, d, (left, right))
        depth[id(node)] = d  # _record, inline
        self._alive.append(node)
        return node

    def _line_col(self, offset: int) -> tuple[int, int]:
        line = bisect_right(self._line_starts, offset)
        return line, offset - self._line_starts[line - 1] + 1

    def _make(self, start: int, end: int) -> Span:
        line_starts = self._line_starts
        line = bisect_right(line_starts, start)
        end_line = bisect_right(line_starts, end)
        return make_span(self.path, line, start - line_starts[line - 1] + 1, end_line, end - line_starts[end_line - 1] + 1, start, end)

    def _span(self, children, left: tuple[str, ...] = (), right: tuple[str, ...] = ()) -> Span | None:
        # Tokens and nodes know their lines and columns: only a span grown over a keyword or a
        # bracket, or ending at a helper value, looks them up from the offsets.
        for c in children:  # the first child with a position (tokens and nodes inline)
            if type(c) is Token and c.start_pos is not None:
                start, line, column = c.start_pos, c.line, c.column
                break
            if isinstance(c, ast.Node) and (span := c.span) is not None and span.offset >= 0:
                start, line, column = span.offset, span.line, span.column
                break
            first = _edge(c, False)
            if first:
                start, line, column = first
                break
        else:
            return None
        for c in reversed(children):
            if type(c) is Token and c.start_pos is not None:
                end, end_line, end_column = c.end_pos, c.end_line, c.end_column
                break
            if isinstance(c, ast.Node) and (span := c.span) is not None and span.offset >= 0:
                end, end_line, end_column = span.end_offset, span.end_line, span.end_column
                break
            last = _edge(c, True)
            if last:
                end, end_line, end_column = last
                break
        if line and end_line and not left and not right:  # most spans: from the first child to the last
            return make_span(self.path, line, column, end_line, end_column, start, end)
        text = self.text
        for word in reversed(left):
            p = start
            while p > 0 and text[p - 1].isspace():
                p -= 1
            if p >= len(word) and text.startswith(word, p - len(word)):
                start = p - len(word)
                line = 0
            else:
                break
        for word in right:
            p = end
            n = len(text)
            while p < n and text[p].isspace():
                p += 1
            if text.startswith(word, p):
                end = p + len(word)
                end_line = 0
            else:
                break
        line_starts = self._line_starts
        if not line:
            line = bisect_right(line_starts, start)
            column = start - line_starts[line - 1] + 1
        if not end_line:
            end_line = bisect_right(line_starts, end)
            end_column = end - line_starts[end_line - 1] + 1
        return make_span(self.path, line, column, end_line, end_column, start, end)

    def _tspan(self, token: Token) -> Span:
        start = token.start_pos
        if start is not None and token.end_line and token.end_column:  # every token of the lexers
            return make_span(self.path, token.line, token.column, token.end_line, token.end_column, start, token.end_pos)
        return make_span(
            self.path, token.line or 1, token.column or 1, token.end_line or token.line or 1,
            token.end_column or (token.column or 1) + len(token), start if start is not None else -1,
            token.end_pos if token.end_pos is not None else -1,
        )

    def _name(self, token: Token) -> str:
        text = token.value if type(token) is Token else str(token)
        if text.startswith("^"):
            return text[1:]
        if text in (self._keywords or self.keywords):
            self.problems.append(
                error(f"'{text}' is a reserved word and cannot be used as a name (write ^{text} to escape it)", self._tspan(token))
            )
        return text
