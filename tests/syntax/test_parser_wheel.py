"""robogen.syntax.parser loads its grammars as package data (robogen.grammar): a wheel built from
the sources, installed into a fresh virtual environment outside the source tree, parses and
checks a model with Lark as its only dependency, and its `robogen check` command works."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import lark
import pytest
from support.frontend import ROOT, VALID

SCRIPT = """
import json, sys
from importlib.resources import files
import robogen
from robogen.semantics import check_texts
model = check_texts({"pulse.rst": sys.stdin.read()})
print(json.dumps({
    "robogen": robogen.__file__,
    "grammar": sorted(p.name for p in files("robogen.grammar").iterdir() if p.name.endswith(".lark")),
    "diagnostics": [d.message for d in model.diagnostics],
    "machines": sorted(s.qname for s in model.scopes),
}))
"""


def run(*args, **kwargs) -> subprocess.CompletedProcess:
    result = subprocess.run([str(a) for a in args], capture_output=True, text=True, timeout=600, **kwargs)
    assert result.returncode == 0, result.stdout + result.stderr
    return result


def dependencies_folder(tmp_path: Path) -> Path:
    """Lark (and interegular, which Lark's strict mode uses) from this environment, without
    anything else of it: a folder of links that a .pth file puts on the new environment's path
    (so that the test needs no download and sees no other copy of robogen)."""
    folder = tmp_path / "deps"
    folder.mkdir()
    packages = [Path(lark.__file__).parent]
    try:
        import interegular

        packages.append(Path(interegular.__file__).parent)
    except ImportError:  # pragma: no cover - Lark works without it
        pass
    for package in packages:
        (folder / package.name).symlink_to(package, target_is_directory=True)
    return folder


@pytest.mark.slow
def test_the_installed_wheel_parses_and_checks_a_model_outside_the_source_tree(tmp_path):
    # build from a copy of the sources, so that the build writes nothing into the working tree
    source = tmp_path / "source"
    ignore = shutil.ignore_patterns("__pycache__", "*.pyc", "*.so", "*.egg-info")
    shutil.copytree(ROOT / "src", source / "src", ignore=ignore)
    shutil.copytree(ROOT / "grammar", source / "grammar", ignore=ignore)
    for name in ("pyproject.toml", "README.md"):
        shutil.copy2(ROOT / name, source / name)
    run(sys.executable, "-m", "pip", "wheel", source, "--no-deps", "--quiet", "--wheel-dir", tmp_path / "dist")
    (wheel,) = (tmp_path / "dist").glob("robogen-*.whl")
    with zipfile.ZipFile(wheel) as z:
        names = set(z.namelist())
    assert {"robogen/grammar/robochart.lark", "robogen/grammar/robosim.lark", "robogen/syntax/parser.py"} <= names
    # what code generation reads at run time ships too: the C runtime and the templates
    assert {"robogen/runtime/robogen_runtime.c", "robogen/runtime/robogen_runtime.h",
            "robogen/templates/model.c.j2", "robogen/templates/config.h.j2"} <= names

    env = tmp_path / "env"
    run(sys.executable, "-m", "venv", "--without-pip", env)
    python = env / "bin" / "python"
    run(sys.executable, "-m", "pip", "--python", python, "install", "--no-deps", "--no-index", "--quiet", wheel)
    purelib = run(python, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])").stdout.strip()
    (Path(purelib) / "robogen_test_deps.pth").write_text(str(dependencies_folder(tmp_path)) + "\n")

    clean = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV")}
    model = (VALID / "pulse.rst").read_text()
    out = json.loads(run(python, "-c", SCRIPT, input=model, cwd=tmp_path, env=clean).stdout)
    installed = Path(out["robogen"]).resolve()
    assert installed.is_relative_to(env.resolve()) and not installed.is_relative_to(ROOT.resolve())
    assert out["grammar"] == ["robochart.lark", "robosim.lark"]
    assert out["diagnostics"] == []
    assert out["machines"] == ["pulse::Pulse"]

    # The command line loads every subcommand, whose dependencies (jinja2, fmpy, numpy, ...)
    # this environment has: make them visible too (after the wheel's own robogen on the path)
    (Path(purelib) / "robogen_test_all_deps.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    (tmp_path / "bad.rct").write_text("stm S { initial i }\n")
    command = subprocess.run([env / "bin" / "robogen", "check", "bad.rct"], capture_output=True, text=True, cwd=tmp_path, env=clean)
    assert "Traceback" not in command.stderr, command.stderr
    assert command.returncode == 1
    assert command.stderr.splitlines()[0] == "bad.rct:1:17: error: initial node 'i' must have exactly one outgoing transition, not 0"

    # ... and it generates, compiles and validates an FMU with its own runtime and templates
    (tmp_path / "pulse.rst").write_text(model)
    package = subprocess.run([env / "bin" / "robogen", "package", "pulse.rst", "-o", "pulse.fmu"],
                             capture_output=True, text=True, cwd=tmp_path, env=clean)
    assert package.returncode == 0, package.stderr
    with zipfile.ZipFile(tmp_path / "pulse.fmu") as z:
        members = set(z.namelist())
    assert {"modelDescription.xml", "sources/robogen_runtime.c", "sources/model.c"} <= members
    assert any(m.startswith("binaries/x86_64-linux/") and m.endswith(".so") for m in members)
