"""Name resolution, types and well-formedness checks over a workspace of parsed models."""

from __future__ import annotations

import os
from typing import Sequence

from robogen.diagnostics import DiagnosticSink
from robogen.semantics.checker import check
from robogen.semantics.model import SemanticModel
from robogen.semantics.workspace import Workspace, from_texts, load
from robogen.syntax.parser import without_gc


def check_paths(paths: Sequence[str | os.PathLike], *, empty_is_error: bool = False) -> SemanticModel:
    """Parse every model under ``paths`` as one workspace and check it. Problems of every file
    (syntax errors included) are in ``result.diagnostics``; nothing is raised for bad models.
    A directory without a model file is an empty project, valid as in RoboTool (a warning), or,
    with ``empty_is_error``, an error (robogen check)."""
    sink = DiagnosticSink()
    with without_gc():  # one pause over parse and check: the collector would scan the ASTs between them
        return check(load(paths, sink, empty_is_error=empty_is_error))


def check_texts(texts: dict[str, str]) -> SemanticModel:
    """The same for in-memory files (path -> text)."""
    with without_gc():
        return check(from_texts(texts, DiagnosticSink()))


__all__ = ["SemanticModel", "Workspace", "check", "check_paths", "check_texts", "load"]
