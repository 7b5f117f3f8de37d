"""What a run's process writes before it simulates: the derived FMU and system file."""

from __future__ import annotations

import tomllib
import zipfile

from robogen.campaign.child import derived_fmu, derived_system
from robogen.campaign.plan import Context
from robogen.fmu.extract import extract_fmu


def test_a_derived_fmu_has_the_files_of_the_run_and_unpacks_safely(campaign_fmus, tmp_path):
    base = campaign_fmus["crasher"]
    derived = derived_fmu(base, {"resources/plan.toml": b"time = 1\n", "sources/crasher.c": b"/* replaced */\n"},
                          tmp_path / "crasher.fmu")
    with zipfile.ZipFile(base) as a, zipfile.ZipFile(derived) as b:
        assert sorted(b.namelist()) == sorted(a.namelist() + ["resources/plan.toml"])
        assert b.read("modelDescription.xml") == a.read("modelDescription.xml")
        assert b.read("sources/crasher.c") == b"/* replaced */\n"
    folder = extract_fmu(derived, tmp_path / "unpacked")
    assert (folder / "resources" / "plan.toml").read_text() == "time = 1\n"
    assert (folder / "binaries" / "x86_64-linux" / "crasher.so").stat().st_mode & 0o111  # still executable


def test_the_derived_system_has_the_runs_fmus_and_start_values(tmp_path):
    system = ('connections = ["a.y -> b.u"]\n[experiment]\nstop = 2.0\n'
              '[instances.a]\nfmu = "a.fmu"\nstart = { k = 1, m = 2.5 }\n[instances.b]\nfmu = "../b.fmu"\n')
    context = Context(system, "system.toml", None, None, 60.0, "metrics", (), {}, ())
    text = derived_system(context, {"a": tmp_path / "x" / "a.fmu", "b": tmp_path / "b.fmu"}, {"a": {"k": 7}, "b": {"on": True}})
    assert tomllib.loads(text) == {
        "connections": ["a.y -> b.u"],
        "experiment": {"stop": 2.0},
        "instances": {"a": {"fmu": str(tmp_path / "x" / "a.fmu"), "start": {"k": 7, "m": 2.5}},
                      "b": {"fmu": str(tmp_path / "b.fmu"), "start": {"on": True}}},
    }
