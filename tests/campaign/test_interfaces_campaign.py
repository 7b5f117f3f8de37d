"""A campaign varies how an instance uses its FMU: its interface (and a Model Exchange FMU's
solver), as ``instance.interface`` parameters merged into each run's system file."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

from robogen.diagnostics import RobogenError
from support import ROOT
from support.campaign import run_quietly, write_campaign_folder

BALL = '[experiment]\nstop = 1.0\nstep = 0.1\ntolerance = 1e-6\n[instances.ball]\nfmu = "bounce3.fmu"\n'


@pytest.fixture(scope="module")
def bounce(tmp_path_factory) -> dict[str, Path]:
    spec = importlib.util.spec_from_file_location("robogen_test_fmus_others", ROOT / "tests/cosim/fmus/others.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return {"bounce3": module.build("bounce3", tmp_path_factory.mktemp("bounce"))}


def test_a_campaign_runs_an_fmu_through_each_of_its_interfaces(tmp_path, bounce):
    import pyarrow.parquet as pq

    campaign = write_campaign_folder(tmp_path, bounce, 'system = "system.toml"\n[grid]\n'
                                     '"ball.interface" = ["co-simulation", "model-exchange"]\n"ball.solver" = ["cvode"]\n'
                                     '[metrics]\nbounces = { final = "ball.bounces" }\nh = { at = "ball.h", time = 0.5 }\n',
                                     BALL)
    run_quietly(campaign, tmp_path / "out")
    rows = sorted(pq.read_table(tmp_path / "out" / "runs.parquet").to_pylist(), key=lambda r: r["ball.interface"])
    assert [(r["ball.interface"], r["status"], r["bounces"]) for r in rows] == [("co-simulation", "ok", 1),
                                                                                ("model-exchange", "ok", 1)]
    # after the bounce at sqrt(2 / g): CVode locates it (model exchange), the FMU's own RK4 bounces
    # at its first 1 ms step past it (co-simulation): the heights at 0.5 s within 5e-3
    assert rows[0]["h"] == pytest.approx(rows[1]["h"], abs=5e-3) and rows[0]["h"] != rows[1]["h"]


def test_an_interface_the_fmu_lacks_is_an_error_at_the_parameter(tmp_path, bounce):
    campaign = write_campaign_folder(tmp_path, bounce, 'system = "system.toml"\n[grid]\n'
                                     '"ball.interface" = ["scheduled-execution"]\n[metrics]\n'
                                     'bounces = { final = "ball.bounces" }\n', BALL)
    with pytest.raises(RobogenError) as exc:
        run_quietly(campaign, tmp_path / "out")
    d = exc.value.diagnostics[0]
    assert d.message == ("'ball.interface' must be one of 'co-simulation', 'model-exchange', not 'scheduled-execution' "
                         "(the FMU offers those interfaces)")
    assert d.span.line == 3
