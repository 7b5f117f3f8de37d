"""Bad `robogen package`, `compile` and `package-py` outputs, as users write them: an output never
destroys an input or a folder robogen did not write, and a failure leaves the previous output.

Each case builds its files in a fresh folder and runs the command there (support.cli_cases).
"""

from __future__ import annotations

import pytest
from support.cli_cases import Case, run_case

GOOD = "stm S {\n\tcycleDef cycle == 1\n\tvar x: nat\n\tinitial i\n\tstate A { }\n\ttransition t { from i to A action x = 1 }\n}\n"
BROKEN = "stm S {\n\tcycleDef cycle == 1\n\tinitial i\n\tstate A { entry y = 1 }\n\ttransition t { from i to A }\n}\n"
CONSTANTS = GOOD.replace("\tvar x: nat\n", "\tconst limit: nat = 3\n\tvar x: nat\n").replace("x = 1", "x = limit")
REFUSED = "is also an input of this command; refusing to overwrite it"

CASES = [
    Case("package output is its model", ["package", "m.rst", "-o", "m.rst"], 1, "err", f"error: -o m.rst {REFUSED}",
         files={"m.rst": GOOD}, unchanged=("m.rst",)),
    Case("package output is its model by another path", ["package", "m.rst", "-o", "sub/../m.rst"], 1, "err", REFUSED,
         files={"m.rst": GOOD, "sub/": ""}, unchanged=("m.rst",)),
    Case("package output is a model of a folder given", ["package", "models", "-o", "models/m.rst"], 1, "err", REFUSED,
         files={"models/m.rst": GOOD}, unchanged=("models/m.rst",)),
    Case("package output is the functions file", ["package", "m.rst", "--functions", "f.c", "-o", "f.c"], 1, "err",
         f"error: -o f.c {REFUSED}", files={"m.rst": GOOD, "f.c": "/* the user's functions */\n"}, unchanged=("f.c",)),
    Case("package output is a folder", ["package", "m.rst", "-o", "out"], 1, "err", "error: -o out is a folder; name a file",
         files={"m.rst": GOOD, "out/": ""}),
    Case("package output under a file", ["package", "m.rst", "-o", "m.rst/x.fmu"], 1, "err",
         "error: -o m.rst/x.fmu: m.rst is a file, not a folder", files={"m.rst": GOOD}, unchanged=("m.rst",)),
    Case("package of a broken model keeps the previous FMU", ["package", "b.rst", "-o", "b.fmu"], 1, "err",
         "b.rst:4:18: error: unknown name 'y'", files={"b.rst": BROKEN, "b.fmu": "the previous FMU"}, unchanged=("b.fmu",)),
    Case("package of sources into their own description", ["package", "src", "-o", "src/modelDescription.xml"], 1, "err",
         REFUSED, files={"src/modelDescription.xml": "<fmiModelDescription/>", "src/sources/buildDescription.xml": "<x/>"},
         unchanged=("src/modelDescription.xml",)),
    Case("compile into the folder of its model", ["compile", "m.rst", "-o", "."], 1, "err",
         "error: -o . holds the input m.rst; choose a separate output folder", files={"m.rst": GOOD}, unchanged=("m.rst",)),
    Case("compile into a user's folder", ["compile", "m.rst", "-o", "work"], 1, "err",
         "error: -o work is a folder robogen did not write and it is not empty", files={"m.rst": GOOD, "work/sources/notes.txt": "mine"},
         unchanged=("work/sources/notes.txt",)),
    Case("compile into a file", ["compile", "m.rst", "-o", "out.txt"], 1, "err", "error: -o out.txt is a file; name a folder",
         files={"m.rst": GOOD, "out.txt": "keep"}, unchanged=("out.txt",)),
    Case("compile output is its model", ["compile", "m.rst", "-o", "m.rst"], 1, "err", f"error: -o m.rst {REFUSED}",
         files={"m.rst": GOOD}, unchanged=("m.rst",)),
    Case("compile into a new folder", ["compile", "m.rst", "-o", "new/out"], 0, "err", "wrote new/out/", files={"m.rst": GOOD}),
    Case("compile into an empty folder", ["compile", "m.rst", "-o", "empty"], 0, "err", "wrote empty/",
         files={"m.rst": GOOD, "empty/": ""}),
    Case("--set of a constant the model does not have", ["package", "c.rst", "--set", "limt=4", "-o", "c.fmu"], 1, "err",
         "error: --set limt: the FMU has no constant named 'limt' (did you mean 'limit'?)", files={"c.rst": CONSTANTS}),
    Case("--set for a model without constants", ["package", "m.rst", "--set", "limit=4", "-o", "m.fmu"], 1, "err",
         "note: it has no constant a --set could give a value", files={"m.rst": GOOD}),
    Case("--set by the constant's FMI name", ["package", "c.rst", "--set", "S.limit=4", "-o", "c.fmu"], 0, "err",
         "wrote c.fmu (valid)", files={"c.rst": CONSTANTS}),
    Case("--functions for a model without functions", ["package", "m.rst", "--functions", "f.c", "-o", "m.fmu"], 0, "err",
         "warning: --functions f.c: the model calls no user function; the file is not used",
         files={"m.rst": GOOD, "f.c": "/* nothing the model calls */\n"}),
    Case("--capacity of no element", ["compile", "m.rst", "--capacity", "0", "-o", "out"], 1, "err",
         "error: --capacity 0: give a number between 1 and 1048576, or one per nesting level separated by commas (32,8,4)",
         files={"m.rst": GOOD}),
    Case("--capacity of a level that is no number", ["compile", "m.rst", "--capacity", "8,x", "-o", "out"], 1, "err",
         "error: --capacity 8,x: give a number", files={"m.rst": GOOD}),
    Case("--capacity per nesting level", ["compile", "m.rst", "--capacity", "32,8,4", "-o", "out"], 0, "err", "wrote out/",
         files={"m.rst": GOOD}),
    Case("package-py output is a folder", ["package-py", "robogen.platforms.controller:PlanController", "-o", "c.fmu"], 1, "err",
         "error: -o c.fmu is a folder; name a file", files={"c.fmu/": ""}),
]


@pytest.mark.parametrize("case", CASES, ids=[c.name for c in CASES])
def test_an_output_never_destroys_an_input(case: Case, tmp_path, monkeypatch, capsys):
    run_case(case, tmp_path, monkeypatch, capsys)


def test_compile_twice_into_its_own_folder_replaces_what_it_wrote_and_keeps_the_rest(tmp_path, monkeypatch, capsys):
    (tmp_path / "m.rst").write_text(GOOD, encoding="utf-8")
    again = Case("compile again", ["compile", "m.rst", "-o", "out"], 0, "err", "wrote out/")
    run_case(again, tmp_path, monkeypatch, capsys)
    (tmp_path / "out" / "notes.txt").write_text("mine", encoding="utf-8")
    stale = tmp_path / "out" / "sources" / "stale.c"
    stale.write_text("/* from an older compile */", encoding="utf-8")
    run_case(again, tmp_path, monkeypatch, capsys)
    assert (tmp_path / "out" / "notes.txt").read_text(encoding="utf-8") == "mine"
    assert not stale.exists()
    assert (tmp_path / "out" / "sources" / "model.c").is_file()
