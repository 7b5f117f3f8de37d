"""The stages import forward only: a later stage reads an earlier stage's finished product, never
its internals, and no module of robogen imports itself back through others.

The imports are read with ``ast`` from every module under src/robogen, those inside functions
and ``if TYPE_CHECKING:`` blocks included (a lazy import is still a dependency).
"""

from __future__ import annotations

import ast
from pathlib import Path

SRC = Path(__file__).resolve().parent.parent / "src"

# what the IR may read of the semantic analysis: its resolved model and the types
IR_READS_OF_SEMANTICS = {"robogen.semantics.model", "robogen.semantics.types"}


def module_name(path: Path) -> str:
    parts = list(path.relative_to(SRC).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def modules() -> dict[str, Path]:
    return {module_name(p): p for p in sorted((SRC / "robogen").rglob("*.py"))}


def imports_of(name: str, path: Path, known: set[str]) -> set[str]:
    """The robogen modules ``name`` imports: ``from p import m`` names module p.m when it is one."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(anchor + ([base] if base else []))
            targets = [f"{base}.{a.name}" if f"{base}.{a.name}" in known else base for a in node.names]
        else:
            continue
        for target in targets:
            while target and target not in known:  # `import a.b.c` depends on the modules it names
                target = target.rpartition(".")[0]
            if target.startswith("robogen") and target != name:
                found.add(target)
    return found


def import_graph() -> dict[str, set[str]]:
    mods = modules()
    known = set(mods)
    return {name: imports_of(name, path, known) for name, path in mods.items()}


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Import cycles, each as the path of modules around it: one for every import a depth-first
    walk meets that leads back to a module on the current path."""
    state: dict[str, str] = {}  # "open" while on the current path, then "done"
    path: list[str] = []
    found: list[list[str]] = []

    def visit(v: str) -> None:
        state[v] = "open"
        path.append(v)
        for w in sorted(graph.get(v, ())):
            if state.get(w) == "open":
                found.append(path[path.index(w):] + [w])
            elif w not in state:
                visit(w)
        path.pop()
        state[v] = "done"

    for v in sorted(graph):
        if v not in state:
            visit(v)
    return found


def test_the_import_graph_is_read():
    graph = import_graph()
    assert "robogen.semantics.model" in graph["robogen.ir.lower"]
    assert "robogen.semantics.types" in graph["robogen.ir.model"]  # `from robogen.semantics.types import Type`
    assert "robogen.semantics.types" in graph["robogen.ir.expressions"]  # `from robogen.semantics import types as T`


def test_the_cycle_finder_finds_cycles():
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c", "a"]]
    assert cycles({"a": {"b"}, "b": set()}) == []


def test_ir_reads_only_the_resolved_model_of_the_semantics():
    wrong = {(name, target) for name, targets in import_graph().items() if name.startswith("robogen.ir")
             for target in targets if target.startswith("robogen.semantics") and target not in IR_READS_OF_SEMANTICS}
    assert wrong == set()


def test_the_master_does_not_import_the_code_generator():
    wrong = {(name, target) for name, targets in import_graph().items() if name.startswith("robogen.cosim")
             for target in targets if target.startswith("robogen.codegen")}
    assert wrong == set()


def test_nothing_imports_the_model_fuzzer():
    """robogen.fuzz is the top of the layering: it drives every stage, and no stage depends on it."""
    wrong = {(name, target) for name, targets in import_graph().items() if not name.startswith("robogen.fuzz")
             for target in targets if target.startswith("robogen.fuzz")}
    assert wrong == set()
    assert "robogen.differential" in import_graph()["robogen.fuzz.properties"]


def test_no_import_cycle_between_robogen_modules():
    assert cycles(import_graph()) == []


#: The modules of robogen.cosim in layers, lowest first: a module imports only modules of the
#: layers below its own (docs/architecture.md draws the same picture).
COSIM_LAYERS = (
    ("signals", "clocks", "columnar", "tomlspan", "watch", "cbuild", "xmltree", "units"),  # no other module of cosim
    ("fmi3", "system", "scenario", "ssp_schema"),  # the FMI 3.0 binding; the system file; scenario files; the SSP schemas' rules
    ("instances", "recorder", "proxy", "worker", "crash", "schema", "adapters", "player", "shared",  # one instance, one row; Python FMUs once per process
     "ssp_model", "ssp_package", "system_data"),  # an SSD's elements; an SSP's files; a system as TOML data
    ("wiring", "interfaces", "ssp_params"),  # who reads what, which clock goes where; the interface adapters; SSP parameters
    ("plan", "ssp_flatten"),  # the run's plan: what both loops execute; an SSP hierarchy flattened
    ("flat", "ssp_components", "ssp_start"),  # the plan as rg_plan (engine.h); SSP components, start values
    ("engine", "ssp_read"),  # the plan run in C; an SSP read into a system
    ("master",),  # the reference loop, setup and errors; runs the engine
    ("assemble",),  # from a system file (or an SSP) to a master
    ("__init__", "plot", "ssp_write"),  # the API (simulate_system), plots of results, SSP export
    ("cli", "ssp_cli"),  # the commands
)


def test_cosim_modules_import_each_other_only_downward():
    layer = {(f"robogen.cosim.{m}" if m != "__init__" else "robogen.cosim"): i
             for i, names in enumerate(COSIM_LAYERS) for m in names}
    graph = import_graph()
    cosim = {name for name in graph if name == "robogen.cosim" or name.startswith("robogen.cosim.")}
    assert cosim == set(layer), "every module of robogen.cosim has its layer in COSIM_LAYERS"
    upward = sorted((name, target) for name in cosim for target in graph[name]
                    if target in layer and layer[target] >= layer[name])
    assert upward == []
