"""robogen.syntax.fastparse: the fast driver gives exactly what Lark gives.

For every model of the repository (and the reference models when ../shared is present): the
tokens the fast driver shifts equal those of Lark's contextual lexer in its own parse (type,
text, offsets, lines and columns), and the AST equals Lark's down to every span, with the same
reserved-word problems. A text Lark rejects makes the fast driver hand the parse back to Lark.
With ROBOGEN_FASTPARSE_CORPUS=PATH, the models under PATH are compared too (a local corpus).
"""

from __future__ import annotations

import dataclasses
import os
from pathlib import Path

import pytest
from lark.exceptions import UnexpectedInput
from support import ROOT
from support.frontend import MODEL_SUFFIXES, model_files, reference_files

from robogen.diagnostics import RobogenError, Span
from robogen.syntax.fastparse import FALLBACK
from robogen.syntax.parser import ROBOCHART, ROBOSIM, _ast_parser, _fast_parser, language_of, parse_text


def repository_models() -> list[Path]:
    return model_files(ROOT / "tests") + model_files(ROOT / "models")


def exact(x):
    """``x`` as nested tuples, with the fields equality ignores (spans) included."""
    if isinstance(x, Span):
        return ("Span", x.path, x.line, x.column, x.end_line, x.end_column, x.offset, x.end_offset)
    if dataclasses.is_dataclass(x):
        return (type(x).__name__,) + tuple((f.name, exact(getattr(x, f.name))) for f in dataclasses.fields(x))
    if isinstance(x, (tuple, list)):
        return tuple(exact(y) for y in x)
    return x


def token_tuple(t) -> tuple:
    return (t.type, str(t), t.start_pos, t.line, t.column, t.end_line, t.end_column, t.end_pos)


def drivers(language: str):
    """(fast driver, its Lark parser, their transformer): one pair, as parse_text takes it
    (threads that use the parser first, as tests/codegen's builds do, may build two)."""
    fast = _fast_parser(language)
    return fast, fast.lark, fast.lark.options.transformer


def lark_parse(text: str, language: str, path: str = "m"):
    """(tokens, tree, problems) of Lark's own parse; tree is None if Lark rejects the text."""
    _, parser, transformer = drivers(language)
    transformer.begin(path, text)
    try:
        interactive = parser.parse_interactive(text)
        tokens = list(interactive.iter_parse())
        tree = interactive.feed_eof(tokens[-1] if tokens else None)
    except UnexpectedInput:
        transformer.end()
        return None, None, None
    return [token_tuple(t) for t in tokens], tree, transformer.end()


def fast_parse(text: str, language: str, path: str = "m"):
    """(tokens, tree, problems) of the fast driver; tree is FALLBACK if it hands over to Lark."""
    fast, _, transformer = drivers(language)
    transformer.begin(path, text)
    trace: list = []
    tree = fast.parse(text, trace)
    return [token_tuple(t) for t in trace], tree, transformer.end()


def differences(text: str, language: str) -> str | None:
    """Why the fast driver and Lark disagree on ``text``, or None."""
    tokens, tree, problems = lark_parse(text, language)
    fast_tokens, fast_tree, fast_problems = fast_parse(text, language)
    if tree is None:
        return None if fast_tree is FALLBACK else "Lark rejects the text, the fast driver accepts it"
    if fast_tree is FALLBACK:
        return "the fast driver hands a text Lark accepts back to Lark"
    if fast_tokens != tokens:
        first = next(i for i, (a, b) in enumerate(zip(fast_tokens + [None], tokens + [None])) if a != b)
        return f"token {first}: fast {fast_tokens[first:first + 1]}, Lark {tokens[first:first + 1]}"
    if exact(fast_tree) != exact(tree):
        return "the ASTs differ"
    if [exact(d) for d in fast_problems] != [exact(d) for d in problems]:
        return f"the problems differ: fast {fast_problems}, Lark {problems}"
    return None


def test_the_fast_driver_is_usable_for_both_languages():
    assert _fast_parser(ROBOCHART).usable and _fast_parser(ROBOSIM).usable


def test_the_repository_has_models_of_every_kind():
    assert len(repository_models()) >= 60
    assert {p.suffix for p in repository_models()} == set(MODEL_SUFFIXES)


@pytest.mark.parametrize("path", repository_models(), ids=lambda p: str(p.relative_to(ROOT)))
def test_fast_and_lark_agree_on_every_repository_model(path):
    text = path.read_text(encoding="utf-8")
    assert differences(text, language_of(path)) is None


@pytest.mark.shared
@pytest.mark.parametrize("path", reference_files(), ids=lambda p: p.name)
def test_fast_and_lark_agree_on_every_reference_model(path):
    text = path.read_text(encoding="utf-8")
    assert differences(text, language_of(path)) is None


def local_corpus() -> list[Path]:
    """The models under $ROBOGEN_FASTPARSE_CORPUS, if set: a local checkout of other models
    (RoboTool's test models, say), compared without being part of the repository."""
    root = os.environ.get("ROBOGEN_FASTPARSE_CORPUS")
    return model_files(Path(root)) if root else []


@pytest.mark.parametrize("path", local_corpus(), ids=str)
def test_fast_and_lark_agree_on_every_model_of_a_local_corpus(path):
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        pytest.skip("not UTF-8 text")
    assert differences(text, language_of(path)) is None


# Texts where the token of the whole-text scan is not one the parser state accepts, so the
# state's own contextual lexer lexes there: a keyword where only a name is accepted is a name
# (which the transformer reports as reserved).
RELEXED = {
    "keyword as a variable": ("stm S { var state: nat }", ROBOCHART),
    "RoboSim keyword as a name": ("stm S { var exec: nat }", ROBOSIM),
    "exec is a name in RoboChart": ("stm S { var exec: nat }", ROBOCHART),
}


@pytest.mark.parametrize("text, language", RELEXED.values(), ids=RELEXED.keys())
def test_fast_and_lark_agree_where_the_state_lexes_differently(text, language):
    assert differences(text, language) is None
    tokens, tree, _ = fast_parse(text, language)
    assert tree is not FALLBACK


def test_a_reserved_word_as_a_name_is_lexed_as_a_name_and_reported():
    tokens, tree, problems = fast_parse("stm S { var state: nat }", ROBOCHART)
    assert tree is not FALLBACK
    assert tokens[4][:2] == ("NAME", "state")  # the whole-text scan said STATE
    assert tree.items[0].members[0].vars[0].name == "state"
    assert [(d.span.line, d.span.column, d.message) for d in problems] == [
        (1, 13, "'state' is a reserved word and cannot be used as a name (write ^state to escape it)")
    ]


SYNTAX_ERRORS = {
    "unknown character": "stm S { var x: nat = 1 & 2 }",
    "missing brace": "stm S { var x: nat ",
    "token out of place": "stm S { transition t { to a from b } }",
    "unterminated comment": "stm S { } /* no end",
    "unterminated string": 'stm S { var s: string = "abc\n }',
    # the state after `2` accepts `>=` (a reduction), so both lexers read `>=`, not `>` `==`
    "sequence end before ==": "stm S { var s: Seq(nat) = <1, 2>== <1> }",
}


@pytest.mark.parametrize("text", SYNTAX_ERRORS.values(), ids=SYNTAX_ERRORS.keys())
def test_a_syntax_error_hands_the_parse_back_to_lark(text):
    assert fast_parse(text, ROBOCHART)[1] is FALLBACK
    assert lark_parse(text, ROBOCHART)[1] is None
    with pytest.raises(RobogenError):
        parse_text(text, "m.rct")


def test_the_fast_driver_calls_the_transformer_parse_text_prepares():
    """Threads that use the parser first may build two (Lark, transformer) pairs, and the cache
    keep either: parse_text prepares the transformer whose callbacks the fast driver calls."""
    fast = _fast_parser(ROBOCHART)
    _ast_parser.cache_clear()  # another pair from now on, as a second thread may have built
    try:
        assert _ast_parser(ROBOCHART)[1] is not fast.lark.options.transformer
        first = parse_text("stm A { var a: nat }", "a.rct")
        second = parse_text("stm Bee { var b: nat = 1 }", "b.rct")
        assert differences("stm Bee { var b: nat = 1 }", ROBOCHART) is None  # the helpers take one pair too
    finally:
        _ast_parser.cache_clear()
        _fast_parser.cache_clear()
    assert (first.path, first.items[0].name, first.items[0].span.end_offset) == ("a.rct", "A", 20)
    assert (second.path, second.items[0].name, second.items[0].span.end_offset) == ("b.rct", "Bee", 26)
