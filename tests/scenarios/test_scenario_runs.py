"""Scenarios run on the example models (examples/scenarios), built once for the module: the traces
against hand calculation, the reference interpreter, the cache, the template, expectations,
``robogen test`` with its table, exit codes and JUnit XML, and scenarios in system files."""

from __future__ import annotations

import shutil
import tomllib
from pathlib import Path

import pytest
from lxml import etree

from robogen.cli import main
from robogen.cosim import simulate_system
from robogen.cosim.scenario import load_scenario, timeline
from robogen.diagnostics import RobogenError
from robogen.scenarios.build import fmu_key, model_fmu, parse_options
from robogen.scenarios.expect import expectations
from robogen.scenarios.reference import first_difference
from robogen.scenarios.run import fmu_description, run_scenario
from robogen.scenarios.template import skeleton

from support import ROOT

EXAMPLES = ROOT / "examples" / "scenarios"
SCHEMA = Path(__file__).with_name("junit.xsd")


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    """A cache of its own for the module; both example models built into it once."""
    folder = tmp_path_factory.mktemp("fmu-cache")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("ROBOGEN_CACHE", str(folder))
        built = {"rover": model_fmu([EXAMPLES / "rover.rst"], parse_options(["--time-unit", "0.5"], None)),
                 "sprinkler": model_fmu([EXAMPLES / "sprinkler.rct"], parse_options(["--machine", "Sprinkler"], None))}
        yield built


def ticks(result, clock: str, *values: str, instance: str = "model") -> list:
    """(time, values...) of each tick of <instance>.<clock>."""
    i = result.columns.index(f"{instance}.{clock}")
    j = [result.columns.index(f"{instance}.{v}") for v in values]
    return [(r[0], *(r[k] for k in j)) for r in result.rows if r[i] == 1]


def test_the_rover_drives_halts_and_docks_as_calculated(cache):
    """rover.toml by hand (cycle 0.5 s; an exec transition completes at the start of the next
    cycle): the route at 1.0 starts Driving, each exec from next announces a leg one cycle later,
    go!3 at 1.5, go!1 at 2.0; the obstacle at 2.0 (0.5 < near) decides t3, which halts at 2.5; the
    clear reading at 3.5 resumes, go!4 at 4.0; the legs are over at 4.5: dock."""
    done = run_scenario(EXAMPLES / "rover.toml")
    assert not done.built.compiled  # the fixture built it
    r = done.result
    assert ticks(r, "go", "go.value") == [(1.5, 3), (2.0, 1), (4.0, 4)]
    assert ticks(r, "halt") == [(2.5,)] and ticks(r, "dock") == [(4.5,)]
    assert [t for t, in ticks(r, "battery")] == [0.25, 1.25, 2.25, 3.25, 4.25, 5.25]  # every = 1.0 from 0.25
    assert ticks(r, "route") == [(1.0,)]
    assert ticks(r, "route", "route.value.size", instance="model_scenario") == [(1.0, 3)]  # what the player sent
    reference = run_scenario(EXAMPLES / "rover.toml", reference=True)
    assert first_difference(r.columns, r.rows, reference.result.rows) is None


def test_the_sprinkler_takes_records_sets_and_repeats(cache):
    """sprinkler.toml by hand: smoke at 1 raises alarm 1; 42 degrees at 2 goes through 'hot' back
    to Alarmed (not above 50): alarm 2; the fire at 3 sprays at (2, -1); the set {3, 1} at 4 is not
    empty: stop, Watching; the readings at 4.5 and 5.5 arrive in Watching, which takes none: the
    second replaces the first (dropped_events 1)."""
    r = run_scenario(EXAMPLES / "sprinkler.toml").result
    assert ticks(r, "alarm", "alarm.value") == [(1.0, 1), (2.0, 2)]
    assert ticks(r, "spray", "spray.x", "spray.y") == [(3.0, 2, -1)]
    assert ticks(r, "stop") == [(4.0,)]
    assert ticks(r, "temperature") == [(2.0,), (4.5,), (5.5,)]
    assert r.rows[-1][r.columns.index("model.dropped_events")] == 1
    assert ticks(r, "cleared", "cleared.value.size", instance="model_scenario") == [(4.0, 2)]
    # the player's own columns show the payloads it sent
    i = r.columns.index("model_scenario.fire.x")
    assert [row[i] for row in r.rows if row[i] is not None] == [2]


def test_a_second_build_comes_from_the_cache(cache, tmp_path):
    args = parse_options(["--machine", "Sprinkler"], None)
    again = model_fmu([EXAMPLES / "sprinkler.rct"], args)
    assert (again.fmu, again.compiled) == (cache["sprinkler"].fmu, False)
    model = tmp_path / "sprinkler.rct"
    shutil.copy(EXAMPLES / "sprinkler.rct", model)
    key = fmu_key([model], args)
    assert key == fmu_key([EXAMPLES / "sprinkler.rct"], args)  # the content decides, not the path
    model.write_text(model.read_text().replace("50.0", "40.0"))
    assert fmu_key([model], args) != key
    assert fmu_key([EXAMPLES / "sprinkler.rct"], parse_options(["--machine", "Sprinkler", "--semantics", "stepwise"], None)) != key


def test_the_template_lists_every_input_event_with_a_valid_example(cache, tmp_path):
    md = fmu_description(cache["rover"].fmu)
    text = skeleton(md, model="rover.rst", options={"time_unit": "0.5"}, stop=10.0)
    data = tomllib.loads(text)
    assert (data["model"], data["step"], data["events"]) == ("rover.rst", 0.5, [])
    examples = [line.strip()[2:].rstrip(",") for line in text.splitlines() if line.strip().startswith("# { at")]
    assert [tomllib.loads(f"e = {e}")["e"]["event"] for e in examples] == ["obstacle", "route", "battery"]
    filled = tmp_path / "s.toml"
    filled.write_text("events = [\n" + ",\n".join(examples) + "\n]\n")
    plan = timeline(load_scenario(filled), md, 0.0, 10.0)  # every example line is a valid occurrence
    assert [o.clock.name for o in plan.occurrences] == ["obstacle", "route", "battery"]
    assert "# route: a set or sequence of UInt64 (at most 32)" in text


def test_expectations_are_checked_against_the_fmu_before_the_run(cache, tmp_path):
    md = fmu_description(cache["rover"].fmu)
    path = tmp_path / "s.toml"
    path.write_text("""[[expect]]
event = "docked"
[[expect]]
state = "Dockd"
at = 1.0
[[expect]]
output = "cycles"
at = 1.0
[[expect]]
event = "go"
value = "far"
[[expect]]
output = "cycles"
range = [1, 2]
""")
    with pytest.raises(RobogenError) as caught:
        expectations(load_scenario(path), md)
    assert [f"{d.span.line}: {d.message}" for d in caught.value.diagnostics] == [
        "1: the FMU has no output event 'docked' (did you mean 'dock'?)",
        "3: machine 'Rover' has no state 'Dockd' (did you mean 'Docked'?)",
        "6: give range = [LOW, HIGH] or value = ...",
        "9: 'go.value' is a UInt64 (an integer), not 'far'",
        "12: an output expectation needs 'at', the time"]


def _scenarios(folder: Path, *names: str) -> Path:
    """Copies of example scenarios whose model paths point back at the examples."""
    folder.mkdir(parents=True, exist_ok=True)
    for name in names:
        text = (EXAMPLES / name).read_text()
        model = tomllib.loads(text)["model"]
        target = (EXAMPLES / name).parent / model
        (folder / Path(name).name).write_text(text.replace(f'model = "{model}"', f'model = "{target.resolve()}"'))
    return folder


def test_robogen_test_on_a_folder_table_exit_status_and_junit(cache, tmp_path, capsys):
    good = _scenarios(tmp_path / "good", "sprinkler.toml", "rover.toml")
    assert main(["test", str(good)]) == 0
    out = capsys.readouterr().out.splitlines()
    assert [line.split() for line in out[-4:]] == [["scenario", "passed", "failed", "errors"],
                                                  [f"{good}/rover.toml", "4", "0", "0"],
                                                  [f"{good}/sprinkler.toml", "3", "0", "0"], ["total", "7", "0", "0"]]
    mixed = _scenarios(tmp_path / "mixed", "sprinkler.toml", "failing/stop-too-early.toml")
    (mixed / "broken.toml").write_text('model = "nowhere.rct"\n[[expect]]\nevent = "x"\n')
    (mixed / "system-like.toml").write_text("[instances.a]\nfmu = \"a.fmu\"\n")  # not a scenario: skipped
    report = tmp_path / "out" / "report.xml"
    assert main(["test", str(mixed), "--junit", str(report)]) == 1
    captured = capsys.readouterr()
    assert f"{mixed}/stop-too-early.toml:12:1: FAIL  event 'stop' occurs within [0, 3.5]: no tick (it ticks at t=4)" \
        in captured.out.splitlines()
    assert f"{mixed}/broken.toml:1:1: error: model not found: {mixed}/nowhere.rct" in captured.err
    assert captured.out.splitlines()[-1].split() == ["total", "4", "1", "1"]
    schema = etree.XMLSchema(etree.parse(str(SCHEMA)))
    document = etree.parse(str(report))
    assert schema.validate(document), schema.error_log
    root = document.getroot()
    assert (root.get("tests"), root.get("failures"), root.get("errors")) == ("6", "1", "1")
    suites = {Path(s.get("name")).name: s for s in root}
    assert [c.get("name") for c in suites["stop-too-early.toml"].iter("testcase")] == [
        "1: the run ends without error", "12: event 'stop' occurs within [0, 3.5]"]
    assert suites["broken.toml"].find("testcase/error").get("message").endswith("model not found: " + str(mixed / "nowhere.rct"))
    # the schema has teeth: a suite without its hostname is refused
    del root[0].attrib["hostname"]
    assert not schema.validate(document)


def test_robogen_test_compare_and_reference(cache, tmp_path, capsys):
    folder = _scenarios(tmp_path, "rover.toml")
    assert main(["test", str(folder / "rover.toml"), "--compare"]) == 0
    assert f"{folder}/rover.toml:1:1: PASS  the FMU and the reference interpreter give the same results" \
        in capsys.readouterr().out.splitlines()
    assert main(["test", str(folder / "rover.toml"), "--reference"]) == 0


def test_simulate_a_model_with_a_scenario_and_its_errors(cache, tmp_path, capsys):
    out = tmp_path / "r.csv"
    assert main(["simulate", str(EXAMPLES / "rover.rst"), "--time-unit", "0.5", "--scenario", str(EXAMPLES / "rover.toml"),
                 "-o", str(out), "--no-progress"]) == 0  # (--plot: the README runs it)
    err = capsys.readouterr().err
    assert "the FMU is unchanged: from the cache" in err and (tmp_path / "r.events.jsonl").stat().st_size > 0
    assert out.read_text().splitlines()[0].startswith("time,superdense,model.cycle,model.obstacle")
    bad = tmp_path / "bad.toml"
    bad.write_text('events = [{ at = 1.0, event = "rout", value = [1] }]\nstop = 2.0\n')
    assert main(["simulate", str(EXAMPLES / "rover.rst"), "--time-unit", "0.5", "--scenario", str(bad), "-o", str(out)]) == 1
    err = capsys.readouterr().err
    assert f"{bad}:1:23: error: the FMU has no input event 'rout' (did you mean 'route'?)" in err
    assert "Traceback" not in err and "internal error" not in err
    assert main(["simulate", str(EXAMPLES / "rover.rst"), "--scenario", str(tmp_path / "none.toml"), "-o", str(out)]) == 1
    assert "cannot read scenario file" in capsys.readouterr().err


def test_a_scenario_in_a_system_file_with_parameters(cache, tmp_path):
    scenario = tmp_path / "s.toml"
    scenario.write_text('events = [{ at = "${t_low}", event = "battery", value = 0.1 },\n'
                        '          { at = 1.0, event = "route", value = [2, 7] }]\n[parameters]\nt_low = 3.0\n')
    system = tmp_path / "system.toml"
    system.write_text(f'[experiment]\nstop = 3.0\nstep = 0.5\norder = ["r"]\n[instances.r]\nfmu = "{cache["rover"].fmu}"\n'
                      f'scenario = "s.toml"\nscenario_parameters = {{ t_low = 1.5 }}\n')
    result = simulate_system(system)
    dock = result.columns.index("r.dock")
    go = result.columns.index("r.go.value")
    assert [row[0] for row in result.rows if row[dock] == 1] == [1.5]  # t_low from the system file
    assert [row[go] for row in result.rows if row[go] is not None] == [2]  # one leg, at 1.5, then the battery
    system.write_text(system.read_text().replace("t_low = 1.5", "t_lo = 1.5"))
    with pytest.raises(RobogenError) as caught:
        simulate_system(system)
    d = caught.value.diagnostics[0]
    assert (d.span.line, d.message) == (8, "the scenario has no parameter 't_lo' (did you mean 't_low'?)")
