"""The house limits on code size under src/: no module over 800 lines, no function over 80 (Python and C).

A module or function past them does several things; split it along its seams. The C scan reads
hand-written C (the runtime, the Python-FMU shim, the master's engine), where a function starts
with its signature at column 0 and ends at the first ``}`` at column 0.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

from support import ROOT

SRC = ROOT / "src" / "robogen"
MAX_MODULE_LINES = 800
MAX_FUNCTION_LINES = 80


def _python_files() -> list[Path]:
    return sorted(SRC.rglob("*.py"))


def _c_files() -> list[Path]:
    return sorted(p for p in SRC.rglob("*.c"))


def long_python_functions(path: Path) -> list[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    return [f"{path.name}:{node.lineno} {node.name} ({node.end_lineno - node.lineno + 1} lines)"
            for node in ast.walk(tree)
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef))
            and node.end_lineno - node.lineno + 1 > MAX_FUNCTION_LINES]


_C_SIGNATURE = re.compile(r"^[A-Za-z_][\w \*]*\b(\w+)\s*\(")


def long_c_functions(path: Path) -> list[str]:
    lines = path.read_text(encoding="utf-8").splitlines()
    found, start, name = [], None, ""
    for i, line in enumerate(lines):
        match = _C_SIGNATURE.match(line)
        if start is None and match and not line.rstrip().endswith(";") and not line.startswith(("typedef", "#")):
            start, name = i, match.group(1)
        elif start is not None and line.startswith("}"):
            if i - start + 1 > MAX_FUNCTION_LINES:
                found.append(f"{path.name}:{start + 1} {name} ({i - start + 1} lines)")
            start = None
    return found


def test_no_module_is_over_800_lines():
    big = [f"{p.relative_to(ROOT)} ({n} lines)" for p in _python_files() + _c_files()
           if (n := p.read_text(encoding="utf-8").count("\n")) > MAX_MODULE_LINES]
    assert big == []


def test_no_python_function_is_over_80_lines():
    assert [f for p in _python_files() for f in long_python_functions(p)] == []


def test_no_c_function_is_over_80_lines():
    assert [f for p in _c_files() for f in long_c_functions(p)] == []


def test_the_scans_see_what_they_look_for(tmp_path):
    body = "\n".join(f"    x += {i};" for i in range(85))
    c_file = tmp_path / "long.c"
    c_file.write_text(f"static int long_one(int x)\n{{\n{body}\n    return x;\n}}\n\nint short_one(void) {{ return 0; }}\n")
    py_file = tmp_path / "long.py"
    py_file.write_text("def long_one(x):\n" + "\n".join(f"    x += {i}" for i in range(85)) + "\n    return x\n\n\ndef short_one():\n    return 0\n")
    assert long_c_functions(c_file) == ["long.c:1 long_one (89 lines)"]
    assert long_python_functions(py_file) == ["long.py:1 long_one (87 lines)"]
