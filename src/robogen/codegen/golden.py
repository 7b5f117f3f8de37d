"""Golden files of the generated sources: ``python -m robogen.codegen.golden`` (``make golden``).

For each case (the UR5e d-model in both semantics) the generator's output - modelDescription.xml,
the generated C (config.h, model.c, the unity file), buildDescription.xml and the documentation
with the IR dump - is written to ``tests/codegen/golden/<case>/``, replacing what was there.
Review the change with ``git diff`` before committing it; ``tests/codegen/test_golden.py`` fails
until the golden files and the generator agree. ``--check`` only compares (exit 1 on a
difference). Model paths are given relative to the repository root, so the files name
``models/ur5e/ur5e.rst`` whatever the checkout's location.
"""

from __future__ import annotations

import argparse
import contextlib
import sys
from pathlib import Path

from robogen.codegen.api import lower_paths
from robogen.codegen.generate import generate
from robogen.diagnostics import RobogenError
from robogen.ir.lower import LoweringOptions

#: case name -> (model files relative to the repository root, generation options)
CASES: dict[str, tuple[tuple[str, ...], LoweringOptions]] = {
    "ur5e-exhaustive": (("models/ur5e/ur5e.rst",), LoweringOptions(semantics="exhaustive")),
    "ur5e-stepwise": (("models/ur5e/ur5e.rst",), LoweringOptions(semantics="stepwise")),
}


def repository_root() -> Path:
    """The checkout this module belongs to (src/robogen/codegen/golden.py -> the root)."""
    return Path(__file__).resolve().parents[3]


def golden_dir(root: Path) -> Path:
    return root / "tests" / "codegen" / "golden"


def render(case: str, root: Path) -> dict[str, str]:
    """The generated files of ``case`` by relative path (the sources of the FMU, no binary)."""
    paths, options = CASES[case]
    with contextlib.chdir(root):
        fmu, _ = lower_paths(list(paths), options=options)
        return dict(generate(fmu).files)


def differences(root: Path) -> list[str]:
    """Golden files that differ from what the generator writes now (missing and extra ones too)."""
    out = []
    for case in CASES:
        folder = golden_dir(root) / case
        expected = render(case, root)
        present = {p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.is_file()} if folder.is_dir() else set()
        for rel in sorted(set(expected) | present):
            path = folder / rel
            if rel not in expected:
                out.append(f"{case}/{rel}: no longer generated")
            elif not path.is_file():
                out.append(f"{case}/{rel}: missing")
            elif path.read_text(encoding="utf-8") != expected[rel]:
                out.append(f"{case}/{rel}: differs")
    return out


def refresh(root: Path) -> list[Path]:
    """Rewrite every case's golden folder; returns the files written."""
    written = []
    for case in CASES:
        folder = golden_dir(root) / case
        files = render(case, root)
        if folder.is_dir():
            for path in sorted(folder.rglob("*"), reverse=True):
                if path.is_file() and path.relative_to(folder).as_posix() not in files:
                    path.unlink()
        for rel, text in files.items():
            path = folder / rel
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(text, encoding="utf-8")
            written.append(path)
    return written


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m robogen.codegen.golden", description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="compare only; exit 1 if a golden file differs")
    parser.add_argument("--root", type=Path, default=None, help="the repository root (default: this checkout)")
    args = parser.parse_args(argv)
    root = (args.root or repository_root()).resolve()
    if not (root / "models" / "ur5e" / "ur5e.rst").is_file():
        print(f"error: {root} is not a robogen checkout (models/ur5e/ur5e.rst is missing); use --root", file=sys.stderr)
        return 2
    try:
        if args.check:
            diff = differences(root)
            for line in diff:
                print(line)
            print(f"{len(diff)} golden file(s) out of date" if diff else "golden files up to date")
            return 1 if diff else 0
        written = refresh(root)
    except RobogenError as exc:
        print(exc, file=sys.stderr)
        return 1
    print(f"wrote {len(written)} golden files under {golden_dir(root).relative_to(root)}/; review them with git diff")
    return 0


if __name__ == "__main__":
    sys.exit(main())
