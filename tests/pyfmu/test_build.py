"""robogen package-py: the archive, the binary's exports and links, the model description, the
validators, reproducibility, settings and the command line's errors."""

from __future__ import annotations

import re
import subprocess
import xml.etree.ElementTree as ET
import zipfile

import pytest
from fmpy.validation import validate_fmu as fmpy_validate

from robogen.cli import main
from robogen.fmu.binaries import read_binary
from robogen.fmu.validate import fmi3_function_names, validate_fmu
from robogen.pyfmu.build import collect_python, package


def members(fmu) -> set[str]:
    with zipfile.ZipFile(fmu) as z:
        return set(z.namelist())


def read(fmu, name: str) -> bytes:
    with zipfile.ZipFile(fmu) as z:
        return z.read(name)


def test_archive_layout_and_the_python_code_that_travels_with_it(fmus):
    names = members(fmus["counter"])
    assert {
        "modelDescription.xml",
        "binaries/x86_64-linux/counter.so",
        "documentation/externalDependencies.txt",
        "resources/pyfmu.json",
        "resources/python/pyfmu_fixture_models.py",
        "resources/python/robogen/__init__.py",
        "resources/python/robogen/fmu/__init__.py",
        "resources/python/robogen/fmu/fmi.py",  # the FMI constants the slave uses
        "resources/python/robogen/pyfmu/__init__.py",
        "resources/python/robogen/pyfmu/model.py",
        "resources/python/robogen/pyfmu/slave.py",
    } == names  # exactly the modules the model needs, not the packager itself


def test_import_scan_follows_first_party_imports_only():
    files = collect_python("robogen.platforms.controller")
    assert "robogen/platforms/plan.py" in files and "robogen/diagnostics.py" in files
    assert not any(name.startswith(("numpy", "fmpy", "tomllib")) for name in files)
    assert "robogen/pyfmu/build.py" not in files


def test_the_binary_exports_the_75_fmi3_functions_and_the_module_init_only(fmus):
    exported = set(read_binary(read(fmus["counter"], "binaries/x86_64-linux/counter.so")).exports)
    fmi3 = {name for name in exported if name.startswith("fmi3")}
    assert fmi3 == set(fmi3_function_names()) and len(fmi3) == 75
    others = exported - fmi3
    assert len(others) == 1 and re.fullmatch(r"PyInit__pyfmu_counter_[0-9a-f]{12}", others.pop())


def test_the_binary_needs_libpython_and_is_never_unloaded(fmus, tmp_path):
    so = tmp_path / "counter.so"
    so.write_bytes(read(fmus["counter"], "binaries/x86_64-linux/counter.so"))
    dynamic = subprocess.run(["readelf", "-d", str(so)], capture_output=True, text=True, check=True).stdout
    assert re.search(r"NEEDED.*\[libpython3\.\d+\.so\.1\.0\]", dynamic)
    assert re.search(r"FLAGS_1.*NODELETE", dynamic)  # the interpreter keeps pointers into it
    assert "RUNPATH" in dynamic


def test_model_description_from_the_declarations(fmus):
    root = ET.fromstring(read(fmus["counter"], "modelDescription.xml"))
    assert root.attrib["fmiVersion"] == "3.0"
    cs = root.find("CoSimulation").attrib
    assert (cs["modelIdentifier"], cs["hasEventMode"], cs["mightReturnEarlyFromDoStep"]) == ("counter", "true", "true")
    by_name = {v.attrib["name"]: v for v in root.find("ModelVariables")}
    tick = by_name["tick"].attrib
    assert (tick["intervalVariability"], tick["intervalDecimal"], tick["shiftDecimal"]) == ("constant", "0.5", "0.0")
    assert by_name["ticked.count"].attrib["clocks"] == by_name["ticked"].attrib["valueReference"]
    assert "start" not in by_name["ticked.count"].attrib  # calculated
    structure = root.find("ModelStructure")
    outputs = [e.attrib["valueReference"] for e in structure.findall("Output")]
    assert by_name["ticked"].attrib["valueReference"] in outputs and by_name["alarm"].attrib["valueReference"] in outputs
    unknowns = {e.attrib["valueReference"] for e in structure.findall("InitialUnknown")}
    assert by_name["ticked.count"].attrib["valueReference"] not in unknowns  # clocked: never
    assert by_name["ticked"].attrib["valueReference"] in unknowns  # an unclocked output clock
    dependencies = {e.attrib["valueReference"]: e.attrib.get("dependencies") for e in structure.findall("Output")}
    assert dependencies[by_name["ticked"].attrib["valueReference"]] == by_name["tick"].attrib["valueReference"]


def test_a_setting_changes_the_constant_clock_in_the_xml(fmus):
    root = ET.fromstring(read(fmus["counter_fast"], "modelDescription.xml"))
    tick = next(v for v in root.find("ModelVariables") if v.attrib["name"] == "tick")
    assert tick.attrib["intervalDecimal"] == "0.25"
    assert root.attrib["instantiationToken"] != ET.fromstring(read(fmus["counter"], "modelDescription.xml")).attrib[
        "instantiationToken"]


@pytest.mark.parametrize("name", ["counter", "two_instants", "uses_numpy"])
def test_fmpy_and_robogen_validators_accept_the_fmus(fmus, name):
    assert fmpy_validate(str(fmus[name])) == []
    assert [d.render() for d in validate_fmu(fmus[name]) if d.is_error] == []


def test_external_dependencies_name_python_and_cffi(fmus):
    text = read(fmus["counter"], "documentation/externalDependencies.txt").decode()
    assert re.search(r"libpython3\.\d+\.so\.1\.0", text)
    assert "cffi " in text and "site-packages" in text


def test_packaging_is_reproducible(tmp_path):
    a = package("pyfmu_fixture_models:TwoInstants", tmp_path / "a.fmu").path.read_bytes()
    b = package("pyfmu_fixture_models:TwoInstants", tmp_path / "b.fmu").path.read_bytes()
    assert a == b


@pytest.mark.parametrize("argv, message", [
    (["no_such_module:Thing"], "no module named 'no_such_module'"),
    (["pyfmu_fixture_models"], "is not MODULE:CLASS"),
    (["pyfmu_fixture_models:Countr"], "has no class 'Countr' (did you mean 'Counter'?)"),
    (["pyfmu_fixture_models:Counter", "--set", "perod=1"], "has no setting 'perod' (did you mean 'period'?)"),
    (["pyfmu_fixture_models:Counter", "--set", "period=fast"], "--set period=fast: could not convert"),
    (["robogen.diagnostics:Span"], "is not a subclass of robogen.pyfmu.Model"),
    (["robogen.platforms.controller:PlanController"], "PlanController needs --set plan=VALUE"),
])
def test_command_line_errors_are_reported_without_a_traceback(argv, message, tmp_path, capsys):
    status = main(["package-py", *argv, "-o", str(tmp_path / "x.fmu")])
    err = capsys.readouterr().err
    assert status == 1
    assert message in err and "Traceback" not in err
    assert not (tmp_path / "x.fmu").exists()


def test_command_line_writes_the_fmu(tmp_path, capsys):
    target = tmp_path / "counter.fmu"
    assert main(["package-py", "pyfmu_fixture_models:Counter", "-o", str(target), "--set", "period=0.1"]) == 0
    assert "wrote" in capsys.readouterr().err
    assert b'intervalDecimal="0.1"' in read(target, "modelDescription.xml")


# ---- the user's own mistakes: located errors, never an internal error --------------------------

BROKEN_MODULES = {
    # a module that raises while it is imported: located at the raising line
    "raises_on_import": ("import math\n\nLIMIT = math.sqrt(-1)\n",
                         "importing 'raises_on_import' failed: ValueError: math domain error", 3),
    # a declaration FMI 3.0 does not allow: located at the class statement
    "bad_declaration": ("from robogen.pyfmu import Float64, Model\n\n\nclass Bad(Model):\n"
                        "    x = Float64(0.0, causality='parameter', variability='continuous')\n",
                        "a declaration in 'bad_declaration' is not valid: Bad: variable 'x': a parameter must be", 4),
    # a Float64 whose start is not a number
    "bad_start": ("from robogen.pyfmu import Float64, Model\n\n\nclass Bad(Model):\n"
                  "    x = Float64('high', causality='output')\n",
                  "importing 'bad_start' failed: TypeError: x: expected Float64, got str 'high'", 4),
    # a default outside the limits the class declares
    "bad_default": ("from robogen.pyfmu import Model, Setting\n\n\nclass Bad(Model):\n"
                    "    gain = Setting(-2.0, 'a gain', gt=0)\n",
                    "a declaration in 'bad_default' is not valid: Bad.gain: the default -2.0 is not > 0", 4),
}


@pytest.mark.parametrize("module", sorted(BROKEN_MODULES))
def test_a_broken_model_module_is_a_located_error(module, tmp_path, monkeypatch, capsys):
    source, message, line = BROKEN_MODULES[module]  # line: where in the module the error points
    (tmp_path / f"{module}.py").write_text(source)
    monkeypatch.syspath_prepend(str(tmp_path))
    assert main(["package-py", f"{module}:Bad", "-o", str(tmp_path / "x.fmu")]) == 1
    err = capsys.readouterr().err
    assert f"error: {message}" in err
    assert "Traceback" not in err and "internal error" not in err
    assert f"{module}.py:{line}:1: error" in err
    assert not (tmp_path / "x.fmu").exists()


LIMITED = """from robogen.pyfmu import Clock, Float64, Int64, Model, Setting, String


class Limited(Model):
    period = Setting(0.5, "interval of 'tick' [s]")
    offset = Setting(0.0, "shift of 'tick' [s]")
    gain = Setting(1.0, "a gain", ge=0.5, lt=10)
    mode = Setting("fast", "how", choices=("fast", "slow"))
    tick = Clock(kind="constant", causality="input", interval="period", shift="offset")
    count = Int64(causality="output", clock=None)
    label = String("x", causality="parameter", variability="fixed")
    y = Float64(causality="output")
"""


@pytest.mark.parametrize("setting, message", [
    ("period=0", "--set period=0: 0.0 is not > 0 (the interval of clock 'tick')"),
    ("period=-1", "--set period=-1: -1.0 is not > 0 (the interval of clock 'tick')"),
    ("offset=-0.1", "--set offset=-0.1: -0.1 is not >= 0 (the shift of clock 'tick')"),
    ("gain=0.1", "--set gain=0.1: 0.1 is not >= 0.5"),
    ("gain=10", "--set gain=10: 10.0 is not < 10"),
    ("mode=medium", "--set mode=medium: 'medium' is not one of 'fast', 'slow'"),
])
def test_settings_are_checked_against_what_the_class_declares(setting, message, tmp_path, monkeypatch, capsys):
    (tmp_path / "limited_models.py").write_text(LIMITED)
    monkeypatch.syspath_prepend(str(tmp_path))
    assert main(["package-py", "limited_models:Limited", "--set", setting, "-o", str(tmp_path / "x.fmu")]) == 1
    err = capsys.readouterr().err
    assert f"error: {message}" in err and "Traceback" not in err
    assert not (tmp_path / "x.fmu").exists()


def test_package_resources_that_fail_are_located(tmp_path, monkeypatch, capsys):
    (tmp_path / "resourceful.py").write_text(
        "from robogen.pyfmu import Float64, Model\n\n\nclass R(Model):\n    y = Float64(causality='output')\n\n"
        "    @classmethod\n    def package_resources(cls):\n        return {'table.csv': open('/no/such/table.csv').read()}\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    assert main(["package-py", "resourceful:R", "-o", str(tmp_path / "x.fmu")]) == 1
    err = capsys.readouterr().err
    assert "resourceful.py:9:1: error: R.package_resources() failed: FileNotFoundError:" in err
    assert "Traceback" not in err
