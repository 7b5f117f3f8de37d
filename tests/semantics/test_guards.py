"""robogen.semantics.guards: keys of sub-expressions, and the answers of one machine's guard
analyses remembered by key (a machine's states often repeat a guard)."""

from __future__ import annotations

from support.frontend import at, shallow_stack

from robogen.semantics import check_texts, guards
from robogen.syntax import ast


def n(text: str) -> ast.Name:
    return ast.Name(parts=(text,))


def test_keys_are_equal_exactly_for_equal_expressions():
    a, b, c = n("a"), n("b"), n("c")
    left = ast.Binary(op="-", left=ast.Binary(op="-", left=a, right=b), right=c)  # (a - b) - c
    right = ast.Binary(op="-", left=a, right=ast.Binary(op="-", left=b, right=c))  # a - (b - c)
    again = ast.Binary(op="-", left=ast.Binary(op="-", left=n("a"), right=n("b")), right=n("c"))
    assert guards._key(left) == guards._key(again)
    assert guards._key(left) != guards._key(right)
    assert guards._key(ast.Unary(op="not", operand=a)) != guards._key(ast.Unary(op="-", operand=a))
    assert guards._key(a) is a  # a name is its own key
    field = ast.Field(obj=a, field="valid")
    assert guards._key(field) is field


def test_a_chain_of_ten_thousand_operands_is_keyed_in_a_loop():
    e: ast.Expr = n("x")
    for _ in range(10_000):
        e = ast.Binary(op="+", left=e, right=n("x"))
    with shallow_stack():
        key = guards._key(e)
    assert len(key) == 20_001  # 10,000 operators and 10,001 operands, in prefix order


def test_a_machine_answers_each_guard_and_each_pair_of_guards_once(monkeypatch):
    """Three states with the same two guards: one search for the pair and one satisfiability
    question per guard text, and every state still gets its warning, with its own names."""
    calls = {"witness": 0, "unsatisfiable": 0}
    witness, unsatisfiable = guards.Guards.witness, guards.Guards.unsatisfiable

    def counted_witness(self, g1, g2):
        calls["witness"] += 1
        return witness(self, g1, g2)

    def counted_unsatisfiable(self, g):
        calls["unsatisfiable"] += 1
        return unsatisfiable(self, g)

    monkeypatch.setattr(guards.Guards, "witness", counted_witness)
    monkeypatch.setattr(guards.Guards, "unsatisfiable", counted_unsatisfiable)
    states = ["A", "B", "C"]
    members = ["\tevent go", "\tvar x: nat, m: nat", "\tinitial i", "\ttransition t0 { from i to A }"]
    for s, nxt in zip(states, states[1:] + states[:1]):
        members += [
            f"\tstate {s} {{ }}",
            f"\ttransition {s}1 {{ from {s} to {nxt} trigger go condition x > 1 }}",
            f"\ttransition {s}2 {{ from {s} to {s} trigger go condition x > 0 /\\ m < 3 }}",
        ]
    text = "\n".join(["stm Repeat {", *members, "}"])
    result = check_texts({"m.rct": text})
    # the first assignment in which both hold, leaves in order x, m over 0..4: x = 2, m = 0
    assert [(d.span.line, d.span.column, d.message) for d in result.diagnostics] == [
        (
            *at(text, f"{s}2 {{"),
            f"transitions '{s}1' and '{s}2' leave '{s}' and can be enabled together (for example when x = 2, m = 0); "
            f"'{s}1' is taken, as it is declared first",
        )
        for s in states
    ]
    assert calls == {"witness": 1, "unsatisfiable": 2}


def test_the_operands_keyed_by_one_field_have_exactly_that_field_compared():
    """_shape keys a name or literal by its class and one field: that must be the only field
    that tells two of them apart (their equality), or two different operands would share a key."""
    import dataclasses

    for cls, name in guards._ATOM_FIELD.items():
        assert [f.name for f in dataclasses.fields(cls) if f.compare] == [name], cls
    assert guards._key(ast.Unary(op="-", operand=ast.IntLit(value=1))) != guards._key(ast.Unary(op="-", operand=ast.BoolLit(value=True)))
    inputs = [f.name for f in dataclasses.fields(ast.DollarInput) if f.compare]
    assert sorted(inputs) == ["event", "predicate", "qualifier", "var", "var_qualifier"]  # all in _shape's marker


def test_inputs_with_and_without_a_predicate_have_different_keys():
    bare = ast.DollarInput(event="e", var="x", predicate=None)
    checked = ast.DollarInput(event="e", var="x", predicate=ast.BoolLit(value=True))
    both = ast.Binary(op="/\\", left=bare, right=ast.BoolLit(value=True))
    keys = {guards._key(bare), guards._key(checked), guards._key(both)}
    assert len(keys) == 3
    assert guards._key(ast.DollarInput(event="e", var="x", predicate=None)) == guards._key(bare)
