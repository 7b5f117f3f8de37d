"""The Windows DLL and the aarch64 shared object of a robogen FMU run, under wine and qemu-user,
the UR5e d-model scenario of tests/codegen/test_ur5e_traces.py, loaded by our own C host
(support/trace_host.c) cross-built with the same toolchain: their transcripts (every super-dense
step's output clock ticks and clocked values, machine states, variables, counters) are
byte-identical to the x86_64-linux binary's, whose trace is the Python binding's and the
reference interpreter's.

Where wine or qemu-user (with Debian's aarch64 C library) is missing, the test of that platform
skips and says what to install; `make test` installs them where it can (root, apt-get).
"""

from __future__ import annotations

import pytest

from robogen.fmu.platforms import BUILT, HOST

from support.codegen_driver import Built, Description, Instant, Scenario, Tick, run_checked
from support.trace_host import parse, runner, script

COMMAND = Tick("moveDiscreteCommand", {"moveDiscreteCommand.target_X": 0, "moveDiscreteCommand.target_Y": 23,
                                       "moveDiscreteCommand.target_Z": 1})
INPUTS = {1: COMMAND, 2: Tick("feasibleMoveDiscreteCommand", {}), 4: Tick("moveCompleted", {}),
          5: Tick("robotStopped", {})}
SCENARIO = Scenario([Instant(True, (INPUTS[t],) if t in INPUTS else ()) for t in range(7)], half=False)
MOVE = {"movediscrete": {"movediscrete.target_X": 0, "movediscrete.target_Y": 23, "movediscrete.target_Z": 1}}
# by hand from the model (test_ur5e_traces.EXHAUSTIVE): the outputs of instants t = 0..6
OUTPUTS = [{}, MOVE, MOVE, {}, {"stop": {}}, {}, {}]
CROSS = [p for p in BUILT if p.name in ("x86_64-windows", "aarch64-linux")]


@pytest.fixture(scope="module")
def host_transcript(ur5e_everywhere, trace_hosts, wine_prefix):
    """The x86_64-linux binary's transcript, run by the natively built host."""
    desc = Description(ur5e_everywhere.folder)
    commands = script(desc, SCENARIO)
    transcript = runner(HOST, wine_prefix).run(trace_hosts(HOST), ur5e_everywhere.binary(HOST), commands)
    return desc, commands, transcript


def test_the_host_transcript_is_the_binding_s_and_the_interpreter_s_trace(ur5e_everywhere, host_transcript):
    desc, _, transcript = host_transcript
    built = Built(ur5e_everywhere.fmu, ur5e_everywhere.archive, ur5e_everywhere.folder, {})
    trace = run_checked(built, SCENARIO)  # the Python binding's trace, equal to the interpreter's
    assert parse(transcript, desc) == trace.comparable()
    assert [{c: v for s in trace.steps if s.instant == t for c, v in s.outputs.items()} for t in range(7)] == OUTPUTS


@pytest.mark.parametrize("platform", CROSS, ids=str)
def test_a_cross_built_binary_runs_the_scenario_as_the_host_binary_does(platform, ur5e_everywhere, trace_hosts,
                                                                        wine_prefix, host_transcript):
    run = runner(platform, wine_prefix)
    if run.missing:
        pytest.skip(run.missing)
    _, commands, expected = host_transcript
    transcript = run.run(trace_hosts(platform), ur5e_everywhere.binary(platform), commands)
    assert transcript == expected
    assert transcript.count("\n  tick ") == 3  # movediscrete twice, stop once: the run is not empty
