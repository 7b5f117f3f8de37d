"""Helpers shared by tests/syntax and tests/semantics: where the models are, walking ASTs, and
diagnostics reduced to comparable tuples."""

from __future__ import annotations

import contextlib
import dataclasses
import inspect
import sys
from pathlib import Path
from typing import Iterator

from robogen.diagnostics import Diagnostic
from robogen.semantics import check_texts
from robogen.syntax import ast
from support import REFERENCE_MODELS as REFERENCE
from support import ROOT

MODELS = ROOT / "tests" / "models"
VALID = MODELS / "valid"
UR5E = ROOT / "models" / "ur5e"
MODEL_SUFFIXES = (".rct", ".rst", ".rsim")


def valid_entries() -> list[Path]:
    """The valid corpus: each file, or folder of files read as one workspace, is one model."""
    return sorted(p for p in VALID.iterdir() if p.is_dir() or p.suffix in MODEL_SUFFIXES)


def model_files(root: Path) -> list[Path]:
    if not root.is_dir():
        return []
    return sorted(p for p in root.rglob("*") if p.suffix in MODEL_SUFFIXES)


def corpus_files() -> list[Path]:
    """Every model file of the project's own: the valid corpus and the UR5e case study."""
    return model_files(VALID) + model_files(UR5E)


def reference_files() -> list[Path]:
    return model_files(REFERENCE)


def relative_ids(paths: list[Path], root: Path) -> list[str]:
    return [str(p.relative_to(root)) for p in paths]


def walk(node) -> Iterator[ast.Node]:
    """Every AST node below ``node`` (fields that take part in equality only)."""
    todo = [node]
    while todo:
        n = todo.pop()
        if isinstance(n, (tuple, list)):
            todo.extend(reversed(n))
        elif isinstance(n, ast.Node):
            yield n
            todo.extend(getattr(n, f.name) for f in reversed(dataclasses.fields(n)) if f.compare)


def brief(d: Diagnostic) -> tuple:
    """(severity, line, column, message) of a diagnostic with a span; (severity, message) otherwise."""
    if d.span is None:
        return (d.severity.value, d.message)
    return (d.severity.value, d.span.line, d.span.column, d.message)


def diagnostics(text: str, path: str = "m.rct", others: dict[str, str] | None = None) -> list[tuple]:
    """The diagnostics of one model text (plus other files, path -> text), as ``brief`` tuples."""
    texts = {path: text, **(others or {})}
    return [brief(d) for d in check_texts(texts).diagnostics]


def at(text: str, snippet: str, occurrence: int = 1) -> tuple[int, int]:
    """(line, column) where the ``occurrence``-th ``snippet`` starts in ``text``: golden
    locations are written as the text they must point at."""
    start = -1
    for _ in range(occurrence):
        start = text.index(snippet, start + 1)
    line = text.count("\n", 0, start) + 1
    return line, start - (text.rfind("\n", 0, start) + 1) + 1


def machine(*members: str, action: str = "skip", path: str = "m.rct") -> str:
    """A machine S: ``members`` (one per line), then an initial node i and a state A entered by
    transition t0 with ``action``."""
    return "\n".join(["stm S {", *(f"\t{m}" for m in members), "\tinitial i", "\tstate A { }",
                      f"\ttransition t0 {{ from i to A action {action} }}", "}"])  # fmt: skip


def error(text: str, snippet: str, message: str, occurrence: int = 1) -> tuple:
    """The brief form of an error located at the ``occurrence``-th ``snippet`` of ``text``."""
    return ("error", *at(text, snippet, occurrence), message)


def warning(text: str, snippet: str, message: str, occurrence: int = 1) -> tuple:
    return ("warning", *at(text, snippet, occurrence), message)


def robosim(*members: str, action: str = "skip") -> str:
    """A RoboSim machine S like ``machine``'s, with a period and an exec self-loop on A."""
    return machine("cycleDef cycle == 1", *members, "transition tx { from A to A exec }", action=action, path="m.rst")


@contextlib.contextmanager
def shallow_stack(frames: int = 150) -> Iterator[None]:
    """Let the code inside recurse at most ``frames`` calls deeper than here: what it does in a
    loop passes, what it does by recursion proportional to the size of its input (thousands of
    states, operands) fails with RecursionError."""
    limit = sys.getrecursionlimit()
    sys.setrecursionlimit(len(inspect.stack(0)) + frames)
    try:
        yield
    finally:
        sys.setrecursionlimit(limit)
