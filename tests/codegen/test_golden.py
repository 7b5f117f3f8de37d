"""Golden files of the generated sources (tests/codegen/golden_files.py), one folder per
code-generation fixture model.

A change to the generator that alters the output fails here until the golden files are
refreshed with `make golden` (python tests/codegen/golden_files.py) and the diff reviewed.
"""

from __future__ import annotations

import golden_files
from support.codegen_models import MODELS, ROOT, TEST_MODELS


def test_golden_files_match_the_generator():
    problems = golden_files.differences(ROOT)
    assert problems == [], "out of date: " + ", ".join(problems) + "; run `make golden` and review the diff"


def test_every_fixture_model_has_a_golden_folder():
    compiled = {golden_files.CASES[c].model for c in golden_files.CASES}
    fixtures = {m.path.relative_to(ROOT).as_posix() for m in TEST_MODELS.values()}
    fixtures |= {p.relative_to(ROOT).as_posix() for p in MODELS.iterdir() if p.suffix in (".rst", ".rct")}
    assert fixtures <= compiled
    assert {"ur5e-exhaustive", "ur5e-stepwise"} <= set(golden_files.CASES)
    assert {c.name for c in golden_files.golden_dir(ROOT).iterdir()} == set(golden_files.CASES)


def test_golden_files_name_models_relative_to_the_workspace_root():
    files = golden_files.render("ur5e-stepwise", ROOT)
    assert {"modelDescription.xml", "sources/config.h", "sources/model.c", "sources/DiscreteGrippingArm.c",
            "sources/buildDescription.xml", "documentation/ir.txt"} <= set(files)
    assert "from ur5e.rst (robosim" in files["sources/model.c"]  # the model's folder is the root
    assert all(str(ROOT) not in text and "models/ur5e" not in text for text in files.values())
    assert ".rst" not in files["documentation/ir.txt"]  # the dump (and the token hashed from it) is path-free


def test_check_mode_reports_a_stale_file(tmp_path):
    root = tmp_path / "checkout"
    (root / "models" / "ur5e").mkdir(parents=True)
    (root / "models" / "ur5e" / "ur5e.rst").write_text((ROOT / "models" / "ur5e" / "ur5e.rst").read_text())
    case = ["--root", str(root), "--case", "ur5e-stepwise"]
    assert golden_files.main(case) == 0
    assert golden_files.main(case + ["--check"]) == 0
    stale = root / "tests" / "codegen" / "golden" / "ur5e-stepwise" / "sources" / "model.c"
    stale.write_text(stale.read_text() + "/* edited */\n")
    (stale.parent / "extra.c").write_text("")
    assert golden_files.differences(root, ["ur5e-stepwise"]) == ["ur5e-stepwise/sources/extra.c: no longer generated",
                                                                 "ur5e-stepwise/sources/model.c: differs"]
    assert golden_files.main(case + ["--check"]) == 1
    assert golden_files.main(case) == 0 and golden_files.differences(root, ["ur5e-stepwise"]) == []
