"""Time on long horizons: grid points and clock ticks stay exact (integer indices, and a time
tolerance capped at a quarter of the run's time resolution: robogen.fmu.fmi.tolerance), in the
master and in a generated FMU's runtime (rg_time_equal, the same rule). ``stop = 1e9, step = 1.0``
and ``stop = 1e7, step = 0.01`` run (interrupted here: they would take hours); their last seconds,
run from a start just before the stop, tick where they should; a step doubles cannot resolve at the
stop time is refused with the numbers (tests/cosim/test_master.py)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest

from robogen.cosim import simulate_system
from robogen.fmu.fmi import time_resolution, tolerance


@pytest.fixture(scope="module")
def pulse(tmp_path_factory):
    """A generated FMU (tests/models/valid/pulse.rst) whose cycle clock ticks every 0.25 s."""
    from robogen.cli import main

    out = tmp_path_factory.mktemp("pulse") / "pulse.fmu"
    assert main(["package", "tests/models/valid/pulse.rst", "--time-unit", "0.25", "-o", str(out)]) == 0
    return out


def test_the_time_resolution_and_tolerance():
    assert time_resolution([0.01]) == 0.01 and time_resolution([0.1, 0.25]) == 0.05 and time_resolution([1.0, 0.25]) == 0.25
    assert tolerance(3.0, 0.1) == 1e-9 * 3.0  # as before on short horizons: relative
    assert tolerance(1e7, 0.01) == 0.0025 and tolerance(1e9, 0.25) == 0.0625  # capped: grid points stay apart
    assert tolerance(1e7, 0.01) < 0.01 / 2


def system(fmu, start: float, stop: float, step: float) -> str:
    return (f'[experiment]\nstart = {start!r}\nstop = {stop!r}\nstep = {step!r}\n[instances.p]\nfmu = "{fmu}"\n'
            '[instances.t]\nfmu = "{trivial}"\n[record]\nvariables = ["p.cycle", "p.cycles", "t.y"]\n')


@pytest.mark.parametrize("stop, step", [(1e9, 1.0), (1e7, 0.01)])
@pytest.mark.parametrize("loop", ["Python", "C"])
def test_the_last_seconds_of_a_long_horizon_tick_exactly(write_system, pulse, monkeypatch, loop, stop, step):
    # from 10 s before the stop: every grid point start + n step, every tick of the FMU's cycle
    # (0.25 s) activated once, the cycle count 1 + 40 at the stop; the trivial FMU's y = u + t is t
    if loop == "Python":
        monkeypatch.setenv("ROBOGEN_REFERENCE_LOOP", "1")
    start = stop - 10.0
    result = simulate_system(write_system(system(pulse, start, stop, step)))
    plain = [r for r in result.rows if r[1] == 0]
    times = sorted({r[0] for r in plain})
    assert times == sorted({start + n * step for n in range(round(10 / step) + 1)} | {start + k * 0.25 for k in range(41)})
    ticks = [r[0] for r in result.rows if r[2] == 1]
    assert ticks == [start + k * 0.25 for k in range(41)]
    assert result.rows[-1][0] == stop and result.rows[-1][3] == 41
    assert all(r[4] == r[0] for r in plain)  # the FMU's y is the time it was stepped to


@pytest.mark.parametrize("stop, step", [(1e9, 1.0), (1e7, 0.01)])
def test_robogen_simulate_runs_a_long_horizon_until_interrupted(write_system, pulse, tmp_path, stop, step):
    path = write_system(system(pulse, 0.0, stop, step))
    (tmp_path / "tmp").mkdir(exist_ok=True)
    proc = subprocess.Popen([sys.executable, "-m", "robogen", "simulate", str(path), "-o", "r.csv"], cwd=tmp_path, text=True,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, env={**os.environ, "TMPDIR": str(tmp_path / "tmp")})
    # interrupted once it has recorded rows (about 2 s after it starts; a loaded machine may take
    # over a minute to start the process, so the wait is for the rows, not for a fixed time)
    deadline = time.monotonic() + 300
    while not any(p.stat().st_size > 4096 for p in tmp_path.glob(".r.csv.*.tmp")):
        assert proc.poll() is None, proc.communicate()  # accepted: it runs
        if time.monotonic() > deadline:
            proc.kill()
            pytest.fail(f"no rows recorded in 300 s: {proc.communicate()}")
        time.sleep(0.1)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 128 + signal.SIGINT, err
    assert err.strip().splitlines()[-1] == "robogen simulate: interrupted (SIGINT); results recorded so far are in r.csv"
    times = [float(line.split(",")[0]) for line in (tmp_path / "r.csv").read_text().splitlines()[1:]]
    assert len(set(times)) > 10 and times == sorted(times)
    # every time a grid point n step or a tick k 0.25, computed from its index
    assert all(t == round(t / step) * step or t == round(t / 0.25) * 0.25 for t in times)


def test_a_generated_fmu_tells_its_ticks_apart_at_1e9(pulse, tmp_path):
    # the runtime's rg_time_equal: at t = 1e9 a relative 1e-9 is 1 s, four of the cycle's ticks
    # (0.25 s); capped at a quarter of the FMU's resolution (0.25 s), a step from 1e9 to 1e9 + 0.5
    # passes the tick at 1e9 + 0.25 that was not activated, and the FMU refuses it
    from robogen.cosim.fmi3 import Binding, FMI3Error, Library, ffi, vr_array
    from robogen.fmu.extract import extract_fmu
    from robogen.fmu.modeldesc import load_model_description

    folder = extract_fmu(pulse, tmp_path / "pulse")
    md = load_model_description(folder)
    binding = Binding(Library(str(folder / "binaries" / "x86_64-linux" / f"{md.co_simulation.model_identifier}.so")), "p")
    binding.fmi3InstantiateCoSimulation(md.instantiation_token, None, eventModeUsed=True)
    try:
        binding.fmi3EnterInitializationMode(None, 1e9, None)
        binding.fmi3ExitInitializationMode()
        cycle = md.by_name()["cycle"].value_reference
        binding.fmi3SetClock(vr_array([cycle]), 1, ffi.new("bool[]", [True]))
        while binding.fmi3UpdateDiscreteStates().discrete_states_need_update:
            pass
        binding.fmi3EnterStepMode()
        with pytest.raises(FMI3Error) as exc:
            binding.fmi3DoStep(1e9, 0.5)
        assert "would pass tick k=1 of 'cycle' at t=1000000000.25" in exc.value.message
    finally:
        binding.fmi3FreeInstance()
