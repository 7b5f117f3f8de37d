"""robogen.semantics.toolkit: RoboTool's toolkit functions with their packages and signatures,
imported or qualified (only core is implicit), and robogen's own extensions, each use of which
is warned about."""

from __future__ import annotations

import pytest
from support.frontend import at, diagnostics, error, machine, warning

from robogen.semantics import check_texts
from robogen.semantics import types as T
from robogen.semantics.toolkit import library

# (package, name, signature): a sample of each toolkit, as RoboTool's library declares them
SIGNATURES = [
    ("set_toolkit", "union", "union(s1: Set(?X), s2: Set(?X)): Set(?X)"),
    ("set_toolkit", "symetric_diff", "symetric_diff(s1: Set(?X), s2: Set(?X)): Set(?X)"),
    ("set_toolkit", "Union", "Union(A: Set(Set(?X))): Set(?X)"),
    ("relation_toolkit", "dom", "dom(r: ?X <-> ?Y): Set(?X)"),
    ("relation_toolkit", "override", "override(r: ?X <-> ?Y, s: ?X <-> ?Y): ?X <-> ?Y"),
    ("relation_toolkit", "id", "id(): ?X <-> ?X"),
    ("function_toolkit", "isBijection", "isBijection(f: ?X -> ?Y): boolean"),
    ("function_toolkit", "partitions", "partitions(f: ?L <-> Set(?X), a: Set(?X)): boolean"),
    ("sequence_toolkit", "size", "size(a: Set(?X)): nat"),
    ("sequence_toolkit", "min", "min(a: Set(int)): int"),
    ("sequence_toolkit", "squash", "squash(f: int -> ?X): Seq(?X)"),
    ("sequence_toolkit", "dconcat", "dconcat(s: Seq(Seq(?X))): Seq(?X)"),
]


@pytest.mark.parametrize("package, name, signature", SIGNATURES, ids=[s[1] for s in SIGNATURES])
def test_toolkit_functions_have_robotools_packages_and_signatures(package, name, signature):
    b = library()[package][name]
    shown = f"{name}(" + ", ".join(f"{p}: {t.show()}" for p, t in b.params) + f"): {b.result.show()}"
    assert shown == signature


def test_every_toolkit_function_of_robotool_is_there_and_nothing_else():
    counts = {package: len(functions) for package, functions in library().items()}
    assert counts == {"set_toolkit": 9, "relation_toolkit": 17, "function_toolkit": 11, "sequence_toolkit": 22}
    names = {name for functions in library().values() for name in functions}
    assert not names & {"card", "elems", "abs"}


def test_calls_are_typed_by_unifying_the_type_variables():
    text = "\n".join([
        "import relation_toolkit::*",
        "import sequence_toolkit::*",
        machine("var f: nat -> boolean, q: Seq(real), s: Set(nat), b: Set(boolean), r: real, n: nat",
                action="s = dom(f) ; b = ran(f) ; r = head(q) ; n = size(q) ; s = dom(q) ; b = dom(f)"),
    ])  # fmt: skip
    assert diagnostics(text) == [error(text, "dom(f)", "cannot assign Set(nat) to 'b' of type Set(boolean)", 2)]


def test_toolkit_functions_are_imported_or_qualified():
    """RoboTool imports only core implicitly (K4)."""
    text = "\n".join([
        "import set_toolkit::union",
        machine("var s: Set(nat), r: nat <-> nat", action="s = union(s, s) ; s = relation_toolkit::dom(r) ; s = dom(r) ; s = inter(s, s)"),
    ])  # fmt: skip
    assert diagnostics(text) == [
        error(text, "dom(r) ;", "unknown function 'dom'", 2),
        error(text, "inter", "unknown function 'inter'"),
    ]
    notes = [n.message for d in check_texts({"m.rct": text}).diagnostics for n in d.notes]
    assert notes == [
        "'relation_toolkit::dom' is a toolkit function: add 'import relation_toolkit::*' (or '::dom') to the file",
        "'set_toolkit::inter' is a toolkit function: add 'import set_toolkit::*' (or '::inter') to the file",
    ]


def test_argument_mismatches_name_the_form_or_the_type_expected():
    text = "\n".join([
        "import set_toolkit::*",
        "import relation_toolkit::*",
        machine("var s: Set(nat), b: boolean", action="b = notin(true, s) ; s = union(s, {true}) ; s = dom(b) ; s = Union(s)"),
    ])  # fmt: skip
    assert [d[1:] for d in diagnostics(text)] == [
        (*at(text, "notin(true, s)"), "argument 's' of 'notin' must be Set(boolean), but this is Set(nat)"),
        (*at(text, "union(s, {true})"), "argument 's2' of 'union' must be Set(nat), but this is Set(boolean)"),
        (*at(text, "dom(b)"), "'dom' expects a relation, not boolean"),
        (*at(text, "Union(s)"), "argument 'A' of 'Union' must be Set(Set(?X)), but this is Set(nat)"),
    ]


def test_robogen_extensions_are_warned_about():
    """abs, and min and max of two numbers, are robogen's: RoboTool lacks them (K4)."""
    text = "\n".join([
        "import sequence_toolkit::*",
        machine("var n: nat, i: int, r: real, s: Set(int)", action="r = max(r, 1) ; n = abs(i) ; i = min(s) ; n = min(n, true)"),
    ])  # fmt: skip
    assert diagnostics(text) == [
        warning(text, "max(r", "'max' of 2 arguments is a robogen extension, not a RoboTool toolkit function: RoboTool rejects this model"),
        warning(text, "abs", "'abs' of 1 argument is a robogen extension, not a RoboTool toolkit function: RoboTool rejects this model"),
        error(text, "min(n, true)", "'min' expects numbers, not nat and boolean"),
        warning(text, "min(n", "'min' of 2 arguments is a robogen extension, not a RoboTool toolkit function: RoboTool rejects this model"),
    ]


def test_card_and_elems_are_not_functions_of_robotool():
    text = "\n".join([
        "import set_toolkit::*",
        "import sequence_toolkit::*",
        machine("var n: nat, s: Set(nat), q: Seq(nat)", action="n = card(s) ; s = elems(q)"),
    ])  # fmt: skip
    assert diagnostics(text) == [
        error(text, "card", "unknown function 'card'"),
        error(text, "elems", "unknown function 'elems'"),
    ]


def test_value_types_of_toolkit_functions():
    b = library()["relation_toolkit"]["dom"]
    assert b.value_type == T.FunctionT(T.ProductT((T.FunctionT(T.TypeVarT("X"), T.TypeVarT("Y"), True),)), T.SetT(T.TypeVarT("X")))
    assert library()["relation_toolkit"]["id"].value_type == T.FunctionT(T.TypeVarT("X"), T.TypeVarT("X"), True)
