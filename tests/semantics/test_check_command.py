"""`robogen check` and `robogen graph` (robogen.semantics.cli and robogen.semantics.graph) as a
user runs them: in a subprocess, with exit codes, rendered diagnostics, and never a Python
traceback, whatever the input."""

from __future__ import annotations

import random
import subprocess
import sys
from pathlib import Path

import pytest
from support.frontend import VALID

from robogen.cli import main


def robogen(*args: str | Path, cwd: Path | None = None) -> subprocess.CompletedProcess:
    result = subprocess.run(
        [sys.executable, "-m", "robogen", *map(str, args)], capture_output=True, text=True, cwd=cwd, timeout=120
    )
    assert "Traceback" not in result.stderr and "internal error" not in result.stderr, result.stderr
    return result


def test_a_valid_model_checks_with_exit_code_0():
    result = robogen("check", VALID / "pulse.rst")
    assert (result.returncode, result.stdout, result.stderr) == (0, "checked 1 file: 0 errors, 0 warnings\n", "")


def test_errors_are_rendered_like_a_compiler_and_exit_with_1(tmp_path):
    (tmp_path / "bad.rct").write_text("stm S {\n\tvar x: nat\n\tinitial i\n\tstate A { entry x = true }\n\ttransition t { from i to A }\n}\n")
    result = robogen("check", "bad.rct", cwd=tmp_path)
    assert result.returncode == 1
    assert result.stderr == (
        "bad.rct:4:22: error: cannot assign boolean to 'x' of type nat\n"
        "    4 |     state A { entry x = true }\n"
        "      |                         ^~~~\n"
    )
    assert result.stdout == "checked 1 file: 1 error, 0 warnings\n"


def test_warnings_exit_with_0_unless_treated_as_errors(tmp_path):
    (tmp_path / "w.rct").write_text("stm S { initial i state A { } state B { } transition t { from i to A } }\n")
    result = robogen("check", "w.rct", cwd=tmp_path)
    assert result.returncode == 0
    assert result.stderr.splitlines()[0] == "w.rct:1:37: warning: state 'B' is unreachable: no path from the initial node enters it"
    assert result.stdout == "checked 1 file: 0 errors, 1 warning\n"
    assert robogen("check", "--werror", "w.rct", cwd=tmp_path).returncode == 1
    quiet = robogen("check", "-w", "w.rct", cwd=tmp_path)
    assert (quiet.returncode, quiet.stdout, quiet.stderr) == (0, "checked 1 file: 0 errors, 1 warning\n", "")


def _junk(seed: int, size: int) -> bytes:
    rng = random.Random(seed)
    return bytes(rng.randrange(256) for _ in range(size))


BAD_INPUTS = [
    # name, content, exit code, first line of stderr
    ("junk.rct", b"\xff" + _junk(1, 400), 1, "junk.rct:1:1: error: not valid UTF-8 text (byte 0xff at offset 0); models must be UTF-8"),
    # 0xc3 opens a two-byte sequence that 0x28 cannot continue
    ("junk2.rct", b"ab\n  c\xc3\x28" + _junk(2, 400), 1, "junk2.rct:2:4: error: not valid UTF-8 text (byte 0xc3 at offset 6); models must be UTF-8"),
    ("latin1.rst", "stm S { // café\n}".encode("latin-1"), 1, "latin1.rst:1:15: error: not valid UTF-8 text (byte 0xe9 at offset 14); models must be UTF-8"),
    ("nul.rct", b"stm S {\n  \x00\x01\x02 }", 1, "nul.rct:2:3: error: file contains NUL bytes; is it a binary file, not a model?"),
    ("control.rct", b"stm S { \x1b[31m }", 1, "control.rct:1:9: error: unexpected character U+001B"),
    ("empty.rct", b"", 0, "empty.rct:1:1: warning: the file is empty: it declares nothing"),
    ("text.rst", "intérêt ≠ modèle".encode(), 1, "text.rst:1:1: error: unexpected name 'int'; expected one of 'controller', 'datatype', "
     "'diagram', 'enumeration', 'function', 'import', 'interface', 'module', ... (7 more)"),
    ("deep.rct", ("stm S { var x: nat = " + "(" * 101 + "1" + ")" * 101 + " + 1" * 5000 + " }").encode(), 1,
     "deep.rct:1:22: error: nested too deeply: robogen accepts at most 100 levels of nested expressions, statements, types or states"),
]  # fmt: skip


@pytest.mark.parametrize("name, content, code, first", BAD_INPUTS, ids=[b[0] for b in BAD_INPUTS])
def test_bad_files_are_located_diagnostics_never_tracebacks(tmp_path, name, content, code, first):
    (tmp_path / name).write_bytes(content)
    result = robogen("check", name, cwd=tmp_path)
    assert result.returncode == code
    assert result.stderr.splitlines()[0] == first
    # what the terminal shows has no control characters besides the newlines
    assert not any(ord(ch) < 32 and ch != "\n" for ch in result.stderr)


def test_paths_that_are_not_models(tmp_path):
    (tmp_path / "empty-folder").mkdir()
    (tmp_path / "notes.txt").write_text("hello")
    result = robogen("check", "missing.rct", "empty-folder", "notes.txt", cwd=tmp_path)
    assert result.returncode == 1
    assert result.stderr == (
        "error: no such file or directory: missing.rct\n"
        "empty-folder: error: no model files (.rct, .rst, .rsim) in directory empty-folder\n"
        "error: not a model file: notes.txt (expected a .rct (RoboChart), .rst or .rsim (RoboSim) file)\n"
    )
    assert result.stdout == "checked 0 files: 3 errors, 0 warnings\n"


def test_usage_errors_exit_with_2():
    result = robogen("check")
    assert result.returncode == 2 and "the following arguments are required: PATH" in result.stderr
    result = robogen("graph", VALID / "pulse.rst", "--format", "svg")
    assert result.returncode == 2 and "invalid choice: 'svg'" in result.stderr


def test_a_folder_is_one_workspace():
    result = robogen("check", VALID / "geometry")
    assert (result.returncode, result.stdout, result.stderr) == (0, "checked 3 files: 0 errors, 0 warnings\n", "")


# ---------------------------------------------------------------------------- robogen graph


def test_graph_draws_a_machine_as_dot(tmp_path):
    out = tmp_path / "diagrams" / "pulse.dot"
    assert main(["graph", str(VALID / "pulse.rst"), "-o", str(out)]) == 0
    dot = out.read_text()
    assert dot.startswith('digraph "pulse::Pulse" {')
    assert '"Run" [label="Run\\nentry / k = k + 1 ; $tick!k"];' in dot
    assert '"Idle" -> "Idle" [label="exec [not $go]", style=dashed];' in dot
    assert '"Idle" -> "Run" [label="[$go]"];' in dot


def _mermaid_ids(text: str) -> dict[str, str]:
    """label -> id, from the `state "Label" as sN` lines and the junction notes."""
    import re

    ids = {label: ident for label, ident in re.findall(r'state "([^"]+)" as (s\d+)', text)}
    ids.update({label: ident for ident, label in re.findall(r"note right of (s\d+) : (\S+)", text)})
    return ids


def test_graph_draws_composite_states_in_mermaid(capsys):
    assert main(["graph", str(VALID / "nodes.rct"), "--format", "mermaid", "--machine", "Machine"]) == 0
    text = capsys.readouterr().out
    assert text.startswith("stateDiagram-v2\n  %% state machine nodes::Machine\n")
    ids = _mermaid_ids(text)
    running, working = ids["Running"], ids["Working"]
    assert f"  state {running} {{\n" in text  # a composite state is a nested block
    assert f"    state {working} {{\n" in text  # nested one level deeper
    assert f"  [*] --> {ids['Idle']}\n" in text
    assert f"  {ids['coin']} --> {ids['Retry']} : p = 0.75\n" in text


def test_mermaid_ids_never_merge_states_that_differ_in_nesting(tmp_path, capsys):
    # a top-level state A_B and a state B inside A: one diagram node each
    (tmp_path / "m.rct").write_text(
        "stm M { initial i state A { initial j state B { } transition u { from j to B } } state A_B { }"
        " transition t { from i to A } transition v { from A to A_B } }"
    )
    assert main(["graph", str(tmp_path / "m.rct"), "--format", "mermaid"]) == 0
    ids = _mermaid_ids(capsys.readouterr().out)
    assert len({ids["A"], ids["B"], ids["A_B"]}) == 3


def test_graph_of_an_unknown_machine_or_a_broken_model(tmp_path, capsys):
    assert main(["graph", str(VALID / "pulse.rst"), "--machine", "Pulsar"]) == 2
    assert capsys.readouterr().err == "robogen graph: no state machine 'Pulsar' (did you mean 'Pulse'?)\n"
    (tmp_path / "bad.rct").write_text("stm S { initial i }")
    assert main(["graph", str(tmp_path / "bad.rct")]) == 1
    assert "initial node 'i' must have exactly one outgoing transition, not 0" in capsys.readouterr().err
