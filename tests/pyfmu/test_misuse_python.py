"""FMI 3.0's call-order rules live twice in robogen: in the C runtime every generated FMU links
(robogen_runtime_modes.c and its siblings) and in the Python-FMU slave (robogen/pyfmu/slave.py).
One C importer, misuse_python.c on the shared misuse harness, runs the same cases against a
Python FMU packaged by ``robogen package-py`` and against the runtime's counter test FMU: every
misuse refused with a message saying why, every legal call next to them accepted — by both,
case by case. The roles the cases need (a periodic and a triggered input clock, an output clock,
clocked and unclocked variables, parameters) are found in each FMU's modelDescription.xml.
"""

from __future__ import annotations

import zipfile
from pathlib import Path

import pytest

from robogen.codegen import binary
from robogen.fmu.headers import PLATFORM_TUPLE
from robogen.fmu.modeldesc import ModelDescription, load_model_description
from support import ROOT
from support.harness import build_program, run, verdicts

HERE = Path(__file__).resolve().parent
RUNTIME_COUNTER = ROOT / "tests" / "runtime" / "models" / "counter"

# periodic clock, triggered input clock, its clocked Int64 input, output clock, its clocked
# output, an Int64 output, a fixed and a tunable Float64 parameter
PYTHON_ROLES = ("tick", "bump", "bump.amount", "ticked", "ticked.count", "total", "alarm_time", "speed")
RUNTIME_ROLES = ("cycle", "command", "command.value", "tick", "tick.value", "last_command", "early_at", "offset")


def role_arguments(md: ModelDescription, roles: tuple[str, ...]) -> list[str]:
    """The program's role arguments: value references, the clocked output's type, the interval."""
    by_name = md.by_name()
    vrs = [str(by_name[name].value_reference) for name in roles]
    return [*vrs[:5], by_name[roles[4]].type, *vrs[5:], by_name[roles[0]].interval_decimal]


@pytest.fixture(scope="module")
def program(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("misuse_python")
    return build_program([HERE / "misuse_python.c"], folder / "misuse_python", sanitize=False)


@pytest.fixture(scope="module")
def python_run(program, fmus, tmp_path_factory):
    folder = tmp_path_factory.mktemp("python_counter")
    with zipfile.ZipFile(fmus["counter"]) as z:
        z.extractall(folder)
    md = load_model_description(folder)
    library = folder / "binaries" / PLATFORM_TUPLE / f"{md.co_simulation.model_identifier}.so"
    return run(program, library, md.instantiation_token, folder / "resources", *role_arguments(md, PYTHON_ROLES),
               sanitize=False)


@pytest.fixture(scope="module")
def runtime_run(program, tmp_path_factory):
    folder = tmp_path_factory.mktemp("runtime_counter")
    md = load_model_description(RUNTIME_COUNTER)
    library = binary.compile_fmu_binary(RUNTIME_COUNTER, "counter", folder / "counter.so")
    return run(program, library, md.instantiation_token, folder, *role_arguments(md, RUNTIME_ROLES), sanitize=False)


def test_the_runtime_refuses_every_misuse(runtime_run):
    failed = [text for _, passed, text in verdicts(runtime_run).values() if not passed]
    assert failed == [] and runtime_run.returncode == 0, runtime_run.stderr[-2000:]


def test_the_python_slave_refuses_every_misuse(python_run):
    failed = [text for _, passed, text in verdicts(python_run).values() if not passed]
    assert failed == [] and python_run.returncode == 0, python_run.stderr[-2000:]


def test_both_give_the_same_verdict_case_by_case(runtime_run, python_run):
    runtime, python = verdicts(runtime_run), verdicts(python_run)
    assert runtime.keys() == python.keys()
    disagree = [f"{n}: runtime {runtime[n][2]!r} / python {python[n][2]!r}" for n in runtime
                if runtime[n][:2] != python[n][:2]]
    assert disagree == []
    misuse = [n for n, (kind, _, _) in runtime.items() if kind == "misuse"]
    assert len(misuse) >= 45 and len(runtime) - len(misuse) >= 15
