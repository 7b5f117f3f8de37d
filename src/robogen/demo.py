"""`make demo`: the main job, run end to end from a fresh clone.

Today it checks the UR5e case-study models and draws their state machines into build/ur5e/.
"""

from __future__ import annotations

import sys
from pathlib import Path

from robogen.cli import main as robogen

ROOT = Path(__file__).resolve().parents[2]
MODELS = ROOT / "models" / "ur5e"
OUT = ROOT / "build" / "ur5e"


def run() -> int:
    OUT.mkdir(parents=True, exist_ok=True)
    steps = [
        ["check", str(MODELS)],
        ["graph", str(MODELS / "ur5e.rst"), "--format", "dot", "-o", str(OUT / "ur5e-rst.dot")],
        ["graph", str(MODELS / "ur5e.rst"), "--format", "mermaid", "-o", str(OUT / "ur5e-rst.mmd")],
        ["graph", str(MODELS / "ur5e.rct"), "--format", "dot", "-o", str(OUT / "ur5e-rct.dot")],
        ["graph", str(MODELS / "ur5e.rct"), "--format", "mermaid", "-o", str(OUT / "ur5e-rct.mmd")],
    ]
    for step in steps:
        print("$ robogen " + " ".join(_rel(a) for a in step), flush=True)
        code = robogen(step)
        if code:
            return code
    print(f"diagrams written to {_rel(str(OUT))}/")
    return 0


def _rel(arg: str) -> str:
    try:
        return str(Path(arg).resolve().relative_to(ROOT))
    except ValueError:
        return arg


if __name__ == "__main__":
    sys.exit(run())
