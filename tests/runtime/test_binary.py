"""robogen.codegen.binary and robogen.toolchain: building an FMU binary, the house flags, and the 75 exports of a built FMU."""

from __future__ import annotations

import os
import re
import shutil
import sys
from pathlib import Path

import pytest

from robogen import toolchain
from robogen.codegen import binary
from robogen.diagnostics import RobogenError
from robogen.fmu.headers import include_dir


def header_function_names() -> set[str]:
    """Every function fmi3Functions.h declares with FMI3_Export (the standard's full API)."""
    text = (include_dir() / "fmi3Functions.h").read_text()
    return set(re.findall(r"FMI3_Export\s+fmi3\w+TYPE\s+(fmi3\w+)\s*;", text))


def test_the_header_declares_75_functions():
    # 11 common, 28 get/set, 2 dependency, 6 FMU state, 2 derivative, 2 configuration,
    # 8 interval/shift, 2 discrete state, 10 Model Exchange, 3 Co-Simulation, 1 Scheduled Execution
    assert len(header_function_names()) == 75


@pytest.mark.parametrize("fixture", ["counter_fmu", "plain_fmu"])
def test_a_built_fmu_exports_exactly_the_75_api_functions(fixture, request):
    fmu = request.getfixturevalue(fixture)
    assert toolchain.exported_symbols(fmu.library) == sorted(header_function_names())


def test_runtime_dir_holds_the_runtime():
    folder = binary.runtime_dir()
    assert (folder / "robogen_runtime.h").is_file()
    assert (folder / "robogen_runtime.c").is_file()


def test_runtime_sources_are_the_runtime_files():
    names = [path.name for path in binary.runtime_sources()]
    assert names == sorted(names)
    assert {"robogen_runtime.h", "robogen_machine.h", "robogen_runtime.c"} <= set(names)
    included = re.findall(r'#include "(robogen_runtime_\w+\.c)"', (binary.runtime_dir() / "robogen_runtime.c").read_text())
    assert set(included) == set(names) - {"robogen_runtime.h", "robogen_machine.h", "robogen_runtime.c"}


BUILD_DESCRIPTION = """<?xml version="1.0" encoding="UTF-8"?>
<fmiBuildDescription fmiVersion="3.0">
  <BuildConfiguration modelIdentifier="counter">
    <SourceFileSet language="C99">
      <SourceFile name="counter.c"/>
    </SourceFileSet>
  </BuildConfiguration>
</fmiBuildDescription>
"""


def test_a_sources_folder_builds_with_fmpy(tmp_path, monkeypatch):
    """What `fmpy compile` does: CMake over sources/ with only fmpy's headers added (fmpy depends
    on the cmake package, so its cmake is installed next to this Python)."""
    from fmpy.build import build_platform_binary

    monkeypatch.setenv("PATH", f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}")

    models = Path(__file__).resolve().parent / "models" / "counter"
    sources = tmp_path / "sources"
    sources.mkdir()
    for path in [*binary.runtime_sources(), *(models / name for name in ("config.h", "model.c", "counter.c"))]:
        shutil.copy(path, sources / path.name)
    (sources / "buildDescription.xml").write_text(BUILD_DESCRIPTION)
    shutil.copy(models / "modelDescription.xml", tmp_path / "modelDescription.xml")
    (tmp_path / "build").mkdir()
    build_platform_binary(tmp_path, build_dir=tmp_path / "build", all_warnings=True)
    library = tmp_path / "binaries" / "x86_64-linux" / "counter.so"
    assert toolchain.exported_symbols(library) == sorted(header_function_names())


def test_house_flags():
    assert toolchain.CFLAGS == ("-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-fvisibility=hidden")
    assert "-fsanitize=address,undefined" in toolchain.SANITIZE_FLAGS


def test_include_order_puts_the_sources_first(tmp_path):
    assert binary.include_dirs(tmp_path) == [tmp_path, binary.runtime_dir()]
    assert toolchain.include_args(binary.include_dirs(tmp_path)) == ["-I", str(tmp_path), "-I", str(binary.runtime_dir())]
    assert toolchain.include_args([include_dir()], "-isystem") == ["-isystem", str(include_dir())]


def test_a_compile_error_is_a_robogen_error_with_the_compiler_output(tmp_path):
    (tmp_path / "broken.c").write_text("int broken(void) { return undeclared_name; }\n")
    with pytest.raises(RobogenError) as caught:
        binary.compile_fmu_binary(tmp_path, "broken", tmp_path / "out" / "broken.so")
    assert "undeclared_name" in str(caught.value)
    assert not (tmp_path / "out" / "broken.so").exists()


def test_a_warning_fails_the_build(tmp_path):
    (tmp_path / "warn.c").write_text("int warn(void) { int unused; return 0; }\n")
    with pytest.raises(RobogenError, match="unused"):
        binary.compile_fmu_binary(tmp_path, "warn", tmp_path / "warn.so")


def test_missing_source_and_bad_identifier_are_reported(tmp_path):
    with pytest.raises(RobogenError, match="does not exist"):
        binary.compile_fmu_binary(tmp_path, "absent", tmp_path / "absent.so")
    with pytest.raises(RobogenError, match="not a C identifier"):
        binary.compile_fmu_binary(tmp_path, "not-an-id", tmp_path / "x.so")


def test_exported_symbols_of_a_small_library(tmp_path):
    (tmp_path / "lib.c").write_text(
        "__attribute__((visibility(\"default\"))) int shown(void) { return 1; }\n"
        "int hidden(void) { return 2; }\n"
        "static int internal(void) { return 3; }\n"
        "int use(void) { return internal(); }\n"
    )
    library = binary.compile_fmu_binary(tmp_path, "lib", tmp_path / "lib.so")
    assert toolchain.exported_symbols(library) == ["shown"]


def test_cc_may_be_a_word_list(monkeypatch, tmp_path):
    """CC="ccache gcc" style settings: the first word is the program, the rest its arguments."""
    monkeypatch.setenv("CC", "env cc")
    assert toolchain.compiler() == ["env", "cc"]
    (tmp_path / "lib.c").write_text("__attribute__((visibility(\"default\"))) int shown(void) { return 1; }\n")
    library = toolchain.compile_shared([tmp_path / "lib.c"], tmp_path / "lib.so")
    assert toolchain.exported_symbols(library) == ["shown"]


def test_a_missing_compiler_is_a_located_robogen_error(monkeypatch):
    monkeypatch.setenv("CC", "no-such-compiler-xyz")
    with pytest.raises(RobogenError, match="C compiler 'no-such-compiler-xyz' not found"):
        toolchain.compiler()
