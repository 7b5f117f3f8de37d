"""robogen.syntax.fastscan: the whole-text scanner finds the tokens Lark's root lexer finds.

Each match is one token (what the root lexer ignores is skipped by the prefix), named by its
terminal, or END or ERROR; the first-character analysis that allows reordering and unguarded
skipping is conservative.
"""

from __future__ import annotations

import re

import pytest
from lark.exceptions import UnexpectedCharacters

from lark.lexer import LexerState
from lark.utils import TextSlice

from robogen.syntax import fastscan
from robogen.syntax.fastscan import END, ERROR, START, _first, _reordered, whole_text_scanner
from robogen.syntax.parser import ROBOCHART, ROBOSIM, _fast_parser


def scan(scanner: re.Pattern, text: str) -> list[tuple[str, str]]:
    at = scanner.groupindex[START]
    out = []
    for m in scanner.finditer(text):
        out.append((m.lastgroup, text[m.start(at):m.end()]))
        if m.lastgroup in (END, ERROR):
            break
    return out


def lark_root_tokens(language: str, text: str) -> list[tuple[str, str]]:
    """(type, text) of the tokens of Lark's root lexer (no parser state: every terminal)."""
    root = _fast_parser(language)._lexer.root_lexer
    state = LexerState(TextSlice(text, 0, len(text)))
    return [(t.type, str(t)) for t in root.lex(state, None)]


def real_scanner(language: str) -> re.Pattern:
    return _fast_parser(language)._scanner


def test_first_characters():
    assert _first(r"[ \t]+") == frozenset(" \t")
    assert _first(r"\^?[A-Za-z_][A-Za-z0-9_]*") >= frozenset("^aZ_") and "0" not in _first(r"\^?[A-Za-z_][A-Za-z0-9_]*")
    assert _first(r"(?:ab|cd)") == frozenset("ac")
    assert _first(r"/\*(.|\n)*?\*/") == frozenset("/")
    assert _first("a*") is None  # can be empty
    assert _first("(?i:ab)") is None  # case folded: unknown
    assert _first(".x") is None  # any character
    assert _first("[^a]") is None


def test_an_ignored_terminal_after_an_overlapping_one_is_skipped_only_where_the_root_lexer_skips_it():
    patterns = {"KW": r"\-\-x", "COMMENT": r"\-\-[^\n]*", "WS": r"[ \n]+", "NAME": r"[a-z]+"}
    root = re.compile("|".join(f"(?P<{n}>{p})" for n, p in patterns.items()))
    scanner = whole_text_scanner(root, patterns, frozenset({"COMMENT", "WS"}))
    assert "(?!" in scanner.pattern  # COMMENT is guarded by KW, which can start where it does
    assert scan(scanner, "a --x b -- c d\ne") == [("NAME", "a"), ("KW", "--x"), ("NAME", "b"), ("NAME", "e"), (END, "")]
    assert scan(scanner, "a ?") == [("NAME", "a"), (ERROR, "?")]


def test_no_guard_where_the_first_characters_are_disjoint():
    patterns = {"NAME": r"[a-z]+", "WS": r"[ ]+"}
    root = re.compile("|".join(f"(?P<{n}>{p})" for n, p in patterns.items()))
    assert "(?!" not in whole_text_scanner(root, patterns, frozenset({"WS"})).pattern


def test_a_pattern_the_scanner_does_not_know_is_not_used():
    patterns = {"NAME": r"[a-z]+"}
    assert whole_text_scanner(re.compile(r"(?P<NAME>[a-z]+)|x"), patterns, frozenset()) is None
    assert whole_text_scanner(re.compile(r"(?P<NAME>[a-z]+)", re.I), patterns, frozenset()) is None


@pytest.mark.parametrize("language", [ROBOCHART, ROBOSIM])
def test_the_reordering_keeps_every_pair_that_can_start_alike_in_lark_order(language):
    fast = _fast_parser(language)
    root = fast._lexer.root_lexer
    regex = root.scanner._mres[0]
    patterns = {t.name: t.pattern.to_regexp() for t in root.terminals if t.name in regex.groupindex}
    order = [n for n in regex.groupindex if n not in root.ignore_types]
    new = _reordered(order, patterns)
    assert sorted(new) == sorted(order) and new != order  # some punctuation moved up
    position = {n: i for i, n in enumerate(new)}
    for j, b in enumerate(order):
        for a in order[:j]:
            fa, fb = _first(patterns[a]), _first(patterns[b])
            if fa is None or fb is None or fa & fb:
                assert position[a] < position[b], (a, b)
    assert position["SEMICOLON"] < position["__ANON_8"]  # ';' no longer tried after '/\'
    assert position["__ANON_5"] < position["COLON"]  # '::' before ':', as Lark


TEXTS = {
    "operators": "a::*b::c<->d->e=>f\\/g/\\h==i!=j<=k>=l[|m|](|n|)<{o",
    "comments": "a // line\n/* block\n more */ b /**/c//\n",
    "unterminated comment": "a /* no end",
    "numbers": "1 2.5 3. .4 x1 _y ^z",
    "strings": "\"a\\\"b\" 'c'",
    "only blanks": "  \n\t ",
    "empty": "",
}


@pytest.mark.parametrize("language", [ROBOCHART, ROBOSIM])
@pytest.mark.parametrize("text", TEXTS.values(), ids=TEXTS.keys())
def test_the_tokens_are_those_of_lark_root_lexer(language, text):
    scanner = real_scanner(language)
    keywords = _fast_parser(language)._keywords
    retyped = [(keywords.get(kind, {}).get(value, kind), value) for kind, value in scan(scanner, text)]
    assert retyped[-1] == (END, "")
    assert retyped[:-1] == lark_root_tokens(language, text)


def test_a_character_no_terminal_matches_ends_the_scan_with_error_where_lark_fails():
    scanner = real_scanner(ROBOCHART)
    text = "a = b & c"
    assert scan(scanner, text) == [("NAME", "a"), ("EQUAL", "="), ("NAME", "b"), (ERROR, "&")]
    with pytest.raises(UnexpectedCharacters) as failure:
        lark_root_tokens(ROBOCHART, text)
    assert failure.value.pos_in_stream == text.index("&")


def test_without_the_analysis_every_ignored_terminal_is_guarded_and_no_terminal_moves(monkeypatch):
    monkeypatch.setattr(fastscan, "sre_parse", None)  # a Python without re._parser
    root = _fast_parser(ROBOCHART)._lexer.root_lexer
    regex = root.scanner._mres[0]
    patterns = {t.name: t.pattern.to_regexp() for t in root.terminals if t.name in regex.groupindex}
    scanner = whole_text_scanner(regex, patterns, root.ignore_types)
    assert scanner.pattern.count("(?!") == len(root.ignore_types)
    order = [n for n in regex.groupindex if n not in root.ignore_types]
    assert [n for n in scanner.groupindex if n in order] == order
    keywords = _fast_parser(ROBOCHART)._keywords
    for text in TEXTS.values():
        retyped = [(keywords.get(kind, {}).get(value, kind), value) for kind, value in scan(scanner, text)]
        assert retyped[:-1] == lark_root_tokens(ROBOCHART, text)


@pytest.mark.parametrize("language", [ROBOCHART, ROBOSIM])
def test_the_alternation_the_fast_driver_builds_is_the_one_lark_matches_with(language):
    """FastLALR builds its root regex from the scanner's public terminals; Lark's own (one
    compiled alternation: Python's re has no group limit since 3.11) must be the same text."""
    root = _fast_parser(language)._lexer.root_lexer
    mres = root.scanner._mres
    assert len(mres) == 1
    alternation = "|".join(f"(?P<{t.name}>{t.pattern.to_regexp()})" for t in root.scanner.terminals)
    assert mres[0].pattern == alternation and mres[0].flags == re.compile(alternation, root.g_regex_flags).flags
