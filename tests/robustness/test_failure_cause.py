"""A failing FMU call is reported with its cause: every message the FMU logged at fmi3Error or
worse, not only the last one (a generated FMU logs a machine's deadlock, then the call that fails)."""

from __future__ import annotations

from robogen.cli import main
from robogen.cosim.fmi3 import LogMemory
from robogen.fmu.fmi import ERROR, OK, WARNING

# RoboSim: after the initial transition, A has no transition and no exec: the first cycle deadlocks.
STUCK = "stm S {\n\tcycleDef cycle == 1\n\tvar x: nat\n\tinitial i\n\tstate A { }\n\ttransition t { from i to A action x = 1 }\n}\n"
SYSTEM = '[experiment]\nstop = 1.0\nstep = 0.5\n[instances.g]\nfmu = "g.fmu"\n'


def test_the_memory_keeps_every_error_and_else_the_last_warning():
    memory = LogMemory()
    memory.note(OK, "instantiated")
    assert memory.message() == "instantiated"
    memory.note(WARNING, "slow")
    memory.note(OK, "fine")
    assert memory.message() == "slow"
    memory.note(ERROR, "cause")
    memory.note(ERROR, "the call failed")
    memory.note(ERROR, "cause")
    assert memory.message() == "cause; the call failed"


def test_a_deadlocked_machine_is_named_with_its_state_and_line(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "g.rst").write_text(STUCK, encoding="utf-8")
    (tmp_path / "s.toml").write_text(SYSTEM, encoding="utf-8")
    assert main(["package", "g.rst", "-o", "g.fmu"]) == 0
    capsys.readouterr()

    assert main(["simulate", "s.toml", "-o", "r.csv"]) == 1

    err = capsys.readouterr().err
    assert "S: deadlock in state 'A' (g.rst:5): no transition is enabled and no exec" in err
    assert "the model failed to evaluate the instant at t=0" in err
    assert "Traceback" not in err and "internal error" not in err
