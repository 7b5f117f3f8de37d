"""The mixed system of examples/mixed/system.toml: the UR5e d-model (FMI 3.0, generated, clocks)
commanding an FMI 2.0 Model Exchange gantry, its target cell held in the gantry's Integer inputs;
run as its comment says, checked against the gantry's response by hand, plotted, and run again
from its SSP 2.0 export (robogen export-ssp) to the same bytes."""

from __future__ import annotations

import math
import shutil

import pytest

from robogen.cli import main
from robogen.cosim import simulate_system
from support import ROOT


@pytest.mark.slow
def test_the_ur5e_d_model_commands_an_fmi2_model_exchange_plant(tmp_path, other_builder):
    build = tmp_path / "build" / "mixed"
    other_builder.build("gantry2", build)
    assert main(["package", str(ROOT / "models/ur5e/ur5e.rst"), "--time-unit", "0.5", "-o", str(build / "dmodel.fmu")]) == 0
    assert main(["package-py", "robogen.platforms.controller:PlanController", "--set",
                 f"plan={ROOT / 'models/ur5e/plan.toml'}", "-o", str(build / "controller.fmu")]) == 0
    (tmp_path / "examples" / "mixed").mkdir(parents=True)
    system = tmp_path / "examples" / "mixed" / "system.toml"
    shutil.copy(ROOT / "examples" / "mixed" / "system.toml", system)
    result = simulate_system(system, output=build / "results.csv")
    rows = [dict(zip(result.columns, r)) for r in result.rows]
    # the first command (controller, 5.0 s: cell 0, 23, 1) reaches the d-model, which calls
    # movediscrete(0, 23, 1) in the same instant; the gantry holds it: y = 1.15 (1 - exp(-(t - 5) / 0.5))
    first = next(r for r in rows if r["dmodel.movediscrete"] == 1)
    assert (first["time"], first["dmodel.movediscrete.target_Y"], first["dmodel.movediscrete.target_Z"]) == (5.0, 23, 1)
    for r in rows:
        if r["superdense"] == 0 and r["time"] > 5.0:
            lag = 1 - math.exp(-(r["time"] - 5.0) / 0.5)
            assert r["plant.y"] == pytest.approx(23 * 0.05 * lag, abs=1e-4)  # CVode at rtol 1e-6
            assert r["plant.z"] == pytest.approx(0.05 * lag, abs=1e-5) and r["plant.x"] == 0.0
    figure = build / "results.png"
    assert main(["plot", str(build / "results.csv"), "--vars", "plant.*", "dmodel.movediscrete*", "-o", str(figure)]) == 0
    assert figure.stat().st_size > 10_000
    # the same system as SSP 2.0 (FMI 2.0 ME, a generated FMU with clocks, a Python FMU): the same results
    from robogen.cosim.ssp_write import export_ssp
    from support.ssp import SCHEMAS, validate

    ssp = export_ssp(system, build / "mixed.ssp")
    if SCHEMAS.is_dir():
        validate(ssp)
    simulate_system(ssp, output=build / "ssp.csv")
    assert (build / "ssp.csv").read_bytes() == (build / "results.csv").read_bytes()
