"""robogen.semantics.machine_analysis: the warnings about behaviour (unreachable states, transitions
that can never fire, guards that overlap, RoboSim cycles that may never end)."""

from __future__ import annotations

from support.frontend import at, diagnostics, shallow_stack

from robogen.semantics import check_texts
from robogen.semantics.graph import FORMATS, render
from robogen.syntax import printer


def lines(*text: str) -> str:
    return "\n".join(text)


def test_unreachable_states_are_reported_once():
    text = lines(
        "stm S {",
        "\tinitial i",
        "\tstate A { }",
        "\tstate B { initial j state C { } transition u { from j to C } }",
        "\tstate D { }",
        "\ttransition t0 { from i to A }",
        "\ttransition t1 { from D to A }",
        "}",
    )
    # B is reported, not its inner C; D leads to A but nothing enters D
    assert diagnostics(text) == [
        ("warning", *at(text, "B {"), "state 'B' is unreachable: no path from the initial node enters it"),
        ("warning", *at(text, "D {"), "state 'D' is unreachable: no path from the initial node enters it"),
    ]


def test_a_transition_behind_an_always_enabled_one_never_fires():
    text = lines(
        "stm S {",
        "\tvar x: nat",
        "\tinitial i",
        "\tstate A { }",
        "\tstate B { }",
        "\ttransition t0 { from i to A }",
        "\ttransition t1 { from A to A condition true }",
        "\ttransition t2 { from A to B condition x > 1 }",
        "}",
    )
    result = check_texts({"m.rct": text})
    assert [(d.span.line, d.span.column, d.message) for d in result.diagnostics] == [
        (*at(text, "B { }"), "state 'B' is unreachable: no path from the initial node enters it"),
        (*at(text, "t2"), "transition 't2' can never fire: 't1' leaves 'A' first and is always enabled"),
    ]
    assert [n.message for n in result.diagnostics[1].notes] == [
        "'t1' is declared here; transitions of one source are tried in declaration order"
    ]


def test_a_guard_that_no_value_satisfies_never_fires():
    text = lines(
        "stm S {",
        "\tvar x: nat, b: boolean",
        "\tconst k: nat = 5",
        "\tinitial i",
        "\tstate A { }",
        "\ttransition t0 { from i to A }",
        "\ttransition t1 { from A to A condition b /\\ not b }",
        "\ttransition t2 { from A to A condition x > 3 /\\ x < 2 }",
        "\ttransition t3 { from A to A condition x > k /\\ x < 4 }",
        "\ttransition t4 { from A to A condition false \\/ (x < 1 /\\ x >= 1) }",
        "}",
    )
    assert diagnostics(text) == [
        ("warning", *at(text, "b /\\ not b"), "transition 't1' can never fire: its condition is always false"),
        ("warning", *at(text, "x > 3"), "transition 't2' can never fire: its condition is always false"),
        ("warning", *at(text, "x > k"), "transition 't3' can never fire: its condition is always false"),
        ("warning", *at(text, "false"), "transition 't4' can never fire: its condition is always false"),
    ]


def test_a_guard_against_a_negative_literal_is_sampled_below_it():
    """Found by the model fuzzer: `not x > -10.0` holds for x = -11, so t1 can fire; the samples
    of x came from the literal 10.0 without its sign and never went below -10."""
    text = lines(
        "stm S {",
        "\tvar x: real, n: int",
        "\tconst k: int = 4",
        "\tinitial i",
        "\tstate A { }",
        "\ttransition t0 { from i to A }",
        "\ttransition t1 { from A to A condition not x > -10.0 }",
        "\ttransition t2 { from A to A condition n < -k /\\ n < -5 }",
        "\ttransition t3 { from A to A condition x < -2.5 /\\ x > -2.5 }",
        "}",
    )
    assert [d for d in diagnostics(text) if "never fire" in d[-1]] == [
        ("warning", *at(text, "x < -2.5"), "transition 't3' can never fire: its condition is always false"),
    ]


def test_guards_the_analysis_cannot_decide_are_left_alone():
    # x + y > 3 /\ x + y < 2 is unsatisfiable, but arithmetic of two unknowns is beyond the
    # exhaustive sampling, so nothing is claimed; x > 3 /\ x < 5 is satisfiable (x = 4)
    text = lines(
        "stm S {",
        "\tvar x: nat, y: nat",
        "\tinitial i",
        "\tstate A { }",
        "\ttransition t0 { from i to A }",
        "\ttransition t1 { from A to A condition x + y > 3 /\\ x + y < 2 }",
        "\ttransition t2 { from A to A condition x > 3 /\\ x < 5 /\\ y > 100 }",
        "}",
    )
    assert diagnostics(text) == []


def test_overlapping_guards_are_reported_with_a_witness():
    text = lines(
        "enumeration Mode { up off }",
        "stm S {",
        "\tevent go",
        "\tvar x: int, m: Mode",
        "\tinitial i",
        "\tstate A { }",
        "\ttransition t0 { from i to A }",
        "\ttransition t1 { from A to A trigger go condition x > 3 }",
        "\ttransition t2 { from A to A trigger go condition x < 5 /\\ m == Mode::off }",
        "\ttransition t3 { from A to A condition x < 0 }",
        "}",
    )
    result = check_texts({"m.rct": text})
    assert [(d.severity.value, d.span.line, d.span.column, d.message) for d in result.diagnostics] == [
        (
            "warning",
            *at(text, "t2"),
            "transitions 't1' and 't2' leave 'A' and can be enabled together (for example when x = 4, m = off); "
            "'t1' is taken, as it is declared first",
        ),
    ]
    assert result.diagnostics[0].notes[0].message == "'t1' is declared here"
    assert result.diagnostics[0].notes[0].span.line == 8


def test_constants_with_values_are_not_unknowns_of_a_guard():
    # with band = 0.5 the two guards exclude each other; as an unknown, band = -1 would overlap them
    text = lines(
        "stm S {",
        "\tconst band: real = 0.5",
        "\tvar t: real, target: real",
        "\tinitial i",
        "\tjunction j",
        "\tstate A { }",
        "\ttransition t0 { from i to A }",
        "\ttransition t1 { from A to j }",
        "\ttransition t2 { from j to A condition t < target - band }",
        "\ttransition t3 { from j to A condition t > target + band }",
        "\ttransition t4 { from j to A condition else }",
        "}",
    )
    assert diagnostics(text) == []


def test_no_behaviour_warnings_for_a_machine_with_errors():
    text = "stm S { initial i state A { } state B { } transition t0 { from i to A } transition t1 { from A to A condition zz } }"
    assert diagnostics(text) == [("error", *at(text, "zz"), "unknown name 'zz'")]


# ---------------------------------------------------------------------------- RoboSim


def robosim(*members: str) -> str:
    return lines("stm S {", "\tcycleDef cycle == 1", "\tinput context { event e event f: nat }", "\tvar x: nat",
                 "\tinitial i", *(f"\t{m}" for m in members), "}")  # fmt: skip


def test_states_that_cannot_reach_exec():
    text = robosim(
        "state A { }",
        "state B { }",
        "state C { entry exec }",
        "transition t0 { from i to A }",
        "transition t1 { from A to B condition $e }",
        "transition t2 { from A to C condition not $e }",
        "transition t3 { from C to A }",
    )
    result = check_texts({"m.rst": text})
    assert [(d.severity.value, d.span.line, d.span.column, d.message) for d in result.diagnostics] == [
        ("warning", *at(text, "B { }"), "no path from state 'B' reaches exec: a cycle that enters it may never end"),
    ]
    assert result.diagnostics[0].notes[0].message == "every RoboSim cycle ends at an exec transition or an exec statement"


def test_cycles_without_exec():
    text = robosim(
        "state A { }",
        "state B { }",
        "state C { }",
        "transition t0 { from i to A }",
        "transition t1 { from A to B condition $e }",
        "transition t4 { from B to C condition $f?x }",
        "transition t2 { from B to A condition not $f }",
        "transition t3 { from A to A exec condition not $e }",
        "transition t5 { from C to B exec }",
    )
    result = check_texts({"m.rst": text})
    assert [(d.severity.value, d.span.line, d.span.column, d.message) for d in result.diagnostics] == [
        ("warning", *at(text, "t1"), "transitions 't1', 't2' form a cycle without exec: a cycle that takes them may never end"),
    ]
    assert result.diagnostics[0].notes[0].message == "robogen stops such a cycle after a bound and reports an error at run time"


def test_an_exec_statement_breaks_a_cycle_and_an_operation_may_end_without_exec():
    text = robosim(
        "state A { }",
        "state B { entry x = 1 ; exec }",
        "transition t0 { from i to A }",
        "transition t1 { from A to B condition $e }",
        "transition t2 { from B to A action x = 2 }",
        "transition t3 { from A to A condition not $e action exec }",
    )
    assert diagnostics(text, "m.rst") == []
    operation = "operation op() {\n\tinitial i\n\tfinal f\n\tstate A { }\n\ttransition t0 { from i to A }\n\ttransition t1 { from A to f }\n}"
    assert diagnostics(operation, "o.rst") == []


def test_in_robosim_every_pair_of_guards_of_a_state_is_compared():
    # all transitions of a RoboSim state are tried in the same cycle, whatever they test
    text = robosim(
        "state A { }",
        "transition t0 { from i to A }",
        "transition t1 { from A to A exec condition $e }",
        "transition t2 { from A to A exec condition $f?x /\\ x > 2 }",
    )
    assert diagnostics(text, "m.rst") == [
        (
            "warning",
            *at(text, "t2"),
            "transitions 't1' and 't2' leave 'A' and can be enabled together (for example when $e occurs, $f occurs, x = 3); "
            "'t1' is taken, as it is declared first",
        )
    ]


def test_a_value_bound_in_the_guard_is_not_the_value_read_before():
    # x > 5 reads x before $f?x binds it: the guard is satisfiable and nothing is claimed
    text = robosim(
        "state A { }",
        "transition t0 { from i to A }",
        "transition t1 { from A to A exec condition x > 5 /\\ $f?x /\\ not (x > 5) }",
        "transition t2 { from A to A exec condition not $f }",
    )
    assert diagnostics(text, "m.rst") == []


def loops_on_a(*conditions: str) -> str:
    """A machine with a nat x, a state A and a self-loop t1, t2, ... on A for each condition."""
    loops = [f"\ttransition t{k} {{ from A to A condition {c} }}" for k, c in enumerate(conditions, 1)]
    return lines("stm S {", "\tvar x: nat", "\tinitial i", "\tstate A { }", "\ttransition t0 { from i to A }", *loops, "}")


def test_arithmetic_the_evaluator_does_not_follow_is_declined_not_a_crash():
    # division of two literals used to reach an unsupported operator in the evaluator
    text = loops_on_a("4 / 2 > 1", "x % 2 == 1 /\\ 6 / 3 == 2")
    assert diagnostics(text) == []


def test_the_robosim_period_is_a_value_not_an_unknown():
    # cycle is 2 here: since(C) > 3 * cycle and since(C) < 5 cannot hold together; an unknown
    # cycle could be 1 and would make them overlap
    text = robosim(
        "clock C",
        "state A { }",
        "transition t0 { from i to A }",
        "transition t1 { from A to A exec condition since(C) > 3 * cycle }",
        "transition t2 { from A to A exec condition since(C) < 5 }",
    ).replace("cycle == 1", "cycle == 2")
    assert diagnostics(text, "m.rst") == []
    overlapping = text.replace("since(C) < 5", "since(C) < 8")
    assert diagnostics(overlapping, "m.rst") == [
        (
            "warning",
            *at(overlapping, "t2"),
            "transitions 't1' and 't2' leave 'A' and can be enabled together (for example when since(C) = 7); "
            "'t1' is taken, as it is declared first",
        )
    ]


def test_a_machine_with_more_states_in_a_row_than_python_recursion_allows():
    n = 1500
    states = [f"state S{j} {{ }}" for j in range(n)]
    moves = [f"transition a{j} {{ from S{j} to S{j + 1} condition $e }}" for j in range(n - 1)]
    waits = [f"transition b{j} {{ from S{j} to S{j} exec condition not $e }}" for j in range(n - 1)]
    text = robosim(*states, "transition t0 { from i to S0 }", *moves, *waits, f"transition z {{ from S{n - 1} to S0 exec }}")
    assert diagnostics(text, "m.rst") == []
    # the same chain closed without exec is one cycle of every move
    looping = text.replace(f"transition z {{ from S{n - 1} to S0 exec }}", f"transition z {{ from S{n - 1} to S0 }}")
    (warning,) = diagnostics(looping, "m.rst")
    assert warning[:3] == ("warning", *at(looping, "a0 "))
    assert warning[3].startswith("transitions 'a0', 'a1', 'a10', 'a100', 'a1000', ") and warning[3].endswith(
        "'z' form a cycle without exec: a cycle that takes them may never end"
    )


def test_a_comparison_and_its_negation_are_one_proposition():
    # x >= 3 is not (x < 3): t1 holds for x = 3 and t2 for x = 4, only t3 never holds
    text = loops_on_a("x >= 3 /\\ not (x < 3)", "x > 3 /\\ not (x <= 3) /\\ x < 9", "x >= 3 /\\ x < 3")
    assert diagnostics(text) == [
        (
            "warning",
            *at(text, "t2 {"),
            "transitions 't1' and 't2' leave 'A' and can be enabled together (for example when x = 4); "
            "'t1' is taken, as it is declared first",
        ),
        ("warning", *at(text, "x >= 3 /\\ x < 3"), "transition 't3' can never fire: its condition is always false"),
    ]


def test_guards_of_a_thousand_operands_are_analysed_in_loops():
    n = 1000
    always = " /\\ ".join(["b"] * n)
    text = lines(
        "stm S {",
        "\tvar x: nat, b: boolean",
        "\tinitial i",
        "\tstate A { }",
        "\tstate B { }",
        "\ttransition t0 { from i to A }",
        f"\ttransition t1 {{ from A to B condition {always} }}",
        "\ttransition t2 { from A to B condition " + " \\/ ".join(["not b"] * (n - 1) + ["b"]) + " }",
        "\ttransition t3 { from B to A condition " + " + ".join(["x"] * n) + " > 3 }",
        "\ttransition t4 { from B to A condition " + " + ".join(["x"] * n) + " < 2 }",
        f"\ttransition t5 {{ from B to B condition {always} /\\ not b }}",
        "}",
    )
    with shallow_stack():
        found = diagnostics(text)
    assert found == [
        (
            "warning",
            *at(text, "t2 {"),
            "transitions 't1' and 't2' leave 'A' and can be enabled together (for example when b is true); "
            "'t1' is taken, as it is declared first",
        ),
        ("warning", *at(text, f"{always} /\\ not b"), "transition 't5' can never fire: its condition is always false"),
    ]  # t3 and t4 exclude each other: 1000 x > 3 needs x >= 1, 1000 x < 2 needs x = 0


def test_a_chain_of_ten_thousand_states_is_checked_without_recursion():
    n = 10_000
    states = [f"state S{j} {{ }}" for j in range(n)]
    moves = [f"transition m{j} {{ from S{j} to S{(j + 1) % n} exec action k = k + 1 }}" for j in range(n)]
    text = robosim("var k: nat", *states, "transition s { from i to S0 }", *moves)
    with shallow_stack():
        model = check_texts({"m.rst": text})
        dot, mermaid = (render(model.scopes, fmt) for fmt in FORMATS)
        printed = printer.file(model.files[0])
    assert model.diagnostics == ()
    assert dot.count(" -> ") == mermaid.count(" --> ") == n + 1
    assert printed.count("\texec\n") == n


def test_the_analyses_leave_no_reference_cycles(monkeypatch):
    """A machine's guards, compiled evaluators and witnesses are freed as soon as its analysis
    ends, by reference counting: a reference cycle (a recursive closure) would keep them for the
    cyclic collector, which then scans every one of them (check runs with that collector paused)."""
    import gc
    import weakref

    from robogen.semantics import guards, machine_analysis

    made: list[weakref.ref] = []

    class Recorded(guards.Guards):
        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            made.append(weakref.ref(self))

    monkeypatch.setattr(machine_analysis, "Guards", Recorded)
    text = lines(
        "stm Cycles {",
        "\tvar level: nat",
        "\tvar ready: boolean",
        "\tinitial i",
        "\tstate Idle { }",
        "\tfinal F",
        "\ttransition start { from i to Idle }",
        "\ttransition up { from Idle to F condition level > 1 /\\ (ready \\/ not ready) }",
        "\ttransition high { from Idle to F condition level >= 2 }",
        "\ttransition below { from Idle to F condition level < 0 }",
        "}",
    )
    gc.disable()
    try:
        result = check_texts({"m.rct": text})
        assert [d.message for d in result.diagnostics if "can be enabled together" in d.message]  # the witness search ran
        assert made and all(ref() is None for ref in made)
    finally:
        gc.enable()
