"""The UR5e case study (examples/ur5e) end to end: the FMUs `make demo` builds, co-simulated by robogen's master
in the three variants, must show every property the case study is about.

Expected values come from the semantics: a RoboSim cycle runs every 0.5 s and samples the inputs
latched since the previous cycle, so the d-model calls `stop` exactly one cycle after the first
platform sample at which `moveCompleted` holds; a RoboChart machine reacts when the event comes,
so its `stop` is in the time instant of `moveCompleted`; stepwise semantics shows the same
cycle one transition per super-dense instant.
"""

from __future__ import annotations

import subprocess
import sys

import pytest

from examples.ur5e.analysis import analyse, load_run, node_names_of
from examples.ur5e.build import ROOT, TIME_UNIT, VARIANTS, build_all
from examples.ur5e.figure import draw
from examples.ur5e.report import Timing, end_of_instant_states, max_joint_difference, summary
from robogen.cosim import simulate_system

OUT = ROOT / "build" / "ur5e"  # where models/ur5e/system.toml expects the FMUs
CYCLE = float(TIME_UNIT)
COMMAND_TIMES = [5.0, 10.5, 15.0, 23.5, 30.0, 35.5, 40.0, 48.5, 55.0, 60.5, 65.0, 73.5, 80.0, 85.5, 90.0, 98.5]
TARGETS = [(0, 23, 1), (3, 20, 2), (8, 10, 0), (1, 13, 0)]


@pytest.fixture(scope="session")
def runs(tmp_path_factory):
    built = build_all(OUT)
    work = tmp_path_factory.mktemp("ur5e")
    reports = {}
    for v in VARIANTS:
        results, events = work / f"results-{v.name}.csv", work / f"events-{v.name}.jsonl"
        result = simulate_system(built.systems[v.name], output=results, events=events, keep_rows=False)
        names, machine = node_names_of(OUT / v.fmu)
        run = load_run(v.name, results, events, names, machine)
        run.event_iterations, run.instants = result.stats.event_iterations, result.stats.instants
        reports[v.name] = analyse(run, CYCLE)
    return reports


@pytest.mark.parametrize("variant", [v.name for v in VARIANTS])
def test_every_property_holds(runs, variant):
    report = runs[variant]
    failed = [check for check, ok in report.checks.items() if not ok]
    assert not failed, f"{variant}: {failed}"


@pytest.mark.parametrize("variant", [v.name for v in VARIANTS])
def test_commands_are_the_plan(runs, variant):
    commands = runs[variant].commands
    assert [c.at for c in commands] == [(t, 0) for t in COMMAND_TIMES]
    assert [c.target for c in commands] == [TARGETS[i % 4] for i in range(16)]


def test_robosim_exhaustive_chain_resolves_in_one_instant(runs):
    for c in runs["exhaustive"].commands:
        assert c.dmodel_call == c.at and c.platform_call == c.at  # no step of latency, no extra index
        assert c.feasible == c.at  # the platform answers in the instant that receives the call
        # RoboSim: the cycle after the first sample where moveCompleted holds for the new target
        assert c.stop == (c.completed_sample[0] + CYCLE, 0)
        assert c.stopped == c.stop  # the arm is at rest at its target when stop arrives
        assert c.idle == c.stop[0] + CYCLE  # next cycle: robotStopped seen in J3, back to Idle


def test_stepwise_shows_each_transition_at_its_own_index(runs):
    ex, st = runs["exhaustive"], runs["stepwise"]
    for a, b in zip(ex.commands, st.commands):
        # Idle -> ArmMove is the second micro-step of the command's cycle (the first completes
        # the exec self-loop t1_1 of the previous cycle), at the same time
        assert b.dmodel_call == (a.dmodel_call[0], 1)
        assert b.stop[0] == a.stop[0] and b.stop[1] == 1
    assert st.max_index > ex.max_index == 1
    # identical end-of-cycle behaviour: the same state after every time instant, the same motion
    assert end_of_instant_states(ex.run) == end_of_instant_states(st.run)
    assert max_joint_difference(ex.run, st.run) == 0.0


def test_robochart_stops_when_the_move_completes(runs):
    for c in runs["robochart"].commands:
        assert c.stop[0] == c.completed[0]  # same time instant, the next super-dense index
        assert c.stop[1] == c.completed[1] + 1


def test_flange_reaches_every_target(runs):
    errors = [c.ee_error_mm for c in runs["exhaustive"].commands]
    assert max(errors) <= 1.0


def test_summary_and_figure(runs, tmp_path):
    titles = {v.name: v.title for v in VARIANTS}
    text = summary(runs, titles, [Timing("x", 1.0)], {v: 1.0 for v in runs}, None, CYCLE)
    assert "- [ ]" not in text and text.count("- [x]") == sum(len(r.checks) for r in runs.values())
    assert "identical end-of-cycle behaviour" in text
    png = draw(runs["exhaustive"].run, tmp_path / "figure.png", stepwise=runs["stepwise"].run)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_system_file_runs_on_its_own_and_is_deterministic(runs, tmp_path):
    outputs = []
    for name in ("a", "b"):
        out = tmp_path / f"{name}.csv"
        proc = subprocess.run([sys.executable, "-m", "robogen", "simulate", str(ROOT / "models/ur5e/system.toml"),
                               "-o", str(out)], capture_output=True, text=True, cwd=ROOT)
        assert proc.returncode == 0, proc.stderr
        outputs.append(out.read_bytes())
    assert outputs[0] == outputs[1]
    assert outputs[0].count(b"\n") > 400


def test_realtime_pacing_reports_lag(runs, tmp_path):
    proc = subprocess.run([sys.executable, "-m", "robogen", "simulate", str(ROOT / "models/ur5e/system.toml"),
                           "--stop", "10", "--realtime=100", "-o", str(tmp_path / "paced.csv")],
                          capture_output=True, text=True, cwd=ROOT)
    assert proc.returncode == 0, proc.stderr
    assert "lag" in proc.stderr and "overrun" in proc.stderr


def test_the_system_exported_to_ssp_2_runs_byte_for_byte_alike(runs, tmp_path):
    """models/ur5e/system.toml as an SSP 2.0 archive (robogen export-ssp): valid against the SSP
    2.0 schemas, and the same results, events and statistics from the archive as from the file."""
    from robogen.cosim.ssp_write import export_ssp
    from support.ssp import SCHEMAS, validate

    ssp = export_ssp(ROOT / "models/ur5e/system.toml", tmp_path / "ur5e.ssp")
    if SCHEMAS.is_dir():
        validate(ssp)
    outcomes = []
    for name, path in (("toml", ROOT / "models/ur5e/system.toml"), ("ssp", ssp)):
        result = simulate_system(path, output=tmp_path / f"{name}.csv", events=tmp_path / f"{name}.jsonl", keep_rows=False)
        outcomes.append(((tmp_path / f"{name}.csv").read_bytes(), (tmp_path / f"{name}.jsonl").read_bytes(),
                         result.stats.steps, result.stats.event_iterations, result.stats.instants))
    assert outcomes[1] == outcomes[0]
    assert outcomes[0][0].count(b"\n") > 400
