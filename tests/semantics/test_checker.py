"""robogen.semantics.checker: whole models. The project's corpus, the case study and the
reference models check without errors; each well-formedness rule is reported, with its
location, when broken."""

from __future__ import annotations

from fractions import Fraction

import pytest
from support.frontend import REFERENCE, UR5E, VALID, at, brief, diagnostics, valid_entries, warning

from robogen.semantics import check_paths, check_texts

# ---------------------------------------------------------------------------- valid models


@pytest.mark.parametrize("entry", valid_entries(), ids=lambda p: p.name)
def test_every_model_of_the_valid_corpus_checks_clean(entry):
    model = check_paths([entry])
    assert [d.render() for d in model.diagnostics] == []
    assert model.files


def test_the_valid_corpus_is_large_enough():
    assert len(valid_entries()) >= 25
    suffixes = {p.suffix for e in valid_entries() for p in ([e] if e.is_file() else e.iterdir())}
    assert {".rct", ".rst", ".rsim"} <= suffixes


def test_the_valid_corpus_also_checks_as_one_workspace():
    """Its packages are distinct, so all of it can be given to robogen at once."""
    assert check_paths([VALID]).diagnostics == ()


@pytest.mark.parametrize("name", ["ur5e.rst", "ur5e.rct"])
def test_the_case_study_checks_clean(name):
    assert check_paths([UR5E / name]).diagnostics == ()


def test_what_the_checker_records_for_later_stages():
    model = check_paths([VALID / "pulse.rst"])
    (module,) = model.modules
    assert module.platform.name == "board" and [name for name, _ in module.controllers] == ["ctrl"]
    assert module.period == Fraction(1)
    (scope,) = model.scopes
    assert scope.qname == "pulse::Pulse"
    assert sorted(scope.events) == ["go", "tick"]
    assert scope.events["go"].input and not scope.events["go"].output
    assert scope.events["tick"].output and not scope.events["tick"].input
    assert [path for path, _ in scope.all_states()] == [("i",), ("Idle",), ("Run",)]


# ---------------------------------------------------------------------------- reference models


@pytest.mark.shared
def test_the_reference_workspace_checks_without_errors():
    model = check_paths([REFERENCE / "alpha-untimed"])
    assert len(model.files) == 16
    assert [d.render() for d in model.errors] == []


@pytest.mark.shared
def test_warnings_of_the_reference_workspace_that_are_right():
    model = check_paths([REFERENCE / "alpha-untimed"])
    found = {(d.span.path.split("alpha-untimed/")[1], d.span.line, d.message) for d in model.warnings}
    expected = {
        # Move -> Avoid -> Move needs no exec (Avoid's exec self-loop is guarded by false)
        (
            "rc2rs/robosim/aggregation.rst",
            153,
            "transitions 't1', 't2', 't3', 't4', 't5', 'tAvoid', 'tMove', 'tRandomTurn', 'tTurn180' form a cycle without "
            "exec: a cycle that takes them may never end",
        ),
        # Broadcast -> Receive -> Broadcast through t4 and t5 needs no exec either
        (
            "rc2rs/robosim/communication.rst",
            100,
            "transitions 't2', 't3', 't4', 't5', 'tBroadcast', 'tReceive' form a cycle without exec: a cycle that takes "
            "them may never end",
        ),
        (
            "rc2rs/robosim/aggregation.rst",
            176,
            "transition 'tEmptyCycle_Movement_MovementAndAvoidance_Avoid_EmptyCycle' can never fire: its condition is always false",
        ),
        # both input events can arrive in one cycle
        (
            "rc2rs/robosim/communication.rst",
            141,
            "transitions 't3' and 't2' leave 'Receive' and can be enabled together (for example when $broadcast occurs, "
            "broadcastF is true, y = ID#1, id = ID#2, $receive occurs, receiveF is true); 't3' is taken, as it is declared first",
        ),
        ("rc2rs/robosim/movementC.rst", 5, "'SensingHw' is not imported here; using 'pkg223_aggregation::SensingHw'"),
        ("rc2rs/robochart/AggregationSw.rct", 56, "'since' should be compared with a constant"),
    }
    assert expected <= found
    assert len(model.warnings) == 18


# ---------------------------------------------------------------------------- structure


def test_initial_nodes():
    text = "\n".join([
        "stm S {",
        "\tinitial i",
        "\tinitial j",
        "\tstate A { }",
        "\ttransition t0 { from i to A }",
        "\ttransition t1 { from i to A }",
        "\ttransition t2 { from A to i }",
        "}",
        "stm T { state A { } }",
        "stm U { event e initial i state A { } transition t { from i to A trigger e condition true } }",
    ])  # fmt: skip
    assert diagnostics(text) == [
        ("error", 2, 10, "initial node 'i' must have exactly one outgoing transition, not 2"),
        ("error", 3, 10, "initial node 'j' must have exactly one outgoing transition, not 0"),
        ("error", 3, 10, "state machine 'S' has more than one initial node"),
        ("error", 7, 28, "transition 't2' enters initial node 'i'"),
        ("error", 9, 5, "state machine 'T' has no initial node"),
        ("error", *at(text, "t { from i to A trigger"), "the transition from initial node 'i' can have no trigger (rule J3)"),
    ]


def test_the_transition_from_an_initial_node_may_have_a_condition_and_an_action():
    """RoboTool forbids only a trigger there (J3); RoboSim's exec is a trigger (K6)."""
    text = "\n".join([
        "stm S {",
        "\tvar x: nat",
        "\tinitial i",
        "\tstate A { }",
        "\ttransition t0 { from i to A condition x == 0 action x = 1 }",
        "\ttransition t1 { from A to A exec }",
        "\tcycleDef cycle == 1",
        "}",
        "stm T { initial i state A { } transition t0 { from i to A exec } transition t1 { from A to A exec } cycleDef cycle == 1 }",
    ])  # fmt: skip
    assert diagnostics(text, "m.rst") == [
        ("error", *at(text, "t0 { from i to A exec"), "an exec transition leaves a state, not initial 'i'"),
    ]


def test_junctions_finals_and_composite_states():
    text = "\n".join([
        "stm S {",
        "\tinitial i",
        "\tjunction j",
        "\tjunction k",
        "\tfinal f",
        "\tstate A { initial a junction b transition u { from a to b } }",
        "\tstate B { state C { } }",
        "\ttransition t0 { from i to j }",
        "\ttransition t1 { from k to A }",
        "\ttransition t2 { from A to f }",
        "\ttransition t3 { from f to B }",
        "}",
    ])  # fmt: skip
    assert diagnostics(text) == [
        ("error", 3, 11, "junction 'j' has no outgoing transition"),
        ("warning", 4, 11, "junction 'k' has no incoming transition"),
        ("error", 6, 8, "composite state 'A' has no state or final node"),
        ("error", 6, 31, "junction 'b' has no outgoing transition"),
        ("warning", 7, 8, "state 'B' has no initial node"),  # RoboTool: a warning in a composite state (K1)
        ("error", 11, 23, "transition 't3' leaves final node 'f'"),
    ]


def test_operations_without_nodes_are_abstract_and_with_nodes_should_have_one_initial_node():
    """An operation defined by its contract alone has no nodes: valid. With nodes, a missing
    or second initial node is a warning, as RoboTool gives (K1)."""
    text = "\n".join([
        "operation abstract(d: nat) {",
        "\tterminates",
        "}",
        "operation empty() { }",
        "operation noInitial() { state A { } }",
        "operation twoInitials() { initial i initial j state A { } transition t { from i to A } transition u { from j to A } }",
    ])  # fmt: skip
    assert diagnostics(text) == [
        warning(text, "noInitial", "operation 'noInitial' has no initial node"),
        warning(text, "A { } }\nop", "state 'A' is unreachable: no path from the initial node enters it"),
        warning(text, "j state A", "operation 'twoInitials' has more than one initial node"),
    ]


def test_transitions_join_nodes_of_one_container():
    text = "\n".join([
        "stm S {",
        "\tinitial i",
        "\tstate A { initial j state B { } transition u { from j to B } }",
        "\tstate C { }",
        "\ttransition t0 { from i to A }",
        "\ttransition t1 { from C to B }",
        "\ttransition t2 { from Q to A }",
        "}",
    ])  # fmt: skip
    result = check_texts({"m.rct": text})
    assert [brief(d) for d in result.diagnostics] == [
        ("error", 6, 28, "transition 't1': unknown target 'B' in state machine 'S'"),
        ("error", 7, 23, "transition 't2': unknown source 'Q' in state machine 'S'"),
    ]
    assert [n.message for n in result.diagnostics[0].notes] == [
        "'B' is a node of 'A'; a transition joins nodes of one container (rule T1)"
    ]


def test_triggers_deadlines_conditions_and_probabilities_belong_where_they_mean_something():
    text = "\n".join([
        "stm S {",
        "\tevent e",
        "\tinitial i",
        "\tjunction j",
        "\tprobabilistic p",
        "\tstate A { }",
        "\tstate B { }",
        "\ttransition t0 { from i to A }",
        "\ttransition t1 { from A to j trigger e }",
        "\ttransition t2 { from j to A trigger e }",
        "\ttransition t3 { from A to A <{ 3 } }",
        "\ttransition t4 { from A to p condition else }",
        "\ttransition t5 { from A to B probability 0.5 }",
        "\ttransition t6 { from p to A probability 0.5 }",
        "\ttransition t7 { from p to B probability 0.4 condition true }",
        "\ttransition t8 { from p to B }",
        "\ttransition t9 { from B to A trigger e <{ true } }",
        "}",
    ])  # fmt: skip
    # (with t8 lacking a probability, their sum is not checked)
    assert diagnostics(text) == [
        ("error", *at(text, "e }", 2), "a transition from junction 'j' cannot have a trigger (rule J3)"),
        ("error", *at(text, "3 }"), "a deadline '<{ d }' needs a trigger (rule TT1)"),
        ("error", *at(text, "t4"), "'condition else' is the default branch of a junction; here it leaves a state"),
        ("error", *at(text, "0.5 }"), "only transitions from a probabilistic junction have a probability"),
        ("error", *at(text, "t7"), "transition 't7' from a probabilistic junction cannot have a condition"),
        ("error", *at(text, "t8"), "transition 't8' from probabilistic junction 'p' needs a probability"),
        ("error", *at(text, "true }", 2), "a deadline is a number of time units, not boolean"),
    ]
    text = "stm S { initial i probabilistic p state A { } transition t0 { from i to p } transition t1 { from p to A probability 0.5 } transition t2 { from p to A probability 0.4 } }"
    assert diagnostics(text) == [("error", *at(text, "p state"), "the probabilities of the transitions from 'p' sum to 0.9, not 1")]


def test_states_have_one_action_of_each_kind_and_datatypes_have_fields():
    text = "datatype Empty { }\nstm S { initial i state A { entry skip exit skip entry skip } transition t { from i to A } }"
    result = check_texts({"m.rct": text})
    assert [brief(d) for d in result.diagnostics] == [
        ("error", 1, 10, "datatype 'Empty' has no fields"),
        ("error", *at(text, "entry skip }"), "state 'A' has two entry actions"),
    ]


def test_controllers_modules_platforms_and_interfaces():
    text = "\n".join([
        "interface E { event e stop() }",
        "interface V { var v: nat }",
        "robotic platform P { requires V clock K }",
        "robotic platform Q { }",
        "controller C { clock K stop() rref r = P }",
        "controller D { sref s = Missing }",
        "module M { rref p = P rref q = Q stm T { initial i state A { } transition t { from i to A } } sref s = S }",
        "module N { cref c = D }",
        "stm S { stop() initial i state A { } transition t { from i to A } }",
    ])  # fmt: skip
    assert diagnostics(text) == [
        ("error", 1, 11, "interface 'E' declares both events and operations"),
        ("error", 3, 22, "a robotic platform requires no interface"),
        ("error", 3, 33, "a robotic platform declares no clocks"),
        ("error", 5, 12, "controller 'C' has no state machine"),
        ("error", 5, 16, "a controller declares no clocks"),
        ("error", 5, 24, "a controller declares no operation signatures: 'stop' belongs in an interface the controller requires or provides"),
        ("error", 5, 31, "'rref' is not allowed in a controller"),
        ("error", 6, 25, "unknown state machine 'Missing'"),
        ("error", 7, 8, "module 'M' has no controller"),
        ("error", 7, 28, "module 'M' has more than one robotic platform"),
        ("error", 7, 38, "state machine 'T' must be inside a controller, not directly in module 'M'"),
        ("error", *at(text, "sref s = S }"), "'sref' is not allowed in a module"),
        ("error", 8, 8, "module 'N' has no robotic platform"),
        ("error", 9, 9, "a state machine declares no operation signatures: 'stop' belongs in an interface it requires (rule STM6)"),
    ]


def test_duplicate_members_of_every_kind():
    text = "\n".join([
        "interface I { event e event e var v: nat, v: nat }",
        "robotic platform P { var a: nat event a }",
        "datatype R { f: nat f: nat }",
        "enumeration E { a a }",
        "function fn(x: nat, x: nat): nat { }",
        "stm S {",
        "\tvar x: nat",
        "\tvar x: nat",
        "\tclock C",
        "\tclock C",
        "\tevent ev",
        "\tevent ev",
        "\tinitial i",
        "\tstate A { entry skip }",
        "\tstate A { }",
        "\ttransition t { from i to A }",
        "\ttransition t { from A to A }",
        "}",
        "controller Ctl { sref s = S sref s = S }",
    ])  # fmt: skip
    assert diagnostics(text) == [
        ("error", 1, 29, "'e' is declared twice in interface 'I'"),
        ("error", 1, 43, "'v' is declared twice in interface 'I'"),
        ("error", 2, 39, "'a' is declared twice in robotic platform 'P'"),
        ("error", 3, 21, "field 'f' is declared twice in datatype 'R'"),
        ("error", 4, 19, "literal 'a' is declared twice in enumeration 'E'"),
        ("error", 5, 21, "parameter 'x' is declared twice in function 'fn'"),
        ("error", 8, 6, "'x' is declared twice in state machine 'S'"),
        ("error", 10, 8, "clock 'C' is declared twice in state machine 'S'"),
        ("error", 12, 8, "event 'ev' is declared twice in state machine 'S'"),
        ("error", 15, 8, "node 'A' is declared twice in state machine 'S'"),
        ("error", 17, 13, "transition 't' is declared twice in state machine 'S'"),
        ("error", 19, 34, "'s' is declared twice in controller 'Ctl'"),
    ]


# ---------------------------------------------------------------------------- connections

CONNECTED = """interface E { event e: nat event b }
interface F { event e: boolean _broadcast event c }
robotic platform P { uses E }
stm S { uses E initial i state A { } transition t { from i to A } }
stm T { uses F initial i state A { } transition t { from i to A } }
controller C { uses E sref s = S sref u = T connection s on b to u on c connection C on e to s on e }
"""


def test_connection_ends_and_events_must_exist():
    text = CONNECTED + "module M { rref p = P cref c = C connection q on e to c on e ( _async ) connection p on nope to c on b ( _async ) }"
    assert diagnostics(text) == [
        ("error", 6, 45, "a broadcast event connects only to a broadcast event"),
        ("error", 7, 45, "'q' is not a part of module 'M'"),
        ("error", *at(text, "nope"), "robotic platform 'p' has no event 'nope'"),
    ]
    (d,) = [d for d in check_texts({"m.rct": text}).diagnostics if "not a part" in d.message]
    assert [n.message for n in d.notes] == ["the ends of a connection in module 'M' are c, p"]


def test_connected_events_must_carry_the_same_type():
    text = CONNECTED + "controller D { uses F sref u = T }\nmodule M { rref p = P cref d = D connection p on e to d on e ( _async ) }"
    result = check_texts({"m.rct": text})
    assert [brief(d) for d in result.diagnostics] == [
        ("error", 6, 45, "a broadcast event connects only to a broadcast event"),
        ("error", 8, 34, "connected events have different types: 'e' of 'p' carries nat, 'e' of 'd' carries boolean"),
    ]
    assert [n.message for n in result.diagnostics[1].notes] == ["'e' is declared in interface 'E'", "'e' is declared in interface 'F'"]


def test_platform_connections_are_asynchronous_and_each_event_end_has_one_connection():
    text = CONNECTED + "module M { rref p = P cref c = C connection p on e to c on e connection p on b to c on b ( _async ) connection p on b to c on b ( _async ) [ mult ] connection c on b to p on b ( _async ) }"
    result = check_texts({"m.rct": text})
    assert [brief(d) for d in result.diagnostics] == [
        ("error", 6, 45, "a broadcast event connects only to a broadcast event"),
        ("error", 7, 34, "connections with the robotic platform must be asynchronous"),
        # [ mult ] makes a connection bidirectional; it does not let an event end be connected twice
        ("error", 7, 117, "event 'b' of 'p' is connected twice"),
        ("error", 7, 127, "event 'b' of 'c' is connected twice"),
    ]
    assert [n.message for n in result.diagnostics[1].notes] == ["append '( _async )' to the connection (rule Cn2)"]
    text = CONNECTED.replace("connection C on e to s on e", "connection C on e to s on e connection C on e to s on e")
    assert diagnostics(text)[1:] == [
        ("error", *at(text, "e to s on e", 2), "event 'e' of 'C' is connected twice"),
        ("error", *at(text, "e }"), "event 'e' of 's' is connected twice"),
    ]


def test_robosim_connections_follow_the_machines_inputs_and_outputs():
    text = "\n".join([
        "interface E { event e }",
        "stm S { cycleDef cycle == 1 input context { uses E } initial i state A { } transition t0 { from i to A } transition t1 { from A to A exec } }",
        "stm T { cycleDef cycle == 1 output context { uses E } initial i state A { } transition t0 { from i to A } transition t1 { from A to A exec } }",
        "controller C { sref s = S sref t = T connection s on e to t on e connection t on e to s on e }",
    ])  # fmt: skip
    assert diagnostics(text, "m.rst") == [
        ("error", 4, 38, "'e' is not an input of state machine 't'"),
        ("error", 4, 38, "'e' is not an output of state machine 's'"),
    ]


# ---------------------------------------------------------------------------- RoboSim structure and periods


def test_robosim_machines_declare_events_in_contexts_and_interfaces_of_inputs_hold_only_events():
    text = "\n".join([
        "interface V { var v: nat }",
        "interface B { _broadcast event x }",
        "interface O { go() }",
        "stm S {",
        "\tcycleDef cycle == 1",
        "\tprovides V",
        "\tevent e",
        "\tinput context { _broadcast event b uses O }",
        "\tinitial i",
        "\tstate A { }",
        "\ttransition t0 { from i to A }",
        "\ttransition t1 { from A to A trigger e }",
        "\ttransition t2 { from A to A exec <{ 1 } }",
        "}",
    ])  # fmt: skip
    assert diagnostics(text, "m.rst") == [
        ("error", 2, 15, "RoboSim has no broadcast events"),
        ("error", 6, 2, "a RoboSim state machine provides no interface"),
        ("error", 7, 2, "a RoboSim state machine declares no events directly: declare 'e' in its input or output context"),
        ("error", 8, 18, "RoboSim has no broadcast events"),
        ("error", 8, 37, "interface 'O' declares operations, but an input context uses only events"),
        ("error", 12, 38, "RoboSim transitions have no trigger: test inputs in the condition ($e) and use 'exec' to wait for the next cycle"),
        ("error", 13, 38, "RoboSim has no deadlines"),
    ]


def test_cycle_definitions_have_one_form_and_a_positive_period():
    text = "\n".join([
        "stm S {",
        "\tcycleDef cycle == k",
        "\tcycleDef cycle > 2",
        "\tcycleDef cycle == 0",
        "\tcycleDef cycle == 2",
        "\tcycleDef cycle == 0.5",
        "\tinitial i",
        "\tstate A { }",
        "\ttransition t0 { from i to A }",
        "\ttransition t1 { from A to A exec }",
        "}",
    ])  # fmt: skip
    assert diagnostics(text, "m.rst") == [
        ("error", 2, 20, "the period in 'cycleDef cycle == p' must be a number literal"),
        ("error", 3, 11, "a cycle definition has the form 'cycleDef cycle == p' with p a positive number"),
        ("error", 4, 20, "the cycle period must be positive, not 0"),
        ("error", 6, 2, "state machine 'S' declares two different cycle periods"),
    ]


def test_obsolete_cycle_definitions_are_read_as_cycle_equals_p_with_a_warning():
    """`cycleDef p` and `cycleDef { cycle == p }` (older RoboSim; RoboTool no longer checks the
    definition) mean `cycleDef cycle == p`, and give the period p (K8)."""
    machine = "initial i state A { } transition t0 { from i to A } transition t1 { from A to A exec }"
    text = "\n".join([
        f"stm S {{ cycleDef 2 {machine} }}",
        "controller C { sref s = S cycleDef { cycle == 2 } }",
        "module M { robotic platform P { } cref c = C cycleDef 2.0 }",
    ])  # fmt: skip
    model = check_texts({"m.rst": text})
    assert [brief(d) for d in model.diagnostics] == [
        ("warning", *at(text, "2 initial"), "obsolete cycle definition: read as 'cycleDef cycle == 2'"),
        ("warning", *at(text, "{ cycle =="), "obsolete cycle definition: read as 'cycleDef cycle == 2'"),
        ("warning", *at(text, "2.0"), "obsolete cycle definition: read as 'cycleDef cycle == 2.0'"),
    ]
    (scope,), (controller,), (module,) = model.scopes, model.controllers, model.modules
    assert scope.period == controller.period == module.period == Fraction(2)


def test_every_part_of_a_module_has_the_same_period():
    machine = "initial i state A { } transition t0 { from i to A } transition t1 { from A to A exec }"
    text = "\n".join([
        f"stm S {{ cycleDef cycle == 1 {machine} }}",
        f"stm T {{ cycleDef cycle == 0.5 {machine} }}",
        "controller C { cycleDef cycle == 2 sref s = S sref t = T }",
        "robotic platform P { }",
        "module M { cycleDef cycle == 1 rref p = P cref c = C }",
    ])  # fmt: skip
    result = check_texts({"m.rst": text})
    assert [brief(d) for d in result.diagnostics] == [
        ("error", 2, 5, "state machine 'T' has cycle period 0.5, but module 'M' has 1"),
        ("error", 3, 12, "controller 'C' has cycle period 2, but module 'M' has 1"),
    ]
    assert result.diagnostics[0].notes[0].message == "robogen requires one period for every machine, controller and module of a model"


def test_recursive_types():
    text = "\n".join([
        "enumeration Tree { leaf node(Tree, Tree) }",
        "enumeration F { f(G) stop }",
        "enumeration G { g(F) }",
        "datatype List { value: nat rest: Seq(List) }",
        "datatype Loop { again: Loop }",
        "datatype P { a: Q }",
        "datatype Q { b: P * nat }",
        "stm S {",
        "\tvar t: Tree = Tree::node(Tree::leaf, Tree::node(Tree::leaf, Tree::leaf))",
        "\tvar l: List, n: nat",
        "\tinitial i",
        "\tstate A { entry l.rest[1].rest[2].value = 3 ; n = l.rest[1].value ; l = l.rest[1] ; t = Tree::node(t, t) }",
        "\ttransition t0 { from i to A }",
        "}",
    ])  # fmt: skip
    # a value of Loop, P or Q would be infinite; Tree, F, G and List have finite values
    assert diagnostics(text) == [
        ("error", 5, 17, "datatype 'Loop' contains itself through field 'again': its values would be infinite"),
        ("error", 6, 14, "datatype 'P' contains itself through field 'a': its values would be infinite"),
        ("error", 7, 14, "datatype 'Q' contains itself through field 'b': its values would be infinite"),
    ]
