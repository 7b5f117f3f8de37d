"""robogen.semantics.model: what check() hands to later stages is frozen, resolved, and holds no
way back into the checker."""

from __future__ import annotations

import dataclasses
from fractions import Fraction
from pathlib import Path

import pytest

from robogen.semantics import check_paths
from robogen.semantics.checker import Checker
from robogen.semantics.model import MachineScope, SemanticModel

UR5E = Path(__file__).resolve().parent.parent.parent / "models" / "ur5e"


@pytest.fixture(scope="module")
def model() -> SemanticModel:
    return check_paths([UR5E / "ur5e.rst"])


def test_the_model_and_its_parts_are_frozen(model):
    (module,) = model.modules
    scope = module.controllers[0][1].machines[0][1]
    with pytest.raises(dataclasses.FrozenInstanceError):
        model.modules = ()  # type: ignore[misc]
    with pytest.raises(dataclasses.FrozenInstanceError):
        scope.period = Fraction(2)  # type: ignore[misc]
    with pytest.raises(TypeError):
        scope.vars["extra"] = scope.vars["margs"]  # type: ignore[index]
    with pytest.raises(dataclasses.FrozenInstanceError):
        scope.events["collision"].input = False  # type: ignore[misc]


def test_platform_events_and_operations_are_resolved(model):
    (module,) = model.modules
    platform = module.platform
    assert platform is not None and platform.name == "RoboticArmGripper"
    assert platform.events["moveDiscreteCommand"].type.show() == "ur5e::MovementArgs"
    assert [t.show() for _, t in platform.operations["movediscrete"].params] == ["int", "int", "int"]
    assert module.period == Fraction(1)


def test_names_types_and_scopes_are_read_through_the_model(model):
    scope = model.machines[0]
    assert isinstance(scope, MachineScope) and model.scope_of(scope.node) is scope
    (trigger,) = [t for r in scope.region.walk() for t in r.transitions if t.name == "t2"]
    assert model.bound_var(trigger.condition).name == "margs"
    assert model.type_of(trigger.condition).show() == "boolean"


def test_no_part_of_the_model_refers_to_the_checker(model):
    seen: set[int] = set()
    todo: list[object] = [model]
    while todo:
        x = todo.pop()
        if id(x) in seen or isinstance(x, (str, int, Fraction, type(None))):
            continue
        seen.add(id(x))
        assert not isinstance(x, Checker) and not callable(getattr(x, "__self__", None))
        if dataclasses.is_dataclass(x) and not isinstance(x, type):
            todo += [getattr(x, f.name) for f in dataclasses.fields(x)]
        elif isinstance(x, dict) or hasattr(x, "items") and hasattr(x, "keys"):
            todo += list(x.values())  # type: ignore[union-attr]
        elif isinstance(x, (list, tuple, set, frozenset)):
            todo += list(x)
