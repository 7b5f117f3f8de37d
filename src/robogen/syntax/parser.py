"""Parse RoboChart (.rct) and RoboSim (.rst, .rsim) text into :mod:`robogen.syntax.ast`.

The grammars are loaded from the package data ``robogen.grammar`` (the top-level ``grammar/``
folder of the repository): ``robochart.lark``, and for RoboSim the same text followed by
``robosim.lark``, which only extends it. Both are LALR(1) with Lark's contextual lexer and
``strict=True`` (conflicts fail at load time); source spans come from the tokens.

Only robogen.syntax sees Lark: syntax errors are translated here into located
:class:`~robogen.diagnostics.Diagnostic` values, and :mod:`robogen.syntax.transform` builds
the AST nodes during the parse.
"""

from __future__ import annotations

import contextlib
import functools
import gc
import importlib.resources
import os
import re
import threading
from pathlib import Path

from lark import Lark, Token
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

from robogen.diagnostics import Diagnostic, RobogenError, Span, error
from robogen.syntax import ast
from robogen.syntax.fastparse import FALLBACK, FastLALR
from robogen.syntax.transform import MAX_NESTING, ToAst

__all__ = ["EXTENSIONS", "MAX_NESTING", "ROBOCHART", "ROBOSIM", "decode", "keywords", "language_of", "parse_file",
           "parse_text", "without_gc"]  # fmt: skip

ROBOCHART = "robochart"
ROBOSIM = "robosim"

EXTENSIONS = {".rct": ROBOCHART, ".rst": ROBOSIM, ".rsim": ROBOSIM}


def language_of(path: str | os.PathLike) -> str | None:
    return EXTENSIONS.get(Path(path).suffix.lower())


# ---------------------------------------------------------------------------- grammar loading


def _grammar_text(name: str) -> str:
    return (importlib.resources.files("robogen.grammar") / name).read_text(encoding="utf-8")


@functools.lru_cache(maxsize=None)
def _parser(language: str) -> Lark:
    """The bare parser of a language (for keywords, error tables and benchmarks)."""
    return Lark(_grammar(language), parser="lalr", lexer="contextual", strict=True, maybe_placeholders=False)


def _grammar(language: str) -> str:
    text = _grammar_text("robochart.lark")
    if language == ROBOSIM:
        text += "\n" + _grammar_text("robosim.lark")
    return text


@functools.lru_cache(maxsize=None)
def _ast_parser(language: str) -> tuple[Lark, ToAst]:
    """The parser that builds the AST while it parses: the transformer's callbacks run at each
    LALR reduction, so no intermediate tree is built. Positions are computed by the callbacks
    from the tokens (Lark's generic position propagation would cost as much as the parse)."""
    transformer = ToAst(language, lambda: keywords(language))
    parser = Lark(
        _grammar(language),
        parser="lalr",
        lexer="contextual",
        strict=True,
        maybe_placeholders=False,
        transformer=transformer,
        # The LALR tables are cached in the temp folder, keyed by the grammar text: a cold
        # `robogen check` then starts in ~0.1 s instead of ~0.5 s per language.
        cache=True,
    )
    return parser, transformer


@functools.lru_cache(maxsize=None)
def _fast_parser(language: str) -> FastLALR:
    """The fast driver over the AST parser's tables (see :mod:`robogen.syntax.fastparse`)."""
    return FastLALR(_ast_parser(language)[0])


_lock = threading.Lock()


@contextlib.contextmanager
def without_gc():
    """Pause the cyclic garbage collector while a front-end stage builds its large, mostly
    acyclic structures: its collections would otherwise scan them again and again (a quarter
    of the time of checking a 20,000-line model). Garbage made meanwhile is collected later.

    At the end, what was made meanwhile goes to the oldest generation at once (``gc.freeze``
    then ``gc.unfreeze``, unless the program keeps objects frozen itself): otherwise the first
    allocation after the pause would scan all of it as the youngest generation (a twentieth of
    the time of parsing a large model), and the next generation would scan it again, before it
    reaches the oldest, which a full collection scans as usual."""
    if not gc.isenabled():
        yield
        return
    gc.disable()
    try:
        yield
    finally:
        if not gc.get_freeze_count():
            gc.freeze()
            gc.unfreeze()
        gc.enable()


@functools.lru_cache(maxsize=None)
def keywords(language: str) -> frozenset[str]:
    """The reserved words of a language: every word the grammar uses as a literal."""
    words = set()
    for terminal in _ast_parser(language)[0].terminals:
        pattern = terminal.pattern
        if pattern.type == "str" and re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", pattern.value):
            words.add(pattern.value)
    return frozenset(words)


@functools.lru_cache(maxsize=None)
def _terminal_texts(language: str) -> dict[str, str]:
    """Terminal name -> how to show it in an error message."""
    names = {
        "NAME": "a name",
        "INT": "an integer",
        "REAL": "a real number",
        "STRING": "a string",
        "$END": "end of file",
    }
    for terminal in _ast_parser(language)[0].terminals:
        if terminal.name in names:
            continue
        if terminal.pattern.type == "str":
            names[terminal.name] = f"'{terminal.pattern.value}'"
        else:
            names[terminal.name] = terminal.name.lower()
    return names


# ---------------------------------------------------------------------------- entry points


def parse_text(text: str, path: str = "<string>", language: str | None = None) -> ast.File:
    """Parse one model. Raises RobogenError with located diagnostics on bad input."""
    language = language or language_of(path) or ROBOCHART
    nul = text.find("\x00")
    if nul >= 0:
        line = text.count("\n", 0, nul) + 1
        column = nul - (text.rfind("\n", 0, nul) + 1) + 1
        raise RobogenError(error("file contains NUL bytes; is it a binary file, not a model?", Span.point(path, line, column)))
    # the parser whose callbacks the fast driver calls (threads may have built two on first use)
    fast = _fast_parser(language)
    parser, transformer = fast.lark, fast.lark.options.transformer
    with _lock, without_gc():  # the transformer holds the state of the file being parsed
        transformer.begin(path, text)
        try:
            result = fast.parse(text)
            if result is FALLBACK:  # Lark parses it again, and reports any syntax error
                transformer.begin(path, text)
                result = parser.parse(text)
        except UnexpectedInput as exc:
            raise RobogenError(_syntax_error(exc, text, path, language)) from None
        finally:
            problems = transformer.end()
    if problems:
        raise RobogenError(problems)
    return result


def parse_file(path: str | os.PathLike, language: str | None = None) -> ast.File:
    path = os.fspath(path)
    try:
        data = Path(path).read_bytes()
    except FileNotFoundError:
        raise RobogenError(error(f"no such file: {path}", None)) from None
    except IsADirectoryError:
        raise RobogenError(error(f"{path} is a directory, not a model file", None)) from None
    except OSError as exc:
        raise RobogenError(error(f"cannot read {path}: {exc.strerror}", None)) from None
    return parse_text(decode(data, path), path, language)


def decode(data: bytes, path: str) -> str:
    """UTF-8 text of a model file (a BOM is allowed); a located error otherwise."""
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        good = data[: exc.start].decode("utf-8", errors="replace")
        line = good.count("\n") + 1
        column = len(good) - (good.rfind("\n") + 1) + 1
        raise RobogenError(
            error(
                f"not valid UTF-8 text (byte 0x{data[exc.start]:02x} at offset {exc.start}); models must be UTF-8",
                Span.point(path, line, column),
            )
        ) from None


# ---------------------------------------------------------------------------- syntax errors

_MAX_EXPECTED = 8


# Terminals that can start an expression: a list containing all of these is shown as
# "an expression" rather than token by token.
_EXPRESSION_STARTERS = {"NAME", "INT", "REAL", "STRING", "LPAR"}

_TRANSITION_CLAUSES = ("trigger", "exec", "probability", "#", "<{", "condition", "action", "from", "to")


def _syntax_error(exc: UnexpectedInput, text: str, path: str, language: str) -> Diagnostic:
    names = _terminal_texts(language)
    line, column = getattr(exc, "line", 1) or 1, getattr(exc, "column", 1) or 1
    if isinstance(exc, UnexpectedCharacters):
        ch = text[exc.pos_in_stream] if exc.pos_in_stream < len(text) else ""
        span = Span(path, line, column, line, column + 1)
        if ch in "\"'":
            return error(f"unterminated string: no closing {ch} on this line", span)
        what = f"character {ch!r}" if ch.isprintable() else f"character U+{ord(ch):04X}"
        diagnostic = error(f"unexpected {what}", span)
        if text.startswith("&&", exc.pos_in_stream):
            diagnostic = diagnostic.with_note("'and' is written /\\")
        return diagnostic
    expected = _expected(exc, names)
    if isinstance(exc, UnexpectedEOF) or (isinstance(exc, UnexpectedToken) and exc.token.type == "$END"):
        # lines are counted at "\n" only, as the lexer does (not at a lone "\r" or U+2028)
        last = text.count("\n") + 1
        end_col = len(text) - (text.rfind("\n") + 1) + 1
        return error(f"unexpected end of file; expected {expected}", Span(path, last, end_col, last, end_col + 1))
    assert isinstance(exc, UnexpectedToken)
    token = exc.token
    span = _token_span(path, token)
    word = str(token.value)
    start = token.start_pos if token.start_pos is not None else 0
    if word == "/" and text.startswith("/*", start):
        return error("unterminated comment: '/*' has no matching '*/'", Span(path, span.line, span.column, span.line, span.column + 2))
    if token.type == "NAME" and word in keywords(language):
        shown = f"'{word}'"
    elif token.type in ("NAME", "INT", "REAL", "STRING"):
        shown = f"{names[token.type].split(' ', 1)[1]} '{word}'"
    else:
        shown = f"'{word}'"
    diagnostic = error(f"unexpected {shown}; expected {expected}", span)
    if word in _TRANSITION_CLAUSES:
        diagnostic = diagnostic.with_note(
            "the clauses of a transition come in this order: from, to, trigger (or exec, or probability), "
            "#clock resets, <{deadline}, condition, action"
        )
    for note in _hints(text, start, word, expected):
        diagnostic = diagnostic.with_note(note)
    return diagnostic


def _hints(text: str, start: int, word: str, expected: str) -> list[str]:
    """Notes for mistakes people coming from other languages make."""
    hints = []
    if word == "|" and text.startswith("||", start):
        hints.append("'or' is written \\/")
    elif word == "!" and "an expression" in expected:
        hints.append("negation is written 'not'")
    elif word == ":" and text.startswith(":=", start):
        hints.append("assignment is written '='")
    before = text[:start].rstrip()
    if before.endswith(";") and "'skip'" in expected:
        hints.append("';' separates statements: there is none after the last one")
    # forms of RoboTool's older grammars that have no current form (robogen.syntax.transform_obsolete)
    if word == "@" and re.search(r"\btrigger\b[^{}]*$", before):
        hints.append("the time binding '@ t' of a trigger was removed from RoboChart (RoboTool's grammar of 2020-11) and "
                     "has no current form: measure time with a clock, reset on the transition ('#C') and read with 'since(C)'")
    elif word == "{" and re.match(r"\{[^{}]*\}>", text[start:]):
        hints.append("start deadlines '{ d }>' were removed from RoboChart (RoboTool's grammar of 2020-10) and have no "
                     "current form: a deadline '<{ d }' after a trigger or a statement bounds when it ends")
    return hints


# Tokens that close a construct: listed first among the expected tokens, as forgetting one is
# the commonest reason for an error at the end of a file or block.
_CLOSERS = ("'}'", "')'", "']'", "'|)'", "'|]'", "'end'", "'>'")


def _expected(exc: UnexpectedInput, names: dict[str, str]) -> str:
    expected: set[str] = set(getattr(exc, "expected", None) or ())
    interactive = getattr(exc, "interactive_parser", None)
    if interactive is not None:
        try:  # exact: simulates the reductions LALR's default actions may already have made
            expected = set(interactive.accepts()) or expected
        except Exception:  # pragma: no cover - fall back to Lark's own set
            pass
    shown: list[str] = []
    if _EXPRESSION_STARTERS <= expected:
        expected = {t for t in expected - _EXPRESSION_STARTERS if not _starts_expression(names.get(t, ""))}
        shown.append("an expression")
    words = sorted({names.get(t, t.lower()) for t in expected})
    if "'->'" in words:  # after a type: the vector type T^n of 2020-02 is read, never proposed
        words.remove("'^'")
    words.sort(key=lambda s: (s not in _CLOSERS, s.startswith("a ") or s.startswith("an "), s))
    shown = words + shown if shown else words
    if not shown:
        return "something else"
    if len(shown) > _MAX_EXPECTED + 1:  # never "(1 more)": the one would fit in its place
        return f"one of {', '.join(shown[:_MAX_EXPECTED])}, ... ({len(shown) - _MAX_EXPECTED} more)"
    if len(shown) == 1:
        return shown[0]
    return ", ".join(shown[:-1]) + " or " + shown[-1]


def _starts_expression(shown: str) -> bool:
    return shown in {"'('", "'(|'", "'['", "'[|'", "'{'", "'<'", "'-'", "'$'", "'not'", "'if'", "'let'", "'the'",
                     "'forall'", "'exists'", "'exists1'", "'lambda'", "'since'", "'sinceEntry'", "'result'",
                     "'from'", "'to'", "'true'", "'false'", "'inverse'", "'transpose'", "'cycle'"}


def _token_span(path: str, token: Token) -> Span:
    line = token.line or 1
    column = token.column or 1
    end_line = token.end_line or line
    end_column = token.end_column or column + max(1, len(str(token.value)))
    return Span(path, line, column, end_line, end_column)
