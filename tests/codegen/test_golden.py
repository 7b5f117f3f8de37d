"""Golden files of the UR5e model's generated sources (robogen.codegen.golden).

A change to the generator that alters the output fails here until the golden files are
refreshed with `make golden` (python -m robogen.codegen.golden) and the diff reviewed.
"""

from __future__ import annotations

from codegen_models import ROOT
from robogen.codegen import golden


def test_golden_files_match_the_generator():
    problems = golden.differences(ROOT)
    assert problems == [], "out of date: " + ", ".join(problems) + "; run `make golden` and review the diff"


def test_golden_cases_cover_both_semantics_of_the_ur5e_model():
    assert set(golden.CASES) == {"ur5e-exhaustive", "ur5e-stepwise"}
    files = golden.render("ur5e-stepwise", ROOT)
    assert {"modelDescription.xml", "sources/config.h", "sources/model.c", "sources/DiscreteGrippingArm.c",
            "sources/buildDescription.xml", "documentation/ir.txt"} <= set(files)
    assert "models/ur5e/ur5e.rst" in files["sources/model.c"]  # repository-relative paths
    assert str(ROOT) not in files["sources/model.c"]


def test_check_mode_reports_a_stale_file(tmp_path):
    root = tmp_path / "checkout"
    (root / "models" / "ur5e").mkdir(parents=True)
    (root / "models" / "ur5e" / "ur5e.rst").write_text((ROOT / "models" / "ur5e" / "ur5e.rst").read_text())
    assert golden.main(["--root", str(root)]) == 0
    assert golden.main(["--root", str(root), "--check"]) == 0
    stale = root / "tests" / "codegen" / "golden" / "ur5e-stepwise" / "sources" / "model.c"
    stale.write_text(stale.read_text() + "/* edited */\n")
    (stale.parent / "extra.c").write_text("")
    assert golden.differences(root) == ["ur5e-stepwise/sources/extra.c: no longer generated",
                                        "ur5e-stepwise/sources/model.c: differs"]
    assert golden.main(["--root", str(root), "--check"]) == 1
    assert golden.main(["--root", str(root)]) == 0 and golden.differences(root) == []
