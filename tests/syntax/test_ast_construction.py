"""robogen.syntax.ast: the nodes' quicker __init__ is the dataclass's own in all but speed."""

from __future__ import annotations

import copy
import dataclasses
import inspect
import pickle

import pytest

from robogen.diagnostics import Span
from robogen.syntax import ast

NODES = [c for c in vars(ast).values() if isinstance(c, type) and dataclasses.is_dataclass(c) and c.__module__ == ast.__name__]


def test_every_node_class_has_the_quick_init():
    assert len(NODES) > 90
    assert all(hasattr(cls.__init__, "generated") for cls in NODES)


@pytest.mark.parametrize("cls", NODES, ids=lambda c: c.__name__)
def test_the_quick_init_has_the_dataclass_signature_and_effect(cls):
    init = cls.__init__
    assert _parameters(init) == _parameters(init.generated)
    fields = dataclasses.fields(cls)
    values = {f.name: (f"v{i}",) for i, f in enumerate(fields)}  # distinct values, one per field
    node = cls(**values)
    old = object.__new__(cls)
    init.generated(old, **values)
    assert all(getattr(node, f.name) == values[f.name] == getattr(old, f.name) for f in fields)
    assert node == old and hash(node) == hash(old) and repr(node) == repr(old)
    assert pickle.loads(pickle.dumps(node)) == node and copy.deepcopy(node) == node
    with pytest.raises(dataclasses.FrozenInstanceError):
        setattr(node, fields[0].name, None)


def _parameters(function) -> list[tuple]:
    """Names, kinds and defaults of the parameters (annotations aside)."""
    return [(p.name, p.kind, p.default) for p in inspect.signature(function).parameters.values()]


def test_defaults_keywords_and_missing_arguments_behave_as_before():
    span = Span("m", 1, 2, 1, 5)
    t = ast.Transition("t", "a", "b", span=span, source_span=span)
    assert (t.trigger, t.exec, t.resets, t.action, t.span, t.source_span, t.target_span) == (None, False, (), None, span, span, None)
    assert ast.Binary("+", ast.IntLit(1), ast.IntLit(2)).span is None
    with pytest.raises(TypeError):
        ast.Binary("+", ast.IntLit(1))
    with pytest.raises(TypeError):
        ast.Name(("x",), span)  # span is keyword-only
    assert dataclasses.replace(ast.IntLit(3, span=span), value=4) == ast.IntLit(4)
