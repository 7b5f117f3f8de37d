"""tests/codegen/models/strings.rct against traces written by hand: events carrying strings are
FMI String variables. The model holds a string as its number among the model's literals; a text
the importer sets that is none of them ("bob", "élan") is kept by the instance under a number of
its own, the same text always under the same number, so that it compares and travels back as
the text it was. At most --capacity such texts, each below 256 bytes: beyond, fmi3SetString
fails naming the variable and the limit."""

from __future__ import annotations

import pytest

from support.codegen_driver import FmuRunner, Instant, Scenario, Tick, build, outputs_by_instant
from support.codegen_models import MODELS
from robogen.codegen.api import lower_paths
from robogen.cosim import fmi3
from robogen.ir.lower import LoweringOptions


def name(text: str) -> Tick:
    return Tick("name", {"name.value": text})


def answer(reply: str, known: bool) -> dict:
    return {"reply": {"reply.value": reply}, "known": {"known.value": known}}


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_strings_cross_the_fmu_boundary_as_their_texts(builds, semantics):
    inputs = {1: name("hello"), 2: name("bob"), 3: name("bye"), 4: name(""), 5: name("bob"), 6: name("élan")}
    outputs, trace = outputs_by_instant(builds.get("strings", semantics), inputs, 8)
    # t=0: the initial transition says "ready"; then each name: "hi" to the greeting, the name
    # itself to anyone else; known for "hello" and "bye" only ("" and "bob" are neither)
    assert outputs == {
        0: {"reply": {"reply.value": "ready"}},
        1: answer("hi", True),
        2: answer("bob", False),
        3: answer("bye", True),
        4: answer("", False),
        5: answer("bob", False),
        6: answer("élan", False),
        7: {},
    }
    last = trace.steps[-1].variables
    assert (last["Greeter.n"], last["Greeter.last"], last["Greeter.greeting"]) == (6, "élan", "hello")


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_a_string_constant_is_a_string_parameter(builds, semantics):
    # greeting is the FMU parameter Greeter.greeting (start "hello"); the importer sets "bob" in
    # Initialization Mode: now bob is greeted, and hello is just a name
    inputs = {1: name("bob"), 2: name("hello"), 3: name("bye")}
    outputs, trace = outputs_by_instant(builds.get("strings", semantics), inputs, 4, parameters={"Greeter.greeting": "bob"})
    assert outputs == {0: {"reply": {"reply.value": "ready"}}, 1: answer("hi", True), 2: answer("hello", False),
                       3: answer("bye", True)}
    assert trace.steps[-1].variables["Greeter.greeting"] == "bob"


def test_a_string_constant_without_a_value_starts_empty_with_a_warning(tmp_path):
    path = tmp_path / "say.rct"
    path.write_text('stm Say {\n\tconst who: string\n\tevent said: string\n\tinitial i\n'
                    '\tstate S { entry said!who }\n\ttransition t0 { from i to S }\n}\n')
    fmu, _ = lower_paths([path])
    [warning] = fmu.warnings
    assert warning.message == ("constant 'who' has no value: it becomes FMU parameter 'Say.who' with start \"\"; "
                               "set it with --set who=... or in the importer")
    assert (warning.span.line, warning.span.column) == (2, 8)
    assert [(p.fmi_name, p.value) for p in fmu.params] == [("Say.who", "")]
    given, _ = lower_paths([path], options=LoweringOptions(settings={"who": '"Ann"'}))
    assert [(p.fmi_name, p.value) for p in given.params] == [("Say.who", "Ann")]


def test_the_importers_strings_are_bounded_by_the_capacity_and_the_length(tmp_path):
    built = build([MODELS / "strings.rct"], tmp_path / "b", options=LoweringOptions(capacity=2))
    runner = FmuRunner(built.folder)
    try:
        ok = runner.run(Scenario([Instant(True, (name(t),)) for t in ("bob", "bob", "amy", "hello", "bye")], half=False))
        assert ok.error is None, ok.error  # two texts of the importer, as often as it likes; the model's own as well
        # each run resets the instance (fmi3Reset), which forgets the importer's texts: bob and
        # amy fit again, eve is one too many
        third = runner.run(Scenario([Instant(True, (name(t),)) for t in ("bob", "amy", "eve")], half=False))
        assert third.error is not None and third.error.instant == 2
        assert "fmi3SetString" in third.error.where and "'name.value'" in third.error.where
        assert "\"eve\" would be the 3-th string that is none of the model's literals; this FMU holds 2" in third.error.where
        long = runner.run(Scenario([Instant(True, (name("x" * 255),)), Instant(True, (name("y" * 256),))], half=False))
        assert long.error is not None and long.error.instant == 1
        assert "'name.value': a string of 256 bytes, longer than the 255 bytes this FMU holds" in long.error.where
    finally:
        runner.close()


def test_a_string_variable_is_refused_to_the_other_accessors(builds):
    runner = FmuRunner(builds.get("strings", "exhaustive").folder)
    try:
        vr = runner.desc.by_name["reply.value"].vr
        runner.inst.fmi3EnterInitializationMode(None, 0.0, None)
        assert runner.inst.get_values("String", [vr]) == [""]  # the start value
        with pytest.raises(fmi3.FMI3Error):
            runner.inst.get_values("Int64", [vr])
        assert any("'reply.value' (vr %d) is a String variable, not Int64" % vr in e for e in runner.errors), runner.errors
    finally:
        runner.close()


def test_the_importers_strings_are_part_of_the_fmu_state(builds):
    runner = FmuRunner(builds.get("strings", "exhaustive").folder)
    try:
        inst, vr = runner.inst, [runner.desc.by_name["name.value"].vr]
        inst.fmi3EnterInitializationMode(None, 0.0, None)
        inst.set_values("String", vr, ["bob"])
        state = inst.fmi3GetFMUState()
        inst.set_values("String", vr, ["amy"])
        assert inst.get_values("String", vr) == ["amy"]
        inst.fmi3SetFMUState(state)
        assert inst.get_values("String", vr) == ["bob"]  # its text, kept in the state
        inst.set_values("String", vr, ["amy"])
        assert inst.get_values("String", vr) == ["amy"]
    finally:
        runner.close()
