"""`robogen validate` reads every binary of an FMU: an FMU whose Windows DLL lacks an FMI export,
whose binaries/aarch64-linux holds an x86_64 library, or whose binary is a program or an object
file rather than a shared library is rejected, each error located at the binary."""

from __future__ import annotations

import zipfile

import pytest

from robogen import toolchain
from robogen.cli import main
from robogen.fmu.archive import write_fmu
from robogen.fmu.platforms import BUILT, HOST
from robogen.fmu.validate import fmi3_function_names, validate_fmu

WINDOWS, AARCH64_LINUX, X86_64_DARWIN = BUILT[2], BUILT[1], BUILT[3]


def replaced(fmu, target, replacements: dict[str, bytes]):
    with zipfile.ZipFile(fmu) as z:
        files = {n: z.read(n) for n in z.namelist()}
    return write_fmu(target, {**files, **replacements})


def errors(fmu):
    return [(d.span.path if d.span else None, d.message) for d in validate_fmu(fmu) if d.is_error]


def test_a_windows_dll_without_one_export_is_rejected(ur5e_everywhere, tmp_path):
    names = [n for n in fmi3_function_names() if n != "fmi3DoStep"]
    source = tmp_path / "most.c"
    source.write_text("".join(f"__declspec(dllexport) int {n}(void);\nint {n}(void) {{ return 0; }}\n" for n in names))
    dll = toolchain.compile_shared([source], tmp_path / "out" / "most.dll", platform=WINDOWS)
    name = WINDOWS.binary(ur5e_everywhere.identifier)
    fmu = replaced(ur5e_everywhere.archive, tmp_path / "lacking.fmu", {name: dll.read_bytes()})
    assert errors(fmu) == [(f"{fmu}/{name}", "the binary exports 74 of the 75 FMI 3.0 functions; missing: fmi3DoStep")]


def test_an_x86_64_library_in_the_aarch64_linux_folder_is_rejected(ur5e_everywhere, tmp_path):
    name = AARCH64_LINUX.binary(ur5e_everywhere.identifier)
    fmu = replaced(ur5e_everywhere.archive, tmp_path / "wrong-arch.fmu", {name: ur5e_everywhere.binary(HOST).read_bytes()})
    assert errors(fmu) == [(f"{fmu}/{name}", "the binary is an ELF file for x86_64; binaries/aarch64-linux needs an "
                                             "ELF shared library for aarch64")]


def test_a_windows_library_in_a_macos_folder_is_rejected(ur5e_everywhere, tmp_path):
    name = X86_64_DARWIN.binary(ur5e_everywhere.identifier)
    fmu = replaced(ur5e_everywhere.archive, tmp_path / "wrong-format.fmu",
                   {name: ur5e_everywhere.binary(WINDOWS).read_bytes()})
    assert errors(fmu) == [(f"{fmu}/{name}", "the binary is a PE file for x86_64; binaries/x86_64-darwin needs a "
                                             "Mach-O shared library for x86_64")]


@pytest.mark.parametrize("platform", [WINDOWS, AARCH64_LINUX], ids=str)
def test_a_program_instead_of_a_library_is_rejected(platform, ur5e_everywhere, trace_hosts, tmp_path, capsys):
    name = platform.binary(ur5e_everywhere.identifier)
    fmu = replaced(ur5e_everywhere.archive, tmp_path / "program.fmu", {name: trace_hosts(platform).read_bytes()})
    assert errors(fmu) == [(f"{fmu}/{name}", "the binary is an executable, not a shared library: an importer cannot load it")]
    assert main(["validate", str(fmu)]) == 1
    assert f"{name}:1:1: error: the binary is an executable, not a shared library" in capsys.readouterr().err


def test_an_object_file_instead_of_a_library_is_rejected(ur5e_everywhere, tmp_path):
    source = tmp_path / "one.c"
    source.write_text("int one(void);\nint one(void) { return 1; }\n")
    toolchain.run_compiler([*toolchain.CFLAGS, "-c", str(source), "-o", str(tmp_path / "one.o")], "an object file",
                           platform=AARCH64_LINUX)
    name = AARCH64_LINUX.binary(ur5e_everywhere.identifier)
    fmu = replaced(ur5e_everywhere.archive, tmp_path / "object.fmu", {name: (tmp_path / "one.o").read_bytes()})
    assert errors(fmu) == [(f"{fmu}/{name}", "the binary is an object file, not a shared library: an importer cannot load it")]
