"""robogen.semantics.check_texts on broken input, property-based: random mutations of the valid
models (token deletions, swaps, duplications and replacements, truncations, byte noise
including invalid UTF-8 and NUL) either check or give located diagnostics; nothing else escapes. A mutant that
still parses also prints back to an equal tree."""

from __future__ import annotations

import re

from support.frontend import corpus_files
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from robogen.diagnostics import Diagnostic, RobogenError
from robogen.semantics import check_texts
from robogen.syntax import printer
from robogen.syntax.parser import decode, parse_text

SEEDS = [(p.name, p.read_bytes()) for p in corpus_files()]

# a token with the blanks before it, so that deleting or moving it keeps the text's layout
TOKEN = re.compile(rb"\s*(?:\w+|[^\w\s])|\s+$")

WORD = re.compile(rb"\w+")

INTERESTING_BYTES = [b"\x00", b"\xff", b"\xc3", b"\xe2\x82", b"\xed\xa0\x80", b"\x1b[0m", b"\r", b"\t", b"^", b"$", b"'", b'"', b"/*"]

index = st.integers(min_value=0, max_value=10_000)
mutation = st.one_of(
    st.tuples(st.just("delete"), index),
    st.tuples(st.just("swap"), index, index),
    st.tuples(st.just("duplicate"), index, index),
    st.tuples(st.just("replace"), index, index),
    st.tuples(st.just("truncate"), index),
    st.tuples(st.just("noise"), index, st.one_of(st.sampled_from(INTERESTING_BYTES), st.binary(min_size=1, max_size=6))),
)


def mutate(data: bytes, mutations: list[tuple]) -> bytes:
    tokens = TOKEN.findall(data)
    for m in mutations:
        if not tokens:
            break
        kind, at = m[0], m[1] % len(tokens)
        if kind == "delete":
            del tokens[at]
        elif kind == "swap":
            other = m[2] % len(tokens)
            tokens[at], tokens[other] = tokens[other], tokens[at]
        elif kind == "duplicate":
            tokens.insert(m[2] % (len(tokens) + 1), tokens[at])
        elif kind == "replace":  # another token of the model in this one's place
            tokens[at] = _blanks(tokens[at]) + tokens[m[2] % len(tokens)].lstrip()
        elif kind == "rename":  # one word in another's place: mostly still parses, but means nonsense
            words = [k for k, t in enumerate(tokens) if WORD.fullmatch(t.lstrip())]
            if words:
                target, source = words[m[1] % len(words)], words[m[2] % len(words)]
                tokens[target] = _blanks(tokens[target]) + tokens[source].lstrip()
        elif kind == "truncate":
            tokens = tokens[:at]
        else:
            tokens.insert(at, m[2])
    return b"".join(tokens)


def _blanks(token: bytes) -> bytes:
    return token[: len(token) - len(token.lstrip())]


def assert_located(diagnostics: tuple[Diagnostic, ...] | list[Diagnostic], path: str, text: str | None = None) -> None:
    assert diagnostics, "a failure says why"
    lines = text.count("\n") + 1 if text is not None else None
    for d in diagnostics:
        assert d.message
        if d.span is None:
            continue
        assert d.span.path == path
        assert 1 <= d.span.line <= d.span.end_line, d
        assert 1 <= d.span.column, d
        if lines is not None:
            assert d.span.line <= lines, d
        d.render()  # renders without the source map too


def check_mutant(seed: tuple[str, bytes], mutations: list[tuple]) -> None:
    name, original = seed
    data = mutate(original, mutations)
    path = "mutant" + name[name.rindex(".") :]
    try:
        text = decode(data, path)
    except RobogenError as exc:
        assert_located(exc.diagnostics, path)
        return
    result = check_texts({path: text})  # any other exception fails the test
    if result.errors:
        assert_located(result.diagnostics, path, text)
    for f in result.files:
        assert parse_text(printer.file(f), path) == f


SETTINGS = settings(deadline=None, derandomize=True, database=None, suppress_health_check=[HealthCheck.too_slow])


@settings(SETTINGS, max_examples=2000)
@given(seed=st.sampled_from(SEEDS), mutations=st.lists(mutation, min_size=1, max_size=4))
def test_mutated_models_check_or_give_located_diagnostics(seed, mutations):
    check_mutant(seed, mutations)


@settings(SETTINGS, max_examples=1000)
@given(seed=st.sampled_from(SEEDS), mutations=st.lists(st.tuples(st.just("rename"), index, index), min_size=1, max_size=3))
def test_models_with_names_mixed_up_check_or_give_located_diagnostics(seed, mutations):
    """Mostly syntactically valid, so the checks and analyses behind the parser get exercised."""
    check_mutant(seed, mutations)


def test_the_mutations_do_what_they_say():
    data = b"stm S { initial i }"
    assert mutate(data, [("delete", 1)]) == b"stm { initial i }"
    assert mutate(data, [("swap", 0, 1)]) == b" Sstm { initial i }"  # tokens move with the blanks before them
    assert mutate(data, [("duplicate", 3, 0)]) == b" initialstm S { initial i }"
    assert mutate(data, [("truncate", 3)]) == b"stm S {"
    assert mutate(data, [("replace", 4, 1)]) == b"stm S { initial S }"
    assert mutate(data, [("rename", 2, 0)]) == b"stm S { stm i }"
    assert mutate(data, [("noise", 2, b"\xff")]) == b"stm S\xff { initial i }"
    assert len(SEEDS) >= 25
