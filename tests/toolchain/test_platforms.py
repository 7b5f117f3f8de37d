"""`robogen package --platforms`: one FMU with a binary per FMI 3.0 platform, each as strict as
the host's (house flags, exactly the FMI exports, no path of the build machine), byte-identical
from two checkouts; the platform list and the Python FMUs' limits are clear errors.

The macOS binaries are checked here structurally only (format, architecture, exports): nothing
on this machine runs them. The Windows and aarch64 Linux binaries also run: test_cross_run.py.
"""

from __future__ import annotations

import importlib.util
import shutil
import zipfile

import pytest

from robogen import toolchain
from robogen.cli import main
from robogen.diagnostics import RobogenError
from robogen.fmu.binaries import read_binary
from robogen.fmu.platforms import BUILT, HOST, select
from robogen.fmu.validate import fmi3_function_names, validate_fmu

from support.codegen_models import UR5E

FORMATS = {"x86_64-linux": ("ELF", "x86_64"), "aarch64-linux": ("ELF", "aarch64"), "x86_64-windows": ("PE", "x86_64"),
           "x86_64-darwin": ("Mach-O", "x86_64"), "aarch64-darwin": ("Mach-O", "aarch64")}


def test_the_platform_list_names_the_five_tuples_or_all():
    assert select("x86_64-linux,aarch64-linux,x86_64-windows,x86_64-darwin,aarch64-darwin") == BUILT
    assert select("all") == BUILT and [p.name for p in BUILT] == list(FORMATS)
    assert select(" aarch64-darwin , x86_64-linux") == (BUILT[4], HOST)
    assert [(p.suffix, p.format) for p in BUILT] == [(".so", "ELF"), (".so", "ELF"), (".dll", "PE"),
                                                     (".dylib", "Mach-O"), (".dylib", "Mach-O")]


@pytest.mark.parametrize("text, message", [
    ("linux64", "--platforms linux64: 'linux64' is not an FMI 3.0 platform tuple (choose from x86_64-linux, "
                "aarch64-linux, x86_64-windows, x86_64-darwin, aarch64-darwin, or all)"),
    ("riscv64-linux", "'riscv64-linux' is not one robogen builds"),
    ("x86_64-linux,x86_64-linux", "'x86_64-linux' is named twice"),
    ("", "'' is not an FMI 3.0 platform tuple"),
])
def test_a_bad_platform_list_is_a_clear_error(text, message, tmp_path, capsys):
    assert main(["package", str(UR5E), "--platforms", text, "-o", str(tmp_path / "x.fmu")]) == 1
    assert message in capsys.readouterr().err
    assert not (tmp_path / "x.fmu").exists()


def test_without_zig_a_cross_build_names_the_extra_to_install(monkeypatch, tmp_path):
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "ziglang" else real(name, *a))
    with pytest.raises(RobogenError, match=r"building the aarch64-linux binary needs zig, from the ziglang package, "
                                           r"which is not installed: pip install 'robogen\[cross\]'"):
        toolchain.compiler(BUILT[1])
    assert main(["package", str(UR5E), "--platforms", "all", "-o", str(tmp_path / "x.fmu")]) == 1
    assert not (tmp_path / "x.fmu").exists()


def test_a_python_fmu_is_for_the_host_only_and_says_why(tmp_path, capsys):
    code = main(["package-py", "robogen.platforms.controller:PlanController", "--set", "plan=models/ur5e/plan.toml",
                 "--platforms", "x86_64-linux,x86_64-windows", "-o", str(tmp_path / "c.fmu")])
    err = capsys.readouterr().err
    assert code == 1
    assert "a Python FMU is built for x86_64-linux only, not x86_64-windows: its binary embeds this machine's CPython" in err
    assert "Traceback" not in err and not (tmp_path / "c.fmu").exists()


def test_one_fmu_holds_a_binary_per_platform_and_the_sources(ur5e_everywhere):
    with zipfile.ZipFile(ur5e_everywhere.archive) as z:
        names = z.namelist()
    ident = ur5e_everywhere.identifier
    assert sorted(n for n in names if n.startswith("binaries/")) == sorted(p.binary(ident) for p in BUILT)
    assert f"sources/{ident}.c" in names and "sources/buildDescription.xml" in names
    assert validate_fmu(ur5e_everywhere.archive) == []  # no error and no warning, for any binary


@pytest.mark.parametrize("platform", BUILT, ids=str)
def test_each_binary_is_a_shared_library_of_its_platform_exporting_exactly_the_fmi_functions(ur5e_everywhere, platform):
    data = ur5e_everywhere.binary(platform).read_bytes()
    info = read_binary(data)
    assert (info.format, info.arch, info.kind) == (*FORMATS[platform.name], "shared library")
    assert info.exports == set(fmi3_function_names())
    # nothing of the build machine: no temporary folder, no checkout, no user
    for text in (b"/tmp", b"robogen-build", str(UR5E.parent.parent.parent).encode(), b"/home/", b"/root"):
        assert text not in data, (platform, text)


def test_two_checkouts_give_byte_identical_fmus(ur5e_everywhere, tmp_path, monkeypatch):
    """The fixture's FMU was packaged from this checkout by absolute path; this one from a copy of
    the models elsewhere, by a relative path from another working folder."""
    checkout = tmp_path / "another" / "checkout"
    shutil.copytree(UR5E.parent.parent, checkout / "models")
    monkeypatch.chdir(checkout)
    assert main(["package", "models/ur5e/ur5e.rst", "--platforms", "all", "-o", "again.fmu"]) == 0
    assert (checkout / "again.fmu").read_bytes() == ur5e_everywhere.archive.read_bytes()


def test_the_house_flags_hold_on_every_target(tmp_path):
    """A warning fails the build for each platform, and the error names the platform."""
    if importlib.util.find_spec("ziglang") is None:
        pytest.skip("the ziglang package is not installed (pip install 'robogen[cross]')")
    (tmp_path / "warn.c").write_text("int warn(void);\nint warn(void) { int unused; return 0; }\n")
    others = {p: tmp_path / p.name / f"warn{p.suffix}" for p in BUILT if p != HOST}
    with pytest.raises(RobogenError) as caught:
        toolchain.compile_shared_all([tmp_path / "warn.c"], others, what="warn")
    messages = [d.message for d in caught.value.diagnostics]
    assert len(messages) == 4
    for platform, message in zip(others, messages):
        assert message.startswith(f"compiling warn for {platform} failed")
        assert "-std=c99 -Wall -Wextra -Wpedantic -Werror -fvisibility=hidden" in message and "-Werror,-Wunused-variable" in message
