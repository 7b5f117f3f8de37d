"""Every command the README shows, run as a newcomer copies it, in the order it shows them.

The README is read, not copied into this file, so it cannot drift from what robogen does:

- an indented block's lines are shell commands (a ``\\`` joins the next line); in a block whose
  lines start with ``$ ``, the lines after a command up to the next ``$ `` are its expected
  output, compared exactly (standard error, then standard output);
- the fenced ``toml`` block is the system-file example: saved where the README says and simulated;
- the fenced ``python`` block is run as it is, after the commands have built what it loads.

They run in a sandbox that looks like a fresh checkout after ``make test``: the repository's files
linked into a temporary folder, with its own ``build/``, the repository's ``.venv`` and
``../shared`` when it exists, so nothing is written into the working tree. ``make test`` itself
is the one command not run here: it is this suite.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

from support import ROOT, SHARED

README = ROOT / "README.md"
NOT_RUN_HERE = {"make test": "the suite itself (CI runs it)"}
LINKED = ("Makefile", "pyproject.toml", ".venv", "src", "grammar", "docs")
# real folders of linked files: the README saves a file there, or a file there names one in build/
MIRRORED = ("models", "examples")


@dataclass
class Command:
    line: int  # in README.md
    text: str
    expected: list[str] | None = None  # the output the README shows, if it shows one


def indented_blocks(text: str) -> list[tuple[int, list[str]]]:
    """(first line number, lines without their indentation) of each indented code block outside
    fenced blocks."""
    blocks: list[tuple[int, list[str]]] = []
    fenced = False
    current: list[str] = []
    start = 0
    lines = text.splitlines()
    for number, line in enumerate(lines + [""], start=1):
        if line.startswith("```"):
            fenced = not fenced
        if not fenced and line.startswith("    ") and line.strip():
            if not current:
                start = number
            current.append(line[4:])
            continue
        if current:
            blocks.append((start, current))
            current = []
    return blocks


def commands(text: str) -> list[Command]:
    found: list[Command] = []
    for start, lines in indented_blocks(text):
        transcript = lines[0].startswith("$ ")
        pending = ""
        for offset, line in enumerate(lines):
            if transcript and not line.startswith("$ "):
                found[-1].expected.append(line)
                continue
            body = line[2:] if transcript else line
            if body.endswith("\\"):
                pending += body[:-1]
                continue
            found.append(Command(start + offset, pending + body, [] if transcript else None))
            pending = ""
    return found


def fenced_block(text: str, language: str) -> str:
    match = re.search(rf"^```{language}\n(.*?)^```", text, flags=re.M | re.S)
    assert match, f"the README has no {language} block"
    return match.group(1)


@pytest.fixture(scope="module")
def sandbox(tmp_path_factory) -> Path:
    top = tmp_path_factory.mktemp("newcomer")
    repo = top / "robogen"
    repo.mkdir()
    for name in LINKED:
        if (ROOT / name).exists():
            (repo / name).symlink_to(ROOT / name)
    for name in MIRRORED:
        for path in (ROOT / name).rglob("*"):
            if path.is_file() and "__pycache__" not in path.parts:
                (repo / path.relative_to(ROOT)).parent.mkdir(parents=True, exist_ok=True)
                (repo / path.relative_to(ROOT)).symlink_to(path)
    if SHARED.is_dir():
        (top / "shared").symlink_to(SHARED)
    (repo / "build").mkdir()
    return repo


def run(command: str, cwd: Path) -> subprocess.CompletedProcess:
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}")
    env.pop("PYTHONPATH", None)
    return subprocess.run(["bash", "-c", command], cwd=cwd, env=env, capture_output=True, text=True, timeout=600)


def test_the_readme_starts_with_the_two_commands():
    first = commands(README.read_text(encoding="utf-8"))[:2]
    assert [c.text.split("#")[0].strip() for c in first] == ["make demo", "make test"]


def test_every_readme_command_runs_as_shown(sandbox):
    text = README.read_text(encoding="utf-8")
    ran = []
    for command in commands(text):
        name = command.text.split("#")[0].strip()
        if name in NOT_RUN_HERE:
            continue
        if "../shared/" in command.text and not SHARED.is_dir():
            continue  # the reference models are not beside this checkout
        done = run(command.text, sandbox)
        where = f"README.md:{command.line}: {command.text}"
        if command.expected is None or not any("error" in line for line in command.expected):
            assert done.returncode == 0, f"{where}\nexit {done.returncode}\n{done.stderr[-3000:]}"
        assert "Traceback" not in done.stderr and "internal error" not in done.stderr, where
        if command.expected is not None:
            assert (done.stderr + done.stdout).splitlines() == command.expected, where
        ran.append(name)
    assert "make demo" in ran and any(c.startswith("robogen simulate") for c in ran)


def test_the_system_file_example_runs(sandbox):
    """The example is saved where the README says (after the demo built its FMUs)."""
    if not (sandbox / "build" / "ur5e" / "dmodel.fmu").is_file():
        assert run("make demo", sandbox).returncode == 0
    (sandbox / "models" / "ur5e" / "example.toml").write_text(fenced_block(README.read_text(encoding="utf-8"), "toml"))
    done = run("robogen simulate models/ur5e/example.toml -o build/example.csv", sandbox)
    assert done.returncode == 0, done.stderr
    header = (sandbox / "build" / "example.csv").read_text().splitlines()[0].split(",")
    assert "platform.q0" in header and any(h.startswith("dmodel.") for h in header)


def test_the_fmpy_example_runs(sandbox):
    if not (sandbox / "build" / "dmodel.fmu").is_file():
        assert run("robogen package models/ur5e/ur5e.rst --time-unit 0.5 -o build/dmodel.fmu", sandbox).returncode == 0
    done = subprocess.run([sys.executable, "-c", fenced_block(README.read_text(encoding="utf-8"), "python")],
                          cwd=sandbox, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines()[0] == "[True]"  # the cycle called movediscrete
