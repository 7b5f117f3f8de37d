"""A faster driver for the LALR parse, over Lark's own compiled tables.

Lark stays the home of the grammar: this module reads everything from a loaded ``Lark`` object
(the root lexer's compiled regular expression and keyword table, the contextual lexer of each
parser state, the LALR parse table and the rule callbacks that build the AST) and duplicates
nothing. It only drives them with less overhead:

- one scan of the text with the root lexer's regular expression, rewritten so that each match
  is one token (see :mod:`robogen.syntax.fastscan`: what the root lexer ignores is skipped
  inside the match), keywords retyped from names by a dictionary;
- the scan inlined in one loop with the parse table in locals; a chain of reductions by
  ``?rules`` with one child, or by rules whose callback is marked ``first_child``, which keep
  their child unchanged, only replaces the state (memoised per state below, state and token);
  other reductions call the transformer method inside Lark's callback with the children
  Lark's child filter would give it (the helper rules Lark names ``_...`` and splices into
  their parent are plain lists, not Trees), then the goto and the unit reductions after it
  are one memoised step; Lark ``Token`` objects are made only for the terminals some rule
  keeps, their lines and columns looked up in a table of line starts (lines counted at
  ``"\\n"``, as Lark counts them).

Why the tokens are Lark's: Lark's contextual lexer matches, in each parser state, the
alternation of the terminals that state accepts, in the root lexer's order. When the token the
whole-text scan finds is accepted in the current state, every terminal before it in the state's
alternation is also before it in the root alternation and did not match, so the contextual
lexer finds the same token (keywords included: both retype a name to the keyword only where
the keyword is a terminal of the lexer). When the token is not accepted there, the state's own
contextual lexer (Lark's) lexes at that position instead, and the scan resumes after it.

Anything else (a character no terminal matches, a token no state accepts, a grammar feature
this driver does not handle) returns :data:`FALLBACK`, and the caller parses with Lark itself,
so syntax errors are Lark's, unchanged.
"""

from __future__ import annotations

import re
from bisect import bisect_right
from operator import itemgetter

from lark import Lark, Token
from lark.exceptions import LexError, UnexpectedInput
from lark.grammar import Rule
from lark.lexer import ContextualLexer, LexerState, LineCounter, UnlessCallback
from lark.parse_tree_builder import ChildFilterLALR_NoPlaceholders, ExpandSingleChild
from lark.parsers.lalr_analysis import Shift
from lark.utils import TextSlice

from robogen.syntax.fastscan import END, ERROR, START, whole_text_scanner

__all__ = ["FALLBACK", "FastLALR"]

FALLBACK = object()
"""What :meth:`FastLALR.parse` returns when Lark must parse the text itself."""

_END = "$END"
_NEWLINES = re.compile("\n")  # lines are counted at "\n" only, as Lark's lexer counts them


def _plan(rule: Rule, callback, transformer) -> tuple[tuple, tuple[int, ...]] | None:
    """How to reduce by ``rule``: (size, origin, passthrough, select, mode, function), and
    the indices of the children that reach a callback; None if the callback is wrapped in a way
    this driver does not know (then it is not used).

    ``passthrough``: a ``?rule`` with one kept child and no alias, or a rule of one child whose
    callback is marked ``first_child`` (it returns the child): the value stays as it is.
    Otherwise ``function`` is called with the children ``select`` picks as Lark's child filter
    does (None: all; an index; an itemgetter of several; pairs (index, expand) where children
    of ``_rules`` are spliced in), when ``mode`` is 0; when it is 1 (Lark's ExpandSingleChild),
    the single child is the value if only one is left; when it is 2, the value is the list of
    the children: that of a ``_rule`` that the transformer does not handle (Lark makes a Tree,
    which only its parent reads)."""
    size = len(rule.expansion)
    f, include, expand1 = callback, None, False
    if type(f) is ChildFilterLALR_NoPlaceholders:
        include = tuple(f.to_include)
        f = f.node_builder
    if type(f) is ExpandSingleChild:
        expand1 = True
        f = f.node_builder
    if isinstance(f, (ChildFilterLALR_NoPlaceholders, ExpandSingleChild)) or not callable(f):
        return None  # nested wrappers
    name = rule.origin.name
    mode = 1 if expand1 else 0
    if name.startswith("_") and not rule.alias and not expand1 and getattr(transformer, name, None) is None:
        mode, f = 2, _as_list
    indices = tuple(range(size)) if include is None else tuple(i for i, _ in include)
    select = None
    if include is not None and any(expand for _, expand in include):
        select = include
    elif len(indices) != size:
        select = indices[0] if len(indices) == 1 else itemgetter(*indices) if indices else _nothing
    passthrough = (expand1 or getattr(f, "first_child", False)) and size == 1 and select is None
    return (size, name, passthrough, select, mode, f), indices


def _as_list(kids: list) -> list:
    return kids


def _nothing(kids: list) -> tuple:
    return ()


def _splice(kids: list, include: tuple[tuple[int, bool], ...]) -> list:
    """Lark's child filter where ``_rules`` are expanded (their values are lists here)."""
    filtered: list = []
    for i, expand in include:
        if not expand:
            filtered.append(kids[i])
        elif filtered:
            filtered += kids[i]
        else:  # reused, as Lark does for left recursion
            filtered = kids[i]
    return filtered


def _kept(rule: Rule, indices: tuple[int, ...]) -> set[str]:
    """The terminals of ``rule`` that reach a callback (their tokens must be real Tokens)."""
    return {rule.expansion[i].name for i in indices if rule.expansion[i].is_term}


class _Everything:
    def __contains__(self, item) -> bool:
        return True


class FastLALR:
    """The fast driver for one loaded Lark parser (LALR, contextual lexer, inline transformer)."""

    def __init__(self, lark: Lark):
        self.usable = False
        self.lark = lark
        frontend = lark.parser
        lexer = frontend.lexer
        if lark.options.postlex is not None or not isinstance(lexer, ContextualLexer) or len(lark.options.start) != 1:
            return
        root = lexer.root_lexer
        scanner = root.scanner
        if scanner.use_bytes or not all(type(cb) is UnlessCallback for cb in root.callback.values()):
            return
        # The scanner's one alternation of named groups, in its terminals' order (the order Lark
        # gives them: priority, then longest), compiled with its flags: the regex Lark matches with.
        alternation = "|".join(f"(?P<{t.name}>{t.pattern.to_regexp()})" for t in scanner.terminals)
        regex = scanner.re_.compile(alternation, scanner.g_regex_flags)
        parser = frontend.parser.parser
        table = parser.parse_table
        callbacks = parser.callbacks
        if not all(isinstance(key, Rule) for key in callbacks):
            return  # terminal callbacks: not handled here
        start = lark.options.start[0]
        self._lexer = lexer
        patterns = {t.name: t.pattern.to_regexp() for t in root.terminals if t.name in regex.groupindex}
        self._scanner = whole_text_scanner(regex, patterns, root.ignore_types)
        if self._scanner is None:
            return
        # name type -> {keyword text: keyword type}, as the root lexer's UnlessCallback retypes
        self._keywords = {
            kind: {t.pattern.value: t.name for t in cb.scanner.terminals} for kind, cb in root.callback.items()
        }
        self._newline = root.newline_types
        planned = {rule: _plan(rule, cb, lark.options.transformer) for rule, cb in callbacks.items()}
        if None in planned.values():
            return  # a callback wrapped in a way this driver does not know
        plans = {rule: plan for rule, (plan, _) in planned.items()}
        self._kept = set().union(*(_kept(rule, indices) for rule, (_, indices) in planned.items()))
        self._states = [None] * (max(table.states) + 1)
        for state, actions in table.states.items():
            self._states[state] = {
                kind: (arg if action is Shift else plans[arg]) for kind, (action, arg) in actions.items()
            }
        self._units: dict[tuple[int, int, str], tuple[int, object]] = {}  # memo of _unit_chain
        self._gotos: dict[tuple[int, str, str], tuple[int, object]] = {}  # memo of _goto
        self._start = table.start_states[start]
        self._end = table.end_states[start]
        self.usable = True

    def parse(self, text: str, trace: list | None = None):
        """The value of the start rule's callback, or FALLBACK; with a ``trace`` list, each token
        the parser shifts is appended to it (a Lark Token; for tests)."""
        if not self.usable:
            return FALLBACK
        states, units, gotos, end_state, keywords = self._states, self._units, self._gotos, self._end, self._keywords
        kept, newline, new_str = self._kept if trace is None else _Everything(), self._newline, str.__new__
        finditer, at = self._scanner.finditer, self._scanner.groupindex[START]
        line_starts = [0]
        line_starts += [m.end() for m in _NEWLINES.finditer(text)]
        stack, values, pos = [self._start], [], 0
        while True:  # one scan, resumed after a token the state's own lexer gives
            for m in finditer(text, pos):
                kind = m.lastgroup
                start = m.start(at)
                end = m.end()
                word = None
                if (retype := keywords.get(kind)) is not None:  # a name: a keyword if its text is one
                    word = text[start:end]
                    kind = retype.get(word, kind)
                relexed = None
                action = states[stack[-1]].get(kind)
                if action is None:  # the end, or a token not accepted here: the state's own lexer decides
                    kind, action, relexed = self._unexpected(stack[-1], kind, text, start, line_starts)
                    if action is None:
                        return FALLBACK  # a syntax error: Lark reports it
                    if relexed is not None:
                        end = relexed.end_pos
                try:
                    while type(action) is not int:  # reductions before the shift
                        if action[2]:  # a chain of unit reductions: only the state changes
                            state, action = units.get((stack[-2], stack[-1], kind)) or self._unit_memo(stack[-2], stack[-1], kind)
                            stack[-1] = state
                            if action is None:
                                raise KeyError(kind)  # at the end state: accepted below
                            continue
                        size, origin, _, select, mode, f = action
                        kids = values[-size:] if size else []
                        if size:
                            del values[-size:], stack[-size:]
                        if select is not None:
                            kind_of = type(select)
                            kids = [kids[select]] if kind_of is int else _splice(kids, select) if kind_of is tuple else list(select(kids))
                        value = f(kids) if not mode else kids if mode == 2 else kids[0] if len(kids) == 1 else f(kids)
                        # the goto and the unit reductions after it
                        state, action = gotos.get((stack[-1], origin, kind)) or self._goto_memo(stack[-1], origin, kind)
                        stack.append(state)
                        values.append(value)
                        if action is None:
                            raise KeyError(kind)  # at the end state: accepted below
                except KeyError:  # a syntax error (Lark reports it), or the end of the parse
                    return values[-1] if kind is _END and stack[-1] == end_state else FALLBACK
                if kind is _END:
                    return FALLBACK  # Lark never shifts the end
                if kind not in kept:
                    token = None
                elif relexed is not None:
                    token = relexed
                else:  # Lark's Token, its line and column from the table of line starts
                    line = bisect_right(line_starts, start)
                    line_start = line_starts[line - 1]
                    if word is None:
                        word = text[start:end]
                    token = new_str(Token, word)
                    token.type, token.value, token.start_pos = kind, word, start
                    token.line, token.column, token.end_pos = line, start - line_start + 1, end
                    if kind in newline and (end_line := bisect_right(line_starts, end)) != line:
                        line, line_start = end_line, line_starts[end_line - 1]
                    token.end_line, token.end_column = line, end - line_start + 1
                stack.append(action)
                values.append(token)
                if trace is not None:
                    trace.append(token)
                if relexed is not None:
                    pos = end
                    break  # scan again from after it
            else:
                return FALLBACK  # not reached: the scan ends with END or ERROR

    def _unexpected(self, state: int, kind: str, text: str, start: int, line_starts: list[int]):
        """(type, action, relexed token or None) for a token of the scan that ``state`` has no
        action for: the end of the text, or what the state's own lexer finds there; the action
        is None if there is none (a syntax error)."""
        actions = self._states[state]
        if kind == END:
            return _END, actions.get(_END), None
        if kind == ERROR:
            return kind, None, None
        relexed = self._relex(state, text, start, line_starts)
        if relexed is None:
            return kind, None, None
        return relexed.type, actions.get(relexed.type), relexed

    def _unit_memo(self, below: int, state: int, kind: str) -> tuple[int, object]:
        self._units[below, state, kind] = chain = self._unit_chain(below, state, kind)
        return chain

    def _goto_memo(self, below: int, origin: str, kind: str) -> tuple[int, object]:
        self._gotos[below, origin, kind] = step = self._goto(below, origin, kind)
        return step

    def _goto(self, below: int, origin: str, kind: str) -> tuple[int, object]:
        """The state after a reduction to ``origin`` above ``below`` and the unit reductions
        there on ``kind``, and the action then (as :meth:`_unit_chain`)."""
        state = self._states[below][origin]
        if state == self._end:
            return state, None
        return self._unit_chain(below, state, kind)

    def _unit_chain(self, below: int, state: int, kind: str) -> tuple[int, object]:
        """The state after the unit reductions from ``state`` (above ``below``) on ``kind``, and
        the action there (None at the end state, where the parse is over); a missing action
        raises KeyError (a syntax error)."""
        states = self._states
        action = states[state][kind]
        while type(action) is not int and action[2]:
            state = states[below][action[1]]
            if state == self._end:
                return state, None
            action = states[state][kind]
        return state, action

    def _relex(self, state: int, text: str, pos: int, line_starts: list[int]) -> Token | None:
        """The token Lark's contextual lexer finds at ``pos`` in parser state ``state``."""
        line = bisect_right(line_starts, pos)
        counter = LineCounter("\n")
        counter.char_pos = pos
        counter.line = line
        counter.line_start_pos = line_starts[line - 1]
        counter.column = pos - counter.line_start_pos + 1
        try:
            return self._lexer.lexers[state].next_token(LexerState(TextSlice(text, 0, len(text)), counter))
        except (UnexpectedInput, LexError, EOFError):
            return None
