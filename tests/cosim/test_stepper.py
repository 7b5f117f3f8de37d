"""The master's plain-step loop in C (robogen.cosim.stepper) does what the Python loop does: the
same rows byte for byte, the same statistics, the same end when an FMU asks for Event Mode or
to terminate, the same error (and kept rows) when an FMU fails."""

from __future__ import annotations

import pytest

from robogen.cosim import simulate_system, stepper
from robogen.diagnostics import RobogenError

SYSTEMS = {
    # quiet stretches only, over several chunks of the C loop (4,096 rows each)
    "trivial": '[experiment]\nstop = 1.0\nstep = 1e-4\n[instances.t]\nfmu = "{trivial}"\n',
    # a periodic clock every 0.25 s ends each stretch; two FMUs step side by side
    "ticker": '[experiment]\nstop = 3.0\nstep = 0.1\n[instances.k]\nfmu = "{ticker}"\n[instances.t]\nfmu = "{trivial}"\n',
    # a terminate request from fmi3DoStep in the middle of a stretch
    "terminate": '[experiment]\nstop = 10.0\nstep = 0.01\n[instances.t]\nfmu = "{trivial}"\nstart = { stop_at = 3.005 }\n',
}


@pytest.fixture
def loops(monkeypatch):
    """run(system) with the Python loop and with the C stepper: (python, c) results."""

    def run(path, **kwargs):
        monkeypatch.setattr(stepper, "_tried", True)
        monkeypatch.setattr(stepper, "_lib", None)
        python = simulate_system(path, output=path.with_suffix(".py.csv"), **kwargs)
        monkeypatch.setattr(stepper, "_tried", False)
        c = simulate_system(path, output=path.with_suffix(".c.csv"), **kwargs)
        assert stepper._lib is not None, "the C stepper did not build here"
        return python, c

    return run


@pytest.mark.parametrize("name", sorted(SYSTEMS))
def test_c_stepper_gives_the_python_loops_results(loops, write_system, name):
    python, c = loops(write_system(SYSTEMS[name], name=f"{name}.toml"))
    assert c.output.read_bytes() == python.output.read_bytes()
    assert c.rows == python.rows
    for field in ("steps", "event_iterations", "instants", "end_time", "terminated_by"):
        assert getattr(c.stats, field) == getattr(python.stats, field), field
    if name == "trivial":
        assert c.stats.steps == 10_000 and len(c.rows) == 10_002  # (0,0), (0,1) and one row per step
    if name == "terminate":  # the step reaching 3.005 is t = 3.01; its row is recorded
        assert c.stats.terminated_by == "instance 't' asked to terminate in fmi3DoStep at t=3.01"
        assert c.rows[-1][0] == 301 * 0.01  # the grid is n * h, not a running sum


def test_c_stepper_stops_at_a_failing_fmu_with_the_same_error_and_rows(monkeypatch, write_system, tmp_path):
    path = write_system('[experiment]\nstop = 2.0\nstep = 0.1\n[instances.f]\nfmu = "{failer}"\n', name="fail.toml")
    messages = []
    for loop in ("py", "c"):
        monkeypatch.setattr(stepper, "_tried", loop == "py")
        monkeypatch.setattr(stepper, "_lib", None)
        with pytest.raises(RobogenError) as exc:
            simulate_system(path, output=tmp_path / f"{loop}.csv")
        messages.append(exc.value.diagnostics[0].message)
    assert stepper._lib is not None  # the second run used the C stepper
    assert messages[0] == messages[1]
    assert "instance 'f': fmi3DoStep returned fmi3Error at t=0.5" in messages[0]
    assert (tmp_path / "py.csv").read_bytes() == (tmp_path / "c.csv").read_bytes()
