"""Generated FMUs in another importer: fmpy's simulate_fmu with event mode on, and `fmpy compile`
rebuilding the binary from the FMU's sources/ with fmpy's own CMake project."""

from __future__ import annotations

import os
import random
import subprocess
import sys
import zipfile
from pathlib import Path

import fmpy
import pytest

from support.codegen_driver import FmuRunner, interpret, random_scenario

COUNTERS = ["cycles", "dropped_events", "deadline_misses"]


@pytest.mark.parametrize("name", ["ur5e", "timers", "pipeline"])
def test_simulate_fmu_with_event_mode_records_the_unclocked_outputs(built, name):
    """simulate_fmu never sets a clock (fmpy's simulate_fmu has no clock support): the periodic ticks pass unused (the
    runtime warns), so the machines rest in their initial node and no cycle is counted; the run
    goes to the stop time through Event Mode and Step Mode without an error."""
    b = built(name, "stepwise")
    states = [f"{m.name}.state" for m in b.fmu.machines]
    messages: list[str] = []
    result = fmpy.simulate_fmu(str(b.archive), use_event_mode=True, stop_time=3.0, output_interval=0.5,
                               output=states + COUNTERS, debug_logging=True,
                               logger=lambda *args: messages.append(args[-1].decode()))
    assert list(result.dtype.names) == ["time", *states, *COUNTERS]
    assert [float(t) for t in result["time"]] == [0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0]
    assert not any("Terminated" in text for text in messages)
    if b.fmu.time_free:  # RoboChart, --time skip: no clock to set; the FMU counts its tocks and runs at
        # each Event Mode simulate_fmu opens (at the start: tock 0). It announces tock 2 (since(D) >= 1
        # can change there), which a step counts up to but not past. A step counts the tocks before
        # its end, leaving a tock at its end to an Event Mode there (1 at 0.5 and 1.0, 2 from 1.5);
        # the step from 2.0 passes tock 2 (warned: it is left to the next Event Mode, which never
        # comes), and the step to 3.0 counts tock 2, leaving tock 3 at its end
        assert [int(c) for c in result["cycles"]] == [1, 1, 1, 2, 2, 2, 3]
        assert any("passes the next event time t=2" in text for text in messages), messages
        return
    for m in b.fmu.machines:
        assert set(result[f"{m.name}.state"]) == {m.initial_node}
    assert set(result["cycles"]) == {0}
    assert any("passed without being activated" in text for text in messages)


def test_fmpy_compile_rebuilds_a_working_binary_from_the_sources(built, tmp_path):
    """The archive without its binary, rebuilt by `fmpy compile` (all warnings, as errors), runs
    the same traces as the interpreter. fmpy depends on the cmake package: its cmake is next to
    this Python."""
    b = built("relay", "stepwise")
    stripped = tmp_path / "relay.fmu"
    with zipfile.ZipFile(b.archive) as src, zipfile.ZipFile(stripped, "w", zipfile.ZIP_DEFLATED) as dst:
        for item in src.infolist():
            if not item.filename.startswith("binaries/"):
                dst.writestr(item, src.read(item.filename))
    env_path = f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}"
    result = subprocess.run([sys.executable, "-m", "fmpy.cli", "compile", "--all-warnings", "--warning-as-error",
                             str(stripped)], capture_output=True, text=True, env={"PATH": env_path, "HOME": str(tmp_path)})
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    folder = tmp_path / "unzipped"
    with zipfile.ZipFile(stripped) as z:
        assert "binaries/x86_64-linux/RelayModule.so" in z.namelist()
        z.extractall(folder)
    runner = FmuRunner(folder)
    try:
        rng = random.Random(3)
        for _ in range(20):
            scenario = random_scenario(rng, runner.desc, 20)
            assert runner.run(scenario).comparable() == interpret(b.fmu, scenario, runner.desc).comparable()
    finally:
        runner.close()
