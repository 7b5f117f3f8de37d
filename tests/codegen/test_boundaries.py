"""What one FMU holds and how its machines are named (tests/codegen/models/twins.rct).

Two instances of one state-machine definition, and a second definition of the same name inside
another controller, are told apart in the FMU by their instance paths; ``--machine`` accepts
``Controller::machine`` and instance paths, and lists the candidates when a name is ambiguous;
``--module`` names a module of a file without ``package`` even when a packaged module has the
same name; a model with nothing to compile says so, located, with exit code 1.
"""

from __future__ import annotations

import re

import pytest

from support.codegen_driver import Instant, Scenario, Tick, run_checked
from support.codegen_models import TEST_MODELS
from robogen.cli import main
from robogen.diagnostics import RobogenError
from robogen.ir.boundary import select_boundary
from robogen.semantics import check_paths

TWINS = TEST_MODELS["twins"].path


def test_instances_of_one_definition_have_their_own_variables(built):
    b = built("twins", "exhaustive")
    names = re.findall(r'<\w+ name="([^"]+)"', b.sources["modelDescription.xml"])
    for n in ("left.count.state", "right.count.state", "odd.Counter.state", "left.count.n", "right.count.n",
              "left.count.step", "right.count.step"):
        assert names.count(n) == 1, n
    assert not [n for n in names if n.startswith("Counter.")]
    # by hand: n = n + step + 1 at each bump; left's step is 2, right's stays 0
    bump_l, bump_r, ping = Tick("bumpL", {}), Tick("bumpR", {}), Tick("ping", {})
    scenario = Scenario([Instant(True, (bump_l,)), Instant(True, (bump_r, ping)), Instant(True, (bump_l,))], half=False)
    settings = {"left.count.step": 2}
    trace = run_checked(b, scenario, settings)
    assert {s.instant: s.outputs for s in trace.steps if s.outputs} == {
        0: {"totalL": {"totalL.value": 3}},
        1: {"totalR": {"totalR.value": 1}, "pong": {}},
        2: {"totalL": {"totalL.value": 6}},
    }
    assert trace.steps[-1].variables["left.count.n"] == 6 and trace.steps[-1].variables["right.count.n"] == 1


@pytest.mark.parametrize("name, chosen", [
    ("Left::count", 22), ("left.count", 22), ("Twins.right.count", 22), ("Right::count", 22),
    ("Odd::Counter", 53), ("odd.Counter", 53), ("twins::Odd::Counter", 53),
])
def test_machines_chosen_by_controller_and_instance_path(name, chosen):
    model = check_paths([TWINS])
    b = select_boundary(model, machine=name)
    assert b.kind == "machine" and b.machine.node.name_span.line == chosen


def test_an_ambiguous_machine_name_lists_the_candidates():
    model = check_paths([TWINS])
    for name in ("Counter", "twins::Counter"):
        with pytest.raises(RobogenError) as exc:
            select_boundary(model, machine=name)
        (d,) = exc.value.diagnostics
        assert d.message == f"several state machines are named '{name}'; choose one of: Left::count, Odd::Counter"
        assert [n.span.line for n in d.notes] == [22, 53]
    with pytest.raises(RobogenError) as exc:
        select_boundary(model, machine="Countr")
    assert exc.value.diagnostics[0].message == "no state machine 'Countr' in the model (did you mean 'Counter'?)"


MODULE = """{package}
interface I {{ event e }}
stm S {{ uses I initial i state A {{ }} transition t {{ from i to A }} transition u {{ from A to A trigger e }} }}
controller C {{ uses I sref s = S connection C on e to s on e }}
module {name} {{ robotic platform P {{ uses I }} cref c = C connection P on e to c on e ( _async ) }}
"""


def test_a_module_of_a_file_without_package_is_chosen_by_its_name(tmp_path):
    (tmp_path / "plain.rct").write_text(MODULE.format(package="", name="Mod"))
    (tmp_path / "packaged.rct").write_text(MODULE.format(package="package sim", name="Mod")
                                           .replace("I ", "J ").replace("I}", "J}").replace(" S ", " T ")
                                           .replace("= S", "= T").replace(" C ", " D ").replace("C on", "D on"))
    model = check_paths([tmp_path])
    assert not model.errors, model.errors
    assert select_boundary(model, module="Mod").file.path.endswith("plain.rct")
    assert select_boundary(model, module="sim::Mod").file.path.endswith("packaged.rct")
    with pytest.raises(RobogenError) as exc:
        select_boundary(model)
    assert exc.value.diagnostics[0].message == "the model has several modules; choose one with --module: Mod, sim::Mod"


def test_a_model_with_nothing_to_compile_says_so(tmp_path, capsys):
    ops = tmp_path / "ops.rct"
    ops.write_text("interface I { event e }\noperation Op(x: nat) { uses I initial i final f transition t { from i to f } }\n")
    assert main(["package", str(ops), "-o", str(tmp_path / "x.fmu")]) == 1
    err = capsys.readouterr().err
    assert f"{ops}:2:11: error: the model has no module and no state machine, so there is nothing to compile into an FMU " \
           "(it holds 1 operation definition; an FMU holds a module or a state machine that uses them)" in err
    types = tmp_path / "types.rct"
    types.write_text("datatype R { x: nat }\n")
    assert main(["compile", str(types), "-o", str(tmp_path / "out")]) == 1
    assert f"{types}:1:1: error: the model has no module and no state machine, so there is nothing to compile into an FMU " \
           "(it declares only types, interfaces or functions)" in capsys.readouterr().err


def test_ports_named_like_fmi_or_another_port_are_renamed(built):
    """clashes.rct: the clocks are renamed, each with a warning; a platform operation called
    inside a software operation gets its argument (report(x * 2 + 1): 7 for time = 3)."""
    b = built("clashes", "exhaustive")
    assert [(w.span.line, w.message) for w in b.fmu.warnings] == [
        (10, "input event 'time' becomes the FMI clock 'time_event': 'time' is FMI's independent variable"),
        (11, "input event 'cycles' becomes the FMI clock 'cycles_event': 'cycles' is one of robogen's own FMI variables"),
        (16, "platform operation 'stop' becomes the FMI clock 'stop_call': 'stop' is the clock of another port"),
    ]
    assert [(p.name, p.source) for p in b.fmu.inputs + b.fmu.outputs] == [
        ("time_event", "time"), ("cycles_event", "cycles"), ("stop", "stop"), ("stop_call", "stop"), ("report", "report")]
    scenario = Scenario([Instant(True, (Tick("time_event", {"time_event.value": 3}),)), Instant(True, (Tick("cycles_event", {}),)),
                         Instant(True, (Tick("time_event", {"time_event.value": 4}),))], half=False)
    trace = run_checked(b, scenario)
    assert {s.instant: s.outputs for s in trace.steps if s.outputs} == {
        0: {"stop": {}, "stop_call": {}, "report": {"report.level": 7}},
        2: {"stop": {}, "stop_call": {}, "report": {"report.level": 9}},
    }
    assert [s.variables["Clash.seen"] for s in trace.steps] == [3, 103, 4]
