"""robogen.codegen.generate and api: every test model compiles and packages in both semantics into an
FMU that robogen's validator and fmpy's accept; the generated sources are deterministic and
traceable to the model."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from fmpy.validation import validate_fmu as fmpy_validate

from support.codegen_models import MODELS, ROOT, SEMANTICS, TEST_MODELS
from robogen.cli import main as robogen_main
from robogen.codegen.api import compile_model, package_model
from robogen.codegen.generate import CodegenOptions
from robogen.diagnostics import RobogenError
from robogen.fmu.validate import validate_fmu
from robogen.ir.lower import LoweringOptions
from robogen.semantics import check_paths


@pytest.mark.parametrize("name", sorted(TEST_MODELS))
def test_model_checks_clean(name):
    model = check_paths([str(TEST_MODELS[name].path)])
    assert [d.message for d in model.errors] == []


@pytest.mark.parametrize("semantics", SEMANTICS)
@pytest.mark.parametrize("name", sorted(TEST_MODELS))
def test_model_packages_into_a_valid_fmu(built, name, semantics):
    b = built(name, semantics)
    assert b.archive.is_file()
    assert [str(d) for d in validate_fmu(b.archive) if d.is_error] == []
    assert fmpy_validate(str(b.archive)) == []
    md = (b.folder / "modelDescription.xml").read_text()
    assert f"{semantics} semantics" in md
    assert (b.folder / "sources" / "buildDescription.xml").is_file()


def test_robogen_validate_command_accepts_a_generated_fmu(built, capsys):
    assert robogen_main(["validate", str(built("relay", "stepwise").archive)]) == 0
    assert "0 errors, 0 warnings" in capsys.readouterr().err


# ---------------------------------------------------------------------------- determinism

GENERATE_ALL = """
import hashlib, json, sys
from pathlib import Path
from robogen.codegen.api import lower_paths
from robogen.codegen.generate import generate
from robogen.ir.lower import LoweringOptions
for path, settings, capacities in json.loads(sys.argv[1]):
    for semantics in ("exhaustive", "stepwise"):
        options = LoweringOptions(semantics=semantics, settings=settings, capacity=capacities[0], capacities=tuple(capacities))
        fmu, _ = lower_paths([path], options=options)
        for rel, text in sorted(generate(fmu).files.items()):
            print(path, semantics, rel, hashlib.sha256(text.encode()).hexdigest())
"""


def test_generated_sources_are_byte_identical_across_processes():
    """Two processes with different hash seeds (set and dict orders that depend on hashing would
    show) generate the same bytes for every test model, in both semantics."""
    paths = [(str(m.path.relative_to(ROOT)), m.settings, m.capacities or [m.capacity]) for m in TEST_MODELS.values()]
    outputs = []
    for seed in ("1", "2"):
        env = dict(os.environ, PYTHONHASHSEED=seed)
        result = subprocess.run([sys.executable, "-c", GENERATE_ALL, json.dumps(paths)], cwd=ROOT, env=env,
                                capture_output=True, text=True, check=True)
        outputs.append(result.stdout)
    assert outputs[0] == outputs[1]
    assert len(outputs[0].splitlines()) == len(paths) * 2 * 8


def test_compiling_twice_writes_identical_folders(tmp_path):
    model = TEST_MODELS["pipeline"].path
    folders = []
    for i in range(2):
        compile_model([str(model)], tmp_path / f"out{i}", options=LoweringOptions(semantics="stepwise"))
        folders.append({p.relative_to(tmp_path / f"out{i}"): p.read_bytes()
                        for p in sorted((tmp_path / f"out{i}").rglob("*")) if p.is_file()})
    assert folders[0] == folders[1]
    assert Path("sources/model.c") in folders[0]


@pytest.mark.parametrize("name", ["ur5e", "timers", "ops"])
def test_one_model_in_two_checkouts_gives_byte_identical_sources_and_token(tmp_path, monkeypatch, name):
    """Generated files name model files relative to the workspace root, and the token is hashed
    from the path-free IR dump: copies of a model at two different absolute paths, one given as
    an absolute path, the other relative to the current folder, give the same files."""
    source = TEST_MODELS[name].path
    outputs = []
    for where in ("one", "two/deeper/checkout"):
        folder = tmp_path / where / "models"
        folder.mkdir(parents=True)
        shutil.copyfile(source, folder / source.name)
        outputs.append(folder / source.name)
    monkeypatch.chdir(tmp_path / "two")
    first = compile_model([outputs[0]], tmp_path / "out1", options=LoweringOptions(settings=dict(TEST_MODELS[name].settings)))
    second = compile_model([Path("deeper/checkout/models") / source.name], tmp_path / "out2",
                           options=LoweringOptions(settings=dict(TEST_MODELS[name].settings)))
    assert first.generated.token == second.generated.token
    assert first.generated.files == second.generated.files
    assert f"from {source.name} (" in first.generated.files["sources/model.c"]
    assert all(str(tmp_path) not in text for text in first.generated.files.values())


# ---------------------------------------------------------------------------- traceability

CASE = re.compile(r"^\s*case (\d+): /\* b\1: (.*?)(?:  (\S+):(\d+))? \*/$")


def element_of(label: str) -> str | None:
    """The model element a block comes from, as its name appears on the block's model line."""
    fixed = {"after exec": "exec", "wait": "wait", "after wait": "wait"}
    if label in fixed:
        return fixed[label]
    if label in ("then", "else", "end if"):
        return None  # the line of a branch's first statement
    for prefix in ("start ", "call ", "wait for "):
        if label.startswith(prefix):
            return label[len(prefix):].rstrip("()")
    if label.startswith("EVAL "):
        return label[5:].split(".")[-1]
    if label.startswith("after "):
        return re.split(r"[?(]", label[6:])[0]
    return label.split(":")[0]  # a transition: "t2: Idle -> ArmMove", "t2: exec decided"


@pytest.mark.parametrize("name", sorted(TEST_MODELS))
def test_every_block_names_its_model_element_and_line(built, name):
    b = built(name, "exhaustive")
    model_c = b.sources["sources/model.c"]
    cases = [CASE.match(line) for line in model_c.splitlines() if re.match(r"^\s*case \d+: /\* b\d+:", line)]
    assert cases and all(cases), [line for line in model_c.splitlines() if "case" in line][:5]
    blocks = sum(len(m.blocks) for m in b.fmu.machines)
    assert len(cases) == blocks
    lines_of: dict[str, list[str]] = {}
    for match in cases:
        label, path, line = match.group(2), match.group(3), match.group(4)
        assert path is not None, f"block without a model location: {match.group(0)}"
        root = TEST_MODELS[name].path.parent  # the workspace root: the folder of the model given
        text = lines_of.setdefault(path, (root / path).read_text().splitlines())[int(line) - 1]
        element = element_of(label)
        assert element is None or re.search(rf"\b{re.escape(element)}\b", text), (label, f"{path}:{line}", text)
    # the machine and each transition in the machine's comments too
    assert f"/* ======== state machine {b.fmu.machines[0].qname} (" in model_c


HOOKS = {"RG_HAS_EXIT_INITIALIZATION": "rg_model_exit_initialization", "RG_HAS_LATCH": "rg_model_latch",
         "RG_HAS_EVALUATE": "rg_model_evaluate", "RG_HAS_UPDATE": "rg_model_update", "RG_HAS_DO_STEP": "rg_model_do_step"}


@pytest.mark.parametrize("name", sorted(TEST_MODELS))
def test_config_lists_exactly_the_hooks_model_c_implements(built, name):
    """Capability macros, as in the Reference FMUs: the runtime's defaults stand in for the hooks
    a model would only stub, so model.c defines a hook exactly when config.h lists it."""
    b = built(name, "exhaustive")
    model_c, config_h = b.sources["sources/model.c"], b.sources["sources/config.h"]
    for macro, hook in HOOKS.items():
        listed = re.search(rf"^#define {macro}\b", config_h, re.M) is not None
        defined = re.search(rf"^static \w+ {hook}\(", model_c, re.M) is not None
        assert listed == defined, (macro, listed, defined)
    # the machines react only in Event Mode; a time-free RoboChart FMU counts the tocks a step passes
    assert ("RG_HAS_DO_STEP" in config_h) == b.fmu.time_free
    assert "RG_HAS_EVALUATE" in config_h
    if any(v.init is not None for m in b.fmu.machines for v in m.vars if v.kind == "var"):
        assert "#define RG_HAS_EXIT_INITIALIZATION" in config_h


def test_line_comments_can_be_switched_off(tmp_path):
    model = TEST_MODELS["ur5e"].path
    with_lines = compile_model([str(model)], tmp_path / "a").generated.files["sources/model.c"]
    without = compile_model([str(model)], tmp_path / "b", codegen=CodegenOptions(line_comments=False)).generated.files["sources/model.c"]
    assert re.search(r"/\* b4: t2: Idle -> ArmMove  \S*ur5e\.rst:\d+ \*/", with_lines)
    assert "/* b4: t2: Idle -> ArmMove */" in without
    assert not re.search(r"case \d+: /\*[^*]*ur5e\.rst:\d+", without)


def test_a_model_name_that_clashes_with_an_fmi_variable_is_renamed_or_a_located_error(tmp_path):
    """Events named like robogen's own FMI variables get renamed clocks (with a warning); a
    machine variable named 'state' would be a second '<machine>.state': a located error."""
    model = tmp_path / "clash.rct"
    model.write_text(
        "package clash\n"
        "interface I { event tock event cycles: nat }\n"
        "stm M {\n"
        "\tuses I\n"
        "\tvar n: nat = 0\n"
        "\tinitial i\n"
        "\tstate S { }\n"
        "\ttransition t0 { from i to S }\n"
        "\ttransition t1 { from S to S trigger tock action n = n + 1 ; send cycles!n }\n"
        "}\n")
    compiled = compile_model([str(model)], tmp_path / "out")
    assert [p.name for p in compiled.fmu.inputs + compiled.fmu.outputs] == ["tock_event", "cycles_event"]
    assert [(w.span.line, w.span.column, w.message) for w in compiled.fmu.warnings] == [
        (2, 21, "input event 'tock' becomes the FMI clock 'tock_event': 'tock' is one of robogen's own FMI variables"),
        (2, 32, "output event 'cycles' becomes the FMI clock 'cycles_event': 'cycles' is one of robogen's own FMI variables"),
    ]
    model.write_text(model.read_text().replace("var n: nat = 0", "var n: nat = 0, ^state: nat = 1"))
    with pytest.raises(RobogenError) as caught:
        compile_model([str(model)], tmp_path / "out")
    found = [(d.span.line, d.span.column, d.message, [n.message for n in d.notes]) for d in caught.value.diagnostics]
    assert [f[:3] for f in found] == [(5, 18, "the FMU would have two variables named 'M.state' (variable state of M); "
                                               "rename it in the model")]
    assert "robogen's own FMI variables" in found[0][3][0]


def test_events_connected_to_nothing_compile(tmp_path):
    """nested.rct without its controller's connections: the platform's events reach no machine and
    the machine's output goes nowhere; the generated C must still build with -Werror."""
    text = (MODELS / "nested.rct").read_text()
    text = re.sub(r"\n\tconnection Ctl on a to m on a\n\tconnection Ctl on b to m on b \[ mult \]\n\tconnection m on out to Ctl on out", "", text)
    assert "connection Ctl" not in text
    model = tmp_path / "unconnected.rct"
    model.write_text(text)
    archive, compiled = package_model([str(model)], tmp_path / "unconnected.fmu")
    assert archive.is_file()
    assert all(not p.routes for p in compiled.fmu.inputs)
    assert "reaches no state machine" in compiled.generated.files["sources/model.c"]


def test_packaging_twice_gives_byte_identical_archives(tmp_path):
    """The .fmu too: same binary, same ZIP entries and times."""
    first, _ = package_model([str(TEST_MODELS["ur5e"].path)], tmp_path / "a.fmu")
    second, _ = package_model([str(TEST_MODELS["ur5e"].path)], tmp_path / "b.fmu")
    assert first.read_bytes() == second.read_bytes()
