"""Golden files of the generated sources: ``python tests/codegen/golden_files.py`` (``make golden``).

For each case (every code-generation fixture model: the UR5e d-model in both semantics, its
RoboChart model, and each model of tests/codegen/models/) the generator's output -
modelDescription.xml, the generated C (config.h, model.c, the unity file), buildDescription.xml
and the documentation with the IR dump - is written to ``tests/codegen/golden/<case>/``,
replacing what was there. Review the change with ``git diff`` before committing it;
``tests/codegen/test_golden.py`` fails until the golden files and the generator agree.
``--check`` only compares (exit 1 on a difference).

Generated files name model files relative to the workspace root (the folder of the model given),
so no change of directory is needed and the files are the same in any checkout.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass, field
from pathlib import Path

if __name__ == "__main__":  # run as a script: the tests' support package, as pytest's pythonpath gives it
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from robogen.codegen.api import diagrams_of, front_end  # noqa: E402
from robogen.codegen.generate import CodegenOptions, generate
from robogen.diagnostics import RobogenError
from robogen.ir.lower import LoweringOptions, lower
from support.codegen_models import ROOT as REPOSITORY  # noqa: E402
from support.codegen_models import TEST_MODELS  # noqa: E402


@dataclass(frozen=True)
class Case:
    model: str  # relative to the repository root
    semantics: str = "exhaustive"
    settings: dict[str, str] = field(default_factory=dict)
    functions: str | None = None  # the C file of the model's user functions, relative to the root
    capacities: tuple[int, ...] = ()  # of collections, per nesting level (default: 32 at every level)
    time: str = "skip"  # RoboChart time (--time)


def _fixture(name: str, semantics: str = "exhaustive") -> Case:
    m = TEST_MODELS[name]
    return Case(m.path.relative_to(REPOSITORY).as_posix(), semantics, dict(m.settings), capacities=m.capacities)


#: case name -> what it compiles
CASES: dict[str, Case] = {
    "ur5e-exhaustive": _fixture("ur5e"),
    "ur5e-stepwise": _fixture("ur5e", "stepwise"),
    "ur5e-robochart": _fixture("ur5e_rct"),
    **{name: _fixture(name) for name in sorted(TEST_MODELS) if name not in ("ur5e", "ur5e_rct")},
    "userfun": Case("tests/codegen/models/userfun.rst", functions="tests/codegen/models/userfun.c"),
    "declared": Case("tests/codegen/models/declared.rct", functions="tests/codegen/models/declared.c"),
    "recursive": Case("tests/codegen/models/recursive.rct"),
    "mixed": Case("tests/codegen/models/mixed.rct"),
    "timers-tick": Case("tests/codegen/models/timers.rct", time="tick"),
}


def golden_dir(root: Path) -> Path:
    return root / "tests" / "codegen" / "golden"


def render(case: str, root: Path) -> dict[str, str]:
    """The generated files of ``case`` by relative path (the sources of the FMU, no binary)."""
    c = CASES[case]
    model, boundary = front_end([root / c.model])
    options = LoweringOptions(semantics=c.semantics, settings=dict(c.settings), time=c.time)
    if c.capacities:
        options.capacity, options.capacities = c.capacities[0], c.capacities
    fmu = lower(model, boundary, options)
    codegen = CodegenOptions(functions=root / c.functions if c.functions else None)
    return dict(generate(fmu, codegen, diagrams=diagrams_of(boundary)).files)


def differences(root: Path, cases: list[str] | None = None) -> list[str]:
    """Golden files that differ from what the generator writes now (missing and extra ones too)."""
    out = []
    for case in cases or list(CASES):
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


def refresh(root: Path, cases: list[str] | None = None) -> list[Path]:
    """Rewrite each case's golden folder; returns the files written."""
    written = []
    for case in cases or list(CASES):
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
    parser = argparse.ArgumentParser(prog="python tests/codegen/golden_files.py", description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="compare only; exit 1 if a golden file differs")
    parser.add_argument("--root", type=Path, default=REPOSITORY, help="the repository root (default: this checkout)")
    parser.add_argument("--case", action="append", choices=sorted(CASES), help="only this case (repeatable)")
    args = parser.parse_args(argv)
    root = args.root.resolve()
    try:
        if args.check:
            diff = differences(root, args.case)
            for line in diff:
                print(line)
            print(f"{len(diff)} golden file(s) out of date" if diff else "golden files up to date")
            return 1 if diff else 0
        written = refresh(root, args.case)
    except RobogenError as exc:
        print(exc, file=sys.stderr)
        return 1
    print(f"wrote {len(written)} golden files under {golden_dir(root).relative_to(root)}/; review them with git diff")
    return 0


if __name__ == "__main__":
    sys.exit(main())
