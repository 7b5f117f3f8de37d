"""Fixtures for the master's tests: robogen's own C test FMUs, built once per session."""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import pytest

FMUS_DIR = Path(__file__).resolve().parent / "fmus"


def _builder():
    spec = importlib.util.spec_from_file_location("robogen_test_fmus_build", FMUS_DIR / "build.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="session")
def fmu_builder():
    return _builder()


def _others():
    spec = importlib.util.spec_from_file_location("robogen_test_fmus_others", FMUS_DIR / "others.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="session")
def other_builder():
    """The builder of the test FMUs of other interfaces (tests/cosim/fmus/others.py)."""
    return _others()


@pytest.fixture(scope="session")
def fmus(tmp_path_factory, fmu_builder, other_builder) -> dict[str, Path]:
    """name -> path of every test FMU: FMI 3.0 Co-Simulation (ball, stair, ticker, relay, zeno,
    failer, trivial, alltypes) and the other interfaces (bounce3, bounce2, vdp2, vdp3, stiff3, lag2,
    lag2me, sched3)."""
    folder = tmp_path_factory.mktemp("fmus")
    return {**fmu_builder.build_all(folder), **other_builder.build_all(folder)}


@pytest.fixture
def write_system(tmp_path, fmus):
    """write_system(text) -> path of a system TOML in tmp_path where '{name}' is replaced by that FMU's path."""

    def write(text: str, name: str = "system.toml") -> Path:
        for key, path in fmus.items():
            text = text.replace("{" + key + "}", str(path))
        p = tmp_path / name
        p.write_text(text)
        return p

    return write


@pytest.fixture(scope="session")
def misbehaving(tmp_path_factory) -> Path:
    """The Python FMU of misbehaving_models.Misbehaving (crashes, raises or sleeps on request)."""
    from robogen.pyfmu.build import package

    return package("misbehaving_models:Misbehaving", tmp_path_factory.mktemp("pyfmus") / "misbehaving.fmu").path


@pytest.fixture
def robogen_process(tmp_path):
    """run(*args, env=None) -> CompletedProcess: ``robogen ARGS`` in a process of its own (for
    crashes and signals), in tmp_path, with TMPDIR = tmp_path/tmp (to see what it leaves there)."""

    def run(*args: str, env: dict | None = None, timeout: float = 120) -> subprocess.CompletedProcess:
        tmp = tmp_path / "tmp"
        tmp.mkdir(exist_ok=True)
        return subprocess.run([sys.executable, "-m", "robogen", *map(str, args)], cwd=tmp_path, capture_output=True,
                              text=True, timeout=timeout, env={**os.environ, "TMPDIR": str(tmp), **(env or {})})

    return run


@pytest.fixture(scope="session")
def unit_fmus(tmp_path_factory, fmu_builder) -> dict[str, Path]:
    """The trivial FMU (y = u + t) in units: 'm' (u and y in metres, defined: BaseUnit m=1),
    'mm' (in millimetres, defined: m=1, factor 0.001) and 'cm' (in centimetres, named by the
    variables but not defined by the model description)."""
    import dataclasses

    from robogen.fmu.modeldesc import Unit

    folder = tmp_path_factory.mktemp("unit-fmus")
    definitions = {"m": Unit("m", (("m", 1),)), "mm": Unit("mm", (("m", 1),), factor="0.001"), "cm": None}
    built = {}
    for name, unit in definitions.items():
        spec = dict(fmu_builder.MODELS["trivial"])
        spec["vars"] = [dataclasses.replace(v, unit=name) if v.name in ("u", "y") else v for v in spec["vars"]]
        spec["units"] = () if unit is None else (unit,)
        built[name] = fmu_builder.build("trivial", folder / name, spec=spec, source=fmu_builder.HERE / "trivial.c")
    return built
