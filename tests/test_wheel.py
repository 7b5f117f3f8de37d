"""What ships is the tool: the wheel holds the robogen package and nothing that only makes sense
inside this repository — no case study or demo, no golden-file refresher, no path that climbs
from a module to the checkout's root, no reference to the repository's models/ or tests/."""

from __future__ import annotations

import ast
import zipfile

import pytest

from support.wheel import build_wheel

REPOSITORY_FOLDERS = ("models", "tests", "examples")

# The golden-file refresher moves from src/ to tests/ with the code-generation part of the same
# redesign (issue 9); while it is still in src/ it is the one module known to break these rules.
@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> dict[str, bytes]:
    """Archive name -> content of every file of the wheel."""
    with zipfile.ZipFile(build_wheel(tmp_path_factory.mktemp("wheel"))) as z:
        return {name: z.read(name) for name in z.namelist() if not name.endswith("/")}


def python_modules(wheel: dict[str, bytes]) -> dict[str, ast.Module]:
    return {name: ast.parse(data, name) for name, data in wheel.items() if name.endswith(".py")}


def climbs_out_of_the_package(name: str, tree: ast.Module) -> list[int]:
    """Lines where a path built from ``__file__`` climbs above the wheel's top folder
    (``Path(__file__).parents[k]`` or a chain of ``.parent``, from a module ``name``)."""
    folder_depth = name.count("/") - 1  # robogen/x.py: 0, robogen/codegen/x.py: 1
    lines = []
    for node in ast.walk(tree):
        if not any(isinstance(n, ast.Name) and n.id == "__file__" for n in ast.walk(node)):
            continue
        if isinstance(node, ast.Subscript) and isinstance(node.value, ast.Attribute) and node.value.attr == "parents":
            up = node.slice.value if isinstance(node.slice, ast.Constant) else 99
        elif isinstance(node, ast.Attribute) and node.attr == "parent":
            chain, inner = 0, node
            while isinstance(inner, ast.Attribute) and inner.attr == "parent":
                chain, inner = chain + 1, inner.value
            up = chain - 1
        else:
            continue
        if up > folder_depth:
            lines.append(node.lineno)
    return lines


def docstrings(tree: ast.Module) -> set[int]:
    """The ids of the docstring nodes (documentation, not code)."""
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant) and isinstance(first.value.value, str):
                found.add(id(first.value))
    return found


def names_a_repository_folder(text: str) -> bool:
    return any(text == folder or f"{folder}/" in text for folder in REPOSITORY_FOLDERS)


def test_the_wheel_holds_the_robogen_package_only(wheel):
    tops = {name.split("/")[0] for name in wheel}
    assert {top for top in tops if not top.endswith(".dist-info")} == {"robogen"}
    assert "robogen/demo.py" not in wheel
    assert not [name for name in wheel if name.startswith("robogen/casestudy/")]
    assert not [name for name in wheel if name.startswith("robogen/platforms/data/")]
    # what the tool reads at run time does ship
    assert {"robogen/grammar/robosim.lark", "robogen/runtime/robogen_runtime.c", "robogen/pyfmu/shim.c",
            "robogen/pyfmu/bridge.h", "robogen/cosim/engine_run.c", "robogen/cosim/engine.h", "robogen/py.typed"} <= set(wheel)


def test_no_golden_file_refresher_ships(wheel):
    assert {name for name in wheel if name.endswith("golden.py")} == set()


def test_no_module_finds_the_repository_from_its_own_location(wheel):
    offenders = {name for name, tree in python_modules(wheel).items() if climbs_out_of_the_package(name, tree)}
    assert offenders == set()


def test_no_code_names_the_repository_folders(wheel):
    offenders = set()
    for name, tree in python_modules(wheel).items():
        skip = docstrings(tree)
        for node in ast.walk(tree):
            if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in skip \
                    and names_a_repository_folder(node.value):
                offenders.add(f"{name}:{node.lineno}")
    for name, data in wheel.items():
        if not name.endswith(".py") and not name.startswith("robogen-") and names_a_repository_folder(
                data.decode("utf-8", "replace")):
            offenders.add(name)
    assert {o.split(":")[0] for o in offenders} == set(), sorted(offenders)


def test_the_checks_see_what_they_look_for():
    shipped = "import pathlib\nROOT = pathlib.Path(__file__).resolve().parents[3]\nUP = pathlib.Path(__file__).parent.parent.parent\n"
    assert climbs_out_of_the_package("robogen/codegen/x.py", ast.parse(shipped)) == [2, 3]
    inside = "import pathlib\nRUNTIME = pathlib.Path(__file__).resolve().parent.parent / 'runtime'\n"
    assert climbs_out_of_the_package("robogen/codegen/x.py", ast.parse(inside)) == []
    assert names_a_repository_folder("models/ur5e/plan.toml") and names_a_repository_folder("tests")
    assert not names_a_repository_folder("the models of a workspace")
