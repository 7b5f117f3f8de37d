"""Bad `robogen check` and `robogen graph` command lines, as users write them: each gives its exit
code and a message that says what is wrong, never a Python traceback or an "internal error".

Each case builds its files in a fresh folder, runs the command there (through robogen.cli.main,
as the `robogen` script does), and states the exit code, the stream and a part of the message.
"""

from __future__ import annotations

import os
import random
from pathlib import Path

import pytest
from support.cli_cases import Case, run_case

GOOD = "stm S {\n\tvar x: nat\n\tinitial i\n\tstate A { }\n\ttransition t { from i to A action x = 1 }\n}\n"
BROKEN = "stm S {\n\tinitial i\n\tstate A { entry y = 1 }\n\ttransition t { from i to A }\n}\n"


def nested_calls(depth: int) -> str:
    return GOOD.replace("x = 1", "x = " + "f(" * depth + "1" + ")" * depth)


def flat_sum(terms: int) -> str:
    return GOOD.replace("x = 1", "x = " + " + ".join(f"x * {i}" for i in range(terms)))


def chain(states: int) -> str:
    body = [f"\tstate S{j} {{ }}\n\ttransition t{j} {{ from S{j} to S{(j + 1) % states} exec }}" for j in range(states)]
    return "stm Chain {\n\tcycleDef cycle == 1\n\tinitial i\n\ttransition t { from i to S0 }\n" + "\n".join(body) + "\n}\n"


def junk(size: int) -> bytes:
    rng = random.Random(size)
    return bytes(rng.randrange(256) for _ in range(size))


def _fifo(folder: Path) -> None:
    os.mkfifo(folder / "pipe.rct")


def _device(folder: Path) -> None:
    (folder / "memory.rct").symlink_to("/proc/self/mem")  # a regular file that no one can read from 0


def _dangling(folder: Path) -> None:
    (folder / "gone.rct").symlink_to(folder / "nowhere.rct")


CASES = [
    # ---- paths that are not models
    Case("missing file", ["check", "missing.rct"], 1, "err", "error: no such file or directory: missing.rct"),
    Case("dangling link", ["check", "gone.rct"], 1, "err", "error: no such file or directory: gone.rct", setup=_dangling),
    Case("folder without models", ["check", "empty"], 1, "err",
         "empty: error: no model files (.rct, .rst, .rsim) in directory empty", files={"empty/notes.txt": "hello"}),
    Case("not a model file", ["check", "notes.txt"], 1, "err", "error: not a model file: notes.txt", files={"notes.txt": GOOD}),
    Case("a named pipe", ["check", "pipe.rct"], 1, "err", "error: pipe.rct is neither a file nor a directory", setup=_fifo),
    Case("unreadable file", ["check", "memory.rct"], 1, "err", "error: cannot read memory.rct: Input/output error", setup=_device),
    Case("a model name that is a folder", ["check", "dir.rct"], 0, "out", "checked 1 file: 0 errors, 0 warnings",
         files={"dir.rct/inner.rct": GOOD}),
    Case("a path under a file", ["check", "m.rct/x.rct"], 1, "err", "error: no such file or directory: m.rct/x.rct", files={"m.rct": GOOD}),
    Case("one file by two paths", ["check", "m.rct", "./m.rct", "."], 0, "out", "checked 1 file: 0 errors, 0 warnings", files={"m.rct": GOOD}),
    # ---- content that is not model text
    Case("binary file", ["check", "junk.rct"], 1, "err", "junk.rct:1:1: error: not valid UTF-8 text (byte 0xff at offset 0)",
         files={"junk.rct": b"\xff" + junk(500)}),
    Case("NUL bytes", ["check", "nul.rst"], 1, "err", "nul.rst:2:3: error: file contains NUL bytes",
         files={"nul.rst": b"stm S {\n  \x00 }"}),
    Case("invalid UTF-8", ["check", "latin1.rct"], 1, "err", "latin1.rct:1:15: error: not valid UTF-8 text (byte 0xe9 at offset 14)",
         files={"latin1.rct": "stm S { // café\n}".encode("latin-1")}),
    Case("empty file", ["check", "--werror", "empty.rct"], 1, "err", "empty.rct:1:1: warning: the file is empty: it declares nothing",
         files={"empty.rct": ""}),
    Case("unterminated comment", ["check", "c.rct"], 1, "err", "c.rct:1:9: error: unterminated comment", files={"c.rct": "stm S { /* no end"}),
    # ---- sizes
    Case("nesting too deep", ["check", "deep.rct"], 1, "err", "error: nested too deeply: robogen accepts at most 100 levels",
         files={"deep.rct": nested_calls(150)}),
    Case("flat sum of 5,000 terms", ["check", "flat.rct"], 0, "out", "checked 1 file: 0 errors, 0 warnings",
         files={"flat.rct": flat_sum(5000)}),
    Case("graph of a flat sum of 5,000 terms", ["graph", "flat.rct", "-o", "flat.dot"], 0, "out", "",
         files={"flat.rct": flat_sum(5000)}),
    Case("10,000 states in a row", ["check", "chain.rst"], 0, "out", "checked 1 file: 0 errors, 0 warnings",
         files={"chain.rst": chain(10_000)}),
    # ---- outputs that would destroy inputs
    Case("graph output is its input", ["graph", "m.rct", "-o", "m.rct"], 1, "err",
         "error: -o m.rct is also an input of this command; refusing to overwrite it", files={"m.rct": GOOD}, unchanged=("m.rct",)),
    Case("graph output is an input by another path", ["graph", "m.rct", "-o", "./sub/../m.rct"], 1, "err",
         "is also an input of this command", files={"m.rct": GOOD, "sub/": ""}, unchanged=("m.rct",)),
    Case("graph output is a model of a folder given", ["graph", "models", "-o", "models/b.rct"], 1, "err",
         "error: -o models/b.rct is also an input of this command", files={"models/a.rct": GOOD, "models/b.rct": GOOD.replace("S", "T")},
         unchanged=("models/b.rct",)),
    Case("graph output is a folder", ["graph", "m.rct", "-o", "out"], 1, "err", "error: -o out is a folder; name a file",
         files={"m.rct": GOOD, "out/": ""}),
    Case("graph output under a file", ["graph", "m.rct", "-o", "m.rct/x.dot"], 1, "err", "error: -o m.rct/x.dot: m.rct is a file, not a folder",
         files={"m.rct": GOOD}, unchanged=("m.rct",)),
    Case("graph of a broken model keeps the old output", ["graph", "b.rct", "-o", "b.dot"], 1, "err",
         "b.rct:3:18: error: unknown name 'y'", files={"b.rct": BROKEN, "b.dot": "the previous diagram"}, unchanged=("b.dot",)),
    # ---- usage
    Case("graph of an unknown machine", ["graph", "m.rct", "--machine", "Sensr"], 2, "err",
         "robogen graph: no state machine 'Sensr' (did you mean 'Sensor'?)", files={"m.rct": GOOD.replace("stm S", "stm Sensor")}),
    Case("graph of models without a machine", ["graph", "i.rct"], 1, "err", "error: the models contain no state machine",
         files={"i.rct": "interface I { event e }\n"}),
    Case("check without paths", ["check"], 2, "err", "the following arguments are required: PATH"),
    Case("unknown option", ["check", "--fast", "m.rct"], 2, "err", "unrecognized arguments: --fast", files={"m.rct": GOOD}),
]


@pytest.mark.parametrize("case", CASES, ids=[c.name for c in CASES])
def test_a_bad_command_line_gets_an_exit_code_and_a_message(case: Case, tmp_path, monkeypatch, capsys):
    run_case(case, tmp_path, monkeypatch, capsys)


def test_the_table_covers_check_and_graph():
    assert len(CASES) >= 15
    assert {c.argv[0] for c in CASES if c.argv} == {"check", "graph"}
