"""robogen.semantics.directions: which way events go through connections (RoboChart's rules
Cn5 to Cn9). A machine at the start of a unidirectional connection takes no input on its event
(Cn9), one at its end does not output on it (Cn8), counting the operations it calls; a module
connection that reaches a controller agrees with the controller's own connection (Cn5 to Cn7).

The twelve models under tests/models/invalid reproduce the shapes of RoboTool's failing projects
operationInput* and operationOutput* (an operation defined in the controller, referenced by an
opref, or called by a machine referenced by an sref; each also with the communication inside a
deadline); RoboTool's integration test expects exactly these messages."""

from __future__ import annotations

import pytest
from support.frontend import MODELS, at, diagnostics

from robogen.semantics import check_texts

INVALID = MODELS / "invalid"


def notes(text: str, path: str = "m.rct") -> list[list[tuple]]:
    """The notes of each diagnostic of ``text``, as (message, line, column)."""
    return [[(n.message, n.span.line, n.span.column) for n in d.notes] for d in check_texts({path: text}).diagnostics]


# ---------------------------------------------------------------------------- RoboTool's twelve shapes

CN8 = "speed on {0} is used as the end of a unidirectional connection, but {0} outputs on speed via the operation drive (rule Cn8)"
CN9 = "bump on {0} is used as the start of a unidirectional connection, but {0} receives input on bump via the operation drive (rule Cn9)"

SHAPES = [
    # (file, the end of the connection the error points at, the machine as messages name it, where drive communicates)
    ("cn8_operation.rct", "Mover on speed", "Mover", "speed!1"),
    ("cn8_operation_deadline.rct", "Mover on speed", "Mover", "speed!1"),
    ("cn8_opref.rct", "Mover on speed", "Mover", "speed!1"),
    ("cn8_opref_deadline.rct", "Mover on speed", "Mover", "speed!1"),
    ("cn8_sref.rct", "mover on speed", "mover (Mover)", "speed!1"),
    ("cn8_sref_deadline.rct", "mover on speed", "mover (Mover)", "speed!1"),
    ("cn9_operation.rct", "Mover on bump", "Mover", "bump?n"),
    ("cn9_operation_deadline.rct", "Mover on bump", "Mover", "bump?n"),
    ("cn9_opref.rct", "Mover on bump", "Mover", "bump?n"),
    ("cn9_opref_deadline.rct", "Mover on bump", "Mover", "bump?n"),
    ("cn9_sref.rct", "mover on bump", "mover (Mover)", "bump?n"),
    ("cn9_sref_deadline.rct", "mover on bump", "mover (Mover)", "bump?n"),
]


@pytest.mark.parametrize("name, end, part, communication", SHAPES, ids=[s[0] for s in SHAPES])
def test_robotools_failing_shapes_are_rejected_on_the_connection(name, end, part, communication):
    text = (INVALID / name).read_text()
    cn8 = name.startswith("cn8")
    assert diagnostics(text, name) == [("error", *at(text, end), (CN8 if cn8 else CN9).format(part))]
    verb = "outputs on speed" if cn8 else "receives input on bump"
    assert notes(text, name) == [[(f"operation drive {verb} here", *at(text, communication))]]


@pytest.mark.parametrize("name", [s[0] for s in SHAPES])
def test_the_shapes_are_accepted_with_a_bidirectional_or_a_reversed_connection(name):
    text = (INVALID / name).read_text()
    (line,) = [x for x in text.splitlines() if x.strip().startswith("connection")]
    _, source, _, event, _, target, _, _ = line.split()
    assert diagnostics(text.replace(line, line + " [ mult ]"), name) == []
    assert diagnostics(text.replace(line, f"\tconnection {target} on {event} to {source} on {event}"), name) == []


# ---------------------------------------------------------------------------- what a machine does itself


OWN = """interface Ops { beep() }
controller C {
	event e: nat
	event f
	operation beep() { initial i final f0 transition t { from i to f0 } }
	stm M {
		event e: nat
		event f
		requires Ops
		var x: nat
		initial i
		state A {
			initial j
			state B {
				during if x > 0 then skip else (beep() ; e!x <{ 1 }) end
			}
			transition u { from j to B }
		}
		transition t { from i to A }
		transition v { from A to A trigger f }
	}
	connection C on e to M on e
	connection M on f to C on f
}
"""


def test_the_machines_own_communications_count_in_nested_states_conditionals_sequences_and_deadlines():
    assert diagnostics(OWN) == [
        ("error", *at(OWN, "M on e"), "e on M is used as the end of a unidirectional connection, but M outputs on e (rule Cn8)"),
        ("error", *at(OWN, "M on f"), "f on M is used as the start of a unidirectional connection, but M receives input on f (rule Cn9)"),
    ]
    assert notes(OWN) == [[("M outputs on e here", *at(OWN, "e!x"))], [("M receives input on f here", *at(OWN, "f }"))]]


@pytest.mark.parametrize("action", ["exit e!1", "entry send e.3", "during x = 1 ; (e!2 ; skip)"])
def test_every_way_of_sending_a_value_is_an_output(action):
    text = OWN.replace("during if x > 0 then skip else (beep() ; e!x <{ 1 }) end", action)
    assert diagnostics(text)[0] == (
        "error", *at(text, "M on e"), "e on M is used as the end of a unidirectional connection, but M outputs on e (rule Cn8)",
    )


def test_a_plain_event_in_an_action_is_an_output():
    text = """stm M { event go initial i state A { entry go } transition t { from i to A } }
controller C { event go sref m = M connection C on go to m on go }
"""
    assert diagnostics(text) == [
        ("error", *at(text, "m on go"), "go on m (M) is used as the end of a unidirectional connection, but m (M) outputs on go (rule Cn8)"),
    ]


def test_an_input_in_an_action_and_a_plain_trigger_are_inputs():
    text = OWN.replace("during if x > 0 then skip else (beep() ; e!x <{ 1 }) end", "entry e?x")
    assert diagnostics(text) == [
        ("error", *at(text, "M on f"), "f on M is used as the start of a unidirectional connection, but M receives input on f (rule Cn9)"),
    ]
    reversed_ = text.replace("connection C on e to M on e", "connection M on e to C on e")
    assert diagnostics(reversed_)[0] == (
        "error", *at(reversed_, "M on e"), "e on M is used as the start of a unidirectional connection, but M receives input on e (rule Cn9)",
    )


def test_both_machine_ends_of_a_connection_between_machines_are_checked():
    text = """interface Chat { event ping: nat }
stm Peer { uses Chat var n: nat initial i state S { } transition t { from i to S } transition u { from S to S trigger ping?n action ping!n } }
controller C { sref a = Peer sref b = Peer connection a on ping to b on ping }
"""
    assert diagnostics(text) == [
        ("error", *at(text, "a on ping"), "ping on a (Peer) is used as the start of a unidirectional connection, but a (Peer) receives input on ping (rule Cn9)"),
        ("error", *at(text, "b on ping"), "ping on b (Peer) is used as the end of a unidirectional connection, but b (Peer) outputs on ping (rule Cn8)"),
    ]
    assert diagnostics(text.replace("b on ping }", "b on ping [ mult ] }")) == []


def test_connections_after_a_bidirectional_one_are_checked_too():
    """RoboTool stops at the first bidirectional connection of a controller (an accident)."""
    text = OWN.replace("connection C on e to M on e", "connection C on e to M on e [ mult ]")
    assert [d[1:3] for d in diagnostics(text)] == [at(text, "M on f")]


# ---------------------------------------------------------------------------- operations


DEEP = """interface Outer { outer() }
interface Inner { inner() }
interface Other { other() }
controller C {
	event e: nat
	operation inner() { event e: nat initial i final f transition t { from i to f action e!1 } }
	operation outer() { requires Inner initial i final f transition t { from i to f action inner() } }
	operation other() { requires Inner initial i final f transition t { from i to f action inner() ; inner() } }
	stm M {
		event e: nat
		requires Outer
		requires Other
		initial i
		final f
		transition t { from i to f action outer() ; other() ; outer() }
	}
	connection C on e to M on e
}
"""


def test_operations_are_followed_however_deep_and_named_by_the_call_the_machine_makes():
    """RoboTool reports nothing when the output is two calls deep (an accident)."""
    message = "e on M is used as the end of a unidirectional connection, but M outputs on e via the operation {} (rule Cn8)"
    assert diagnostics(DEEP) == [
        ("error", *at(DEEP, "M on e"), message.format("other")),
        ("error", *at(DEEP, "M on e"), message.format("outer")),
    ]
    where = at(DEEP, "e!1")
    assert notes(DEEP) == [
        [("operation other calls inner, which outputs on e here", *where)],
        [("operation outer calls inner, which outputs on e here", *where)],
    ]


def test_an_operation_that_is_required_but_never_called_does_nothing():
    """RoboTool counts every operation a machine requires, called or not."""
    text = DEEP.replace("action outer() ; other() ; outer()", "action skip")
    assert diagnostics(text) == []


def test_an_operations_event_is_the_machines_only_with_the_same_name_and_type():
    assert diagnostics(DEEP.replace("event e: nat initial i final f transition t { from i to f action e!1 }",
                                    "event e: boolean initial i final f transition t { from i to f action e!true }")) == []
    assert diagnostics(DEEP.replace("e!1", "g!1").replace("event e: nat initial", "event g: nat initial")) == []
    text = DEEP.replace("event e: nat initial", "event e: int initial")
    assert diagnostics(text) == diagnostics(DEEP)  # nat values are int values


def test_an_operation_visible_from_the_file_counts_and_a_platform_operation_does_nothing():
    text = """interface Ops { drive() halt() }
operation drive() { event e initial i final f transition t { from i to f action e } }
controller C { event e stm M { event e requires Ops initial i final f transition t { from i to f action drive() ; halt() } } connection C on e to M on e }
"""
    assert diagnostics(text) == [
        ("error", *at(text, "M on e"), "e on M is used as the end of a unidirectional connection, but M outputs on e via the operation drive (rule Cn8)"),
    ]


def test_robosim_machines_are_left_to_their_contexts():
    text = """interface E { event e }
stm S { cycleDef cycle == 1 output context { uses E } initial i state A { } transition t0 { from i to A } transition t1 { from A to A exec action $e } }
controller C { uses E sref s = S connection C on e to s on e }
"""
    assert diagnostics(text, "m.rst") == [("error", *at(text, "connection C"), "'e' is not an input of state machine 's'")]


# ---------------------------------------------------------------------------- Cn5 to Cn7


MODULE = """interface E { event e }
robotic platform P { uses E }
stm S { uses E initial i state A { } transition t { from i to A } }
controller Up { uses E sref s = S connection s on e to Up on e }
controller Down { uses E sref s = S connection Down on e to s on e }
controller Both { uses E sref s = S connection s on e to Both on e [ mult ] }
"""


@pytest.mark.parametrize("parts", [
    "cref d = Down connection p on e to d on e ( _async )",
    "cref u = Up connection u on e to p on e ( _async )",
    "cref b = Both connection p on e to b on e ( _async ) [ mult ]",
    "cref u = Up cref d = Down connection u on e to d on e ( _async )",
])
def test_module_connections_that_agree_with_the_controllers(parts):
    assert diagnostics(MODULE + f"module M {{ rref p = P {parts} }}") == []


def test_cn5_a_bidirectional_module_connection_needs_a_bidirectional_controller_connection():
    text = MODULE + "module M { rref p = P cref d = Down cref u = Up connection p on e to d on e ( _async ) [ mult ] connection u on e to p on e ( _async ) [ mult ] }"
    assert diagnostics(text) == [
        ("error", *at(text, "d on e"), "e on d (Down) is used as the end of a bidirectional connection, but d (Down) does not contain a bidirectional connection to e (rule Cn5)"),
        ("error", *at(text, "u on e"), "e on u (Up) is used as the start of a bidirectional connection, but u (Up) does not contain a bidirectional connection to e (rule Cn5)"),
    ]
    assert notes(text) == [
        [("Down's connection on e is unidirectional", *at(text, "connection Down on e"))],
        [("Up's connection on e is unidirectional", *at(text, "connection s on e to Up"))],
    ]


def test_cn6_a_unidirectional_module_connection_into_a_controller_continues_into_it():
    text = MODULE + "module M { rref p = P cref b = Both connection p on e to b on e ( _async ) }\n" \
                    "module N { rref p = P cref u = Up connection p on e to u on e ( _async ) }"
    assert diagnostics(text) == [
        ("error", *at(text, "b on e"), "e on b (Both) is used as the end of a unidirectional connection, but b (Both) contains a bidirectional connection to e (rule Cn6)"),
        ("error", *at(text, "u on e"), "e on u (Up) is used as the end of a unidirectional connection, but u (Up) contains a connection to e (rule Cn6)"),
    ]
    assert notes(text)[1] == [("inside Up, this connection sends e out of Up", *at(text, "connection s on e to Up"))]


def test_cn7_a_unidirectional_module_connection_out_of_a_controller_comes_out_of_it():
    text = MODULE + "module M { rref p = P cref b = Both connection b on e to p on e ( _async ) }\n" \
                    "module N { rref p = P cref d = Down connection d on e to p on e ( _async ) }"
    assert diagnostics(text) == [
        ("error", *at(text, "b on e"), "e on b (Both) is used as the start of a unidirectional connection, but b (Both) contains a bidirectional connection to e (rule Cn7)"),
        ("error", *at(text, "d on e"), "e on d (Down) is used as the start of a unidirectional connection, but d (Down) contains a connection from e (rule Cn7)"),
    ]
    assert notes(text)[1] == [("inside Down, this connection takes e into Down", *at(text, "connection Down on e"))]


# ---------------------------------------------------------------------------- the valid model, turned round


def test_the_valid_model_breaks_when_a_connection_is_turned_round():
    """tests/models/valid/directions.rct checks clean (with the valid corpus); each connection
    turned round breaks a rule at both levels."""
    text = (MODELS / "valid" / "directions.rct").read_text()
    turned = text.replace("connection driver on speed to Pilot on speed", "connection Pilot on speed to driver on speed")
    assert diagnostics(turned) == [
        ("error", *at(turned, "driver on speed"),
         "speed on driver (Driver) is used as the end of a unidirectional connection, but driver (Driver) outputs on speed via the operation cruise (rule Cn8)"),
        ("error", *at(turned, "pilot on speed"),
         "speed on pilot (Pilot) is used as the start of a unidirectional connection, but pilot (Pilot) contains a connection from speed (rule Cn7)"),
    ]
    assert notes(turned) == [
        [("operation cruise calls accelerate, which outputs on speed here", *at(turned, "speed!v"))],
        [("inside Pilot, this connection takes speed into Pilot", *at(turned, "connection Pilot on speed"))],
    ]
    one_way = text.replace("connection Radio on hail to caller on hail [ mult ]", "connection Radio on hail to caller on hail")
    assert diagnostics(one_way) == [
        ("error", *at(one_way, "caller on hail"),
         "hail on caller (Caller) is used as the end of a unidirectional connection, but caller (Caller) outputs on hail (rule Cn8)"),
        ("error", *at(one_way, "radio on hail"),
         "hail on radio (Radio) is used as the end of a bidirectional connection, but radio (Radio) does not contain a bidirectional connection to hail (rule Cn5)"),
    ]
