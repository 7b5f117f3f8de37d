"""robogen.semantics.model: what check() hands to later stages is frozen, resolved, and holds no
way back into the checker."""

from __future__ import annotations

import dataclasses
from fractions import Fraction
from pathlib import Path

import pytest

from robogen.semantics import check_paths, check_texts
from robogen.semantics.checker import Checker
from robogen.semantics.model import IN, OUT, MachineScope, SemanticModel, state_action, statements

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


BODY = """
interface Ops { fetch() park() lift(h: nat) }
interface Lifts { lift(h: nat) }
interface Events { event go event done: nat event stop }
operation fetch() { uses Events initial i final f transition t { from i to f action done!1 } }
operation park() { initial i final f transition t { from i to f } }
operation lifting(h: nat) { initial i final f transition t { from i to f } }
stm M {
	requires Ops
	uses Events
	var n: nat
	initial i
	state A { entry if n > 0 then done!n ; fetch() else stop end exit lift(2) }
	state B { during (park() ; done?n) <{ 3 } }
	transition t0 { from i to A }
	transition t1 { from A to B trigger go action stop ; done.1 }
	transition t2 { from B to A trigger done?n }
}
controller C { uses Events opref lift = lifting sref m = M }
robotic platform P { provides Lifts uses Events }
module Mod { rref p = P cref c = C connection p on go to c on go ( _async ) }
"""


def test_a_body_s_communications_and_calls_in_declaration_order():
    model = check_texts({"m.rct": BODY})
    assert model.errors == []
    (machine,) = model.machines
    uses = [(u.event, u.direction, type(u.node).__name__) for u in model.communications(machine)]
    assert uses == [
        ("go", IN, "Communication"), ("stop", OUT, "Communicate"), ("done", OUT, "Communicate"),  # t1
        ("done", IN, "Communication"),  # t2
        ("done", OUT, "Communicate"), ("stop", OUT, "Communicate"),  # A's entry, through the conditional
        ("done", IN, "Communicate"),  # B's during, through the deadline and the sequence
    ]  # fmt: skip
    assert [s.call.func.text for s in machine.calls()] == ["fetch", "lift", "park"]
    a_entry = state_action(machine.region.nodes["A"], "entry")
    assert [type(s).__name__ for s in statements(a_entry)] == ["IfStmt", "Seq", "Communicate", "CallStmt", "Communicate"]
    assert state_action(machine.region.nodes["A"], "during") is None


def test_the_operation_a_call_runs():
    model = check_texts({"m.rct": BODY})
    (machine,) = model.machines
    (module,) = model.modules
    (ctrl,) = model.controllers
    fetch, lift, park = machine.calls()

    def runs(call, *where):
        found = model.operation_called(call, machine, *where)
        return found.name if found is not None else None

    # without a controller: the definitions visible from the file
    assert [runs(c) for c in (fetch, lift, park)] == ["fetch", None, "park"]
    # the controller's opref names the definition lift runs
    assert [runs(c, ctrl) for c in (fetch, lift, park)] == ["fetch", "lifting", "park"]
    # in the module, the platform provides lift: the call goes to the platform
    assert [runs(c, ctrl, module) for c in (fetch, lift, park)] == ["fetch", None, "park"]
