"""The whole-text scanner of the fast LALR driver (:mod:`robogen.syntax.fastparse`).

It is Lark's root lexer regular expression (the alternation of the terminals, one named group
each, in Lark's order), with changes that let one match give the driver one token cheaply:

- a possessive prefix skips what the root lexer would skip (whitespace and comments, its
  ``ignore`` terminals) before the token, so no match is ever an ignored token;
- the alternation holds the other terminals, reordered where that changes no match (see
  :func:`_reordered`) so that frequent short tokens are tried early; each terminal's group is
  empty and after its pattern (``;(?P<SEMICOLON>)``), so that the alternative starts with its
  first character, which the regular expression engine checks before it tries the rest, and
  still names the terminal (``lastgroup``); the empty group ``START`` before the alternation
  marks where the token starts, and the match ends where it ends;
- two last alternatives end every scan: ``END`` (the end of the text) and ``ERROR`` (one
  character no terminal matches), so the matches of ``finditer`` are contiguous and the driver
  needs no check of its own that nothing was skipped.

The prefix skips exactly what the root lexer skips: at each position the root lexer takes the
first alternative that matches, so an ignored terminal is taken only where no terminal before
it matches. The prefix's alternative for that ignored terminal is guarded by a negative
lookahead over the terminals before it, except those that provably cannot match where it does
(no first character in common, computed from the parsed regular expressions; anything the
analysis does not know is assumed to overlap, which only costs a lookahead).
"""

from __future__ import annotations

import heapq
import re

try:  # the standard library's parser of regular expressions (private; only proves orders safe)
    import re._constants as sre
    import re._parser as sre_parse
except ImportError:  # pragma: no cover - another Python: every pair is assumed to overlap
    sre = sre_parse = None  # type: ignore[assignment]

__all__ = ["END", "ERROR", "START", "whole_text_scanner"]

END = "fastscan_end"
ERROR = "fastscan_error"
START = "fastscan_start"

_LARGE = 4096  # a character class with more members than this is "any character" to the analysis


def whole_text_scanner(regex: re.Pattern, patterns: dict[str, str], ignore: frozenset[str]) -> re.Pattern | None:
    """The scanner over Lark's root ``regex``, whose terminals' regular expressions are
    ``patterns`` (by name) and of which ``ignore`` are skipped; None if it cannot be built."""
    order = list(regex.groupindex)
    if sorted(order) != sorted(patterns) or {END, ERROR, START} & set(order):
        return None
    if regex.pattern != "|".join(f"(?P<{name}>{patterns[name]})" for name in order):
        return None  # not the plain alternation this module knows
    if regex.flags & (re.IGNORECASE | re.VERBOSE):
        return None
    skips, before = [], []
    for name in order:
        if name not in ignore:
            before.append(name)
            continue
        first = _first(patterns[name])
        guards = [patterns[n] for n in before if _may_overlap(first, _first(patterns[n]))]
        guard = f"(?!{'|'.join(f'(?:{g})' for g in guards)})" if guards else ""
        skips.append(f"{guard}(?:{patterns[name]})")
    prefix = f"(?:{'|'.join(skips)})*+" if skips else ""
    tokens = _reordered([name for name in order if name not in ignore], patterns)
    alternation = "|".join(f"(?:{patterns[name]})(?P<{name}>)" for name in tokens)
    try:
        return re.compile(f"{prefix}(?P<{START}>)(?:{alternation}|(?s:.)(?P<{ERROR}>)|\\Z(?P<{END}>))", regex.flags)
    except (re.error, RecursionError, OverflowError):
        return None


def _reordered(order: list[str], patterns: dict[str, str]) -> list[str]:
    """The terminals of ``order`` (an alternation, first match wins) in an order that gives
    the same match everywhere and tries short fixed tokens early: a terminal moves ahead of
    another only if no text can start with both (their first characters are disjoint), so at
    any position at most one of the two can match. Among the terminals free to go next: those
    of variable length (names, numbers) first, then fixed ones, shortest first (punctuation,
    which the root order tries last)."""
    firsts = [_first(patterns[name]) for name in order]
    after: list[list[int]] = [[] for _ in order]  # i -> the later terminals that must stay after i
    blockers = [0] * len(order)
    for j in range(len(order)):
        for i in range(j):
            if _may_overlap(firsts[i], firsts[j]):
                after[i].append(j)
                blockers[j] += 1
    ready = [(_rank(patterns[name]), i) for i, name in enumerate(order) if not blockers[i]]
    heapq.heapify(ready)
    result = []
    while ready:
        _, i = heapq.heappop(ready)
        result.append(order[i])
        for j in after[i]:
            blockers[j] -= 1
            if not blockers[j]:
                heapq.heappush(ready, (_rank(patterns[order[j]]), j))
    return result


def _rank(pattern: str) -> int:
    """0 for a terminal of variable length, else its length (as the scanner prefers them)."""
    if sre_parse is None:
        return 0
    try:
        low, high = sre_parse.parse(pattern).getwidth()
    except (re.error, RecursionError, TypeError, ValueError, AttributeError):
        return 0
    return 0 if low != high else low


def _may_overlap(a: frozenset[str] | None, b: frozenset[str] | None) -> bool:
    return a is None or b is None or not a.isdisjoint(b)


def _first(pattern: str) -> frozenset[str] | None:
    """The characters a match of ``pattern`` can start with; None if unknown, or if the pattern
    can match the empty string."""
    if sre_parse is None:
        return None
    try:
        chars, nullable = _first_of_sequence(list(sre_parse.parse(pattern)))
    except (re.error, RecursionError, TypeError, ValueError, AttributeError):
        return None
    return None if chars is None or nullable else frozenset(chars)


def _first_of_sequence(items: list) -> tuple[set[str] | None, bool]:
    """(first characters, can be empty) of a sequence of parsed items."""
    chars: set[str] = set()
    for op, arg in items:
        first, nullable = _first_of_item(op, arg)
        if first is None:
            return None, False
        chars |= first
        if not nullable:
            return chars, False
    return chars, True


def _first_of_item(op, arg) -> tuple[set[str] | None, bool]:
    if op is sre.LITERAL:
        return {chr(arg)}, False
    if op is sre.IN:
        return _first_of_class(arg), False
    if op is sre.BRANCH:
        chars: set[str] = set()
        nullable = False
        for branch in arg[1]:
            first, empty = _first_of_sequence(list(branch))
            if first is None:
                return None, False
            chars |= first
            nullable = nullable or empty
        return chars, nullable
    if op is sre.SUBPATTERN:
        _, add_flags, _, sub = arg
        if add_flags & (sre.SRE_FLAG_IGNORECASE | sre.SRE_FLAG_VERBOSE):
            return None, False
        return _first_of_sequence(list(sub))
    if op in (sre.MAX_REPEAT, sre.MIN_REPEAT, sre.POSSESSIVE_REPEAT):
        low, _, sub = arg
        first, empty = _first_of_sequence(list(sub))
        return first, empty or low == 0
    if op is sre.AT:
        return set(), True  # an anchor: zero width
    return None, False  # any character, assertions, back references: unknown


def _first_of_class(items) -> set[str] | None:
    chars: set[str] = set()
    for op, arg in items:
        if op is sre.LITERAL:
            chars.add(chr(arg))
        elif op is sre.RANGE and arg[1] - arg[0] < _LARGE:
            chars.update(chr(c) for c in range(arg[0], arg[1] + 1))
        else:  # NEGATE, categories, huge ranges
            return None
    return chars
