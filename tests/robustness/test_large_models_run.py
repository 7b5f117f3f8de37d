"""A model of 10,000 states in a row of exec transitions goes all the way: it checks, compiles
with the project's strict flags (as one C function per part of the machine) and runs in the
master. RoboSim: each cycle takes the exec transition decided in the cycle before, so after the
cycle at t = k the machine rests in S<k>."""

from __future__ import annotations

import csv
import zipfile

from robogen.cli import main
from robogen.fmu.modeldesc import read_model_description

STATES = 10_000


def chain(states: int) -> str:
    body = [f"\tstate S{j} {{ }}\n\ttransition t{j} {{ from S{j} to S{(j + 1) % states} exec }}" for j in range(states)]
    return "stm Chain {\n\tcycleDef cycle == 1\n\tinitial i\n\ttransition t { from i to S0 }\n" + "\n".join(body) + "\n}\n"


def test_a_chain_of_ten_thousand_exec_transitions_compiles_and_runs(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "chain.rst").write_text(chain(STATES), encoding="utf-8")
    (tmp_path / "run.toml").write_text('[experiment]\nstop = 3.0\nstep = 1.0\n[instances.c]\nfmu = "chain.fmu"\n'
                                       '[record]\nvariables = ["c.Chain.state"]\n', encoding="utf-8")

    assert main(["package", "chain.rst", "-o", "chain.fmu"]) == 0
    assert main(["simulate", "run.toml", "-o", "r.csv"]) == 0

    capsys.readouterr()
    with zipfile.ZipFile(tmp_path / "chain.fmu") as z:
        desc = read_model_description(z.read("modelDescription.xml"))
    (nodes,) = [t for t in desc.type_definitions if t.name == "Chain.Node"]
    label = {item.value: item.name for item in nodes.items}
    assert len(label) == STATES + 1  # the states and the initial node
    with open(tmp_path / "r.csv", newline="") as f:
        last = {round(float(r["time"])): label[int(r["c.Chain.state"])] for r in csv.DictReader(f)}  # each time's last row
    assert last == {0: "S0", 1: "S1", 2: "S2", 3: "S3"}


def test_a_flat_sum_of_a_thousand_operands_checks_packages_and_computes(tmp_path, monkeypatch, capsys):
    # RoboSim: x = 1, then the entry action sets x = x*0 + x*1 + ... + x*999 = 999 * 1000 / 2
    terms = 1000
    model = ("stm Flat {\n\tcycleDef cycle == 1\n\tvar x: int = 1\n\tinitial i\n\tstate A { entry x = "
             + " + ".join(f"x * {k}" for k in range(terms)) + " }\n\ttransition t { from i to A }\n"
             "\ttransition u { from A to A exec }\n}\n")
    monkeypatch.chdir(tmp_path)
    (tmp_path / "flat.rst").write_text(model, encoding="utf-8")
    (tmp_path / "run.toml").write_text('[experiment]\nstop = 0.0\nstep = 1.0\n[instances.f]\nfmu = "flat.fmu"\n'
                                       '[record]\nvariables = ["f.Flat.x"]\n', encoding="utf-8")
    assert main(["check", "flat.rst"]) == 0
    assert main(["package", "flat.rst", "-o", "flat.fmu"]) == 0
    assert main(["simulate", "run.toml", "-o", "r.csv"]) == 0
    capsys.readouterr()
    with open(tmp_path / "r.csv", newline="") as f:
        values = [int(r["f.Flat.x"]) for r in csv.DictReader(f)]
    assert values[-1] == terms * (terms - 1) // 2
