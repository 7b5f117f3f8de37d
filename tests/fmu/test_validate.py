"""robogen's FMU checker: the clock rules fmpy and fmutool miss, located in the archive's files."""

from __future__ import annotations

import zipfile

import pytest

from robogen.cli import main
from robogen.fmu.archive import write_fmu
from robogen.fmu.validate import fmi3_function_names, validate_fmu


def rewrite(src, dst, **replace_files):
    with zipfile.ZipFile(src) as z:
        files = {n: z.read(n) for n in z.namelist()}
    for name, change in replace_files.items():
        name = name.replace("__", "/").replace("_DOT_", ".")
        files[name] = change(files.get(name, b"").decode()) if callable(change) else change
    return write_fmu(dst, {k: v for k, v in files.items() if v is not None})


def variant(built, tmp_path, model, old, new):
    def change(xml):
        assert old in xml
        return xml.replace(old, new)
    return rewrite(built[model], tmp_path / f"{model}-variant.fmu", modelDescription_DOT_xml=change)


def messages(fmu):
    return [(d.severity.value, d.span.line if d.span else None, d.message) for d in validate_fmu(fmu)]


def test_the_test_fmus_are_valid(built):
    for fmu in built.values():
        assert messages(fmu) == []


def test_header_declares_75_functions():
    names = fmi3_function_names()
    assert len(names) == 75 == len(set(names)) and "fmi3DoStep" in names


@pytest.mark.parametrize("model, old, new, expected", [
    ("ticker", 'intervalDecimal="0.25" ', "",
     (12, "constant clock 'tick' needs intervalDecimal")),
    ("ticker", '<Clock name="out" valueReference="2" causality="output" variability="discrete" intervalVariability="triggered"/>',
     '<Clock name="out" valueReference="2" causality="output" variability="discrete" intervalVariability="countdown"/>',
     (13, "output clock 'out' is countdown; output clocks must be triggered")),
    ("ticker", 'clocks="2"', 'clocks="5"',
     (14, "'count': clocks= names 'phase' (value reference 5), which is a Float64, not a Clock")),
    ("ticker", 'clocks="2"', 'clocks="42"',
     (14, "'count': clocks=\"42\" names value reference 42, which no variable has")),
    ("ticker", 'hasEventMode="true"', 'hasEventMode="false"',
     (6, "the FMU has clocks (tick, out) but <CoSimulation> lacks hasEventMode=\"true\"")),
    ("ticker", '<Float64 name="phase" valueReference="5" causality="output" variability="continuous"/>',
     '<Float64 name="phase" valueReference="5" causality="output" variability="continuous" clocks="2"/>',
     (16, "clocked variable 'phase' has variability=\"continuous\"; clocked variables are discrete or tunable")),
    ("relay", 'intervalVariability="triggered"/>\n    <Int64 name="x_in"', 'intervalVariability="triggered" intervalDecimal="1.0"/>\n    <Int64 name="x_in"',
     (12, "triggered clock 'u' must not have intervalDecimal")),
    ("relay", '<Clock name="y" valueReference="3" causality="output" variability="discrete" intervalVariability="triggered"/>',
     '<Clock name="y" valueReference="3" causality="output" variability="discrete" intervalVariability="triggered" priority="1"/>',
     (14, "output clock 'y' must not have priority")),
    ("relay", '    <Output valueReference="3" dependencies="1"/>\n', "",
     (14, "output clock 'y' is missing from <ModelStructure><Output>")),
])
def test_clock_rules(built, tmp_path, model, old, new, expected):
    found = [(line, msg) for sev, line, msg in messages(variant(built, tmp_path, model, old, new)) if sev == "error"]
    assert expected in found


def test_structure_order_and_local_clock(built, tmp_path):
    fmu = variant(built, tmp_path, "ticker", '    <InitialUnknown valueReference="2" dependencies="1"/>\n    <InitialUnknown valueReference="4"/>\n',
                  '    <InitialUnknown valueReference="2" dependencies="1"/>\n    <Output valueReference="4"/>\n')
    assert any(m == "<Output> after <InitialUnknown>: ModelStructure lists Output, ContinuousStateDerivative, ClockedState, InitialUnknown, EventIndicator in that order"
               for _s, _l, m in messages(fmu))


def test_missing_exports_and_layout(built, tmp_path, fmu_builder):
    from robogen import toolchain
    from robogen.fmu.headers import include_dir

    so = tmp_path / "lib.so"
    (tmp_path / "few.c").write_text('#include "fmi3Functions.h"\nFMI3_Export const char* fmi3GetVersion(void) { return fmi3Version; }\n')
    toolchain.compile_shared([tmp_path / "few.c"], so, includes=[include_dir()])
    fmu = rewrite(built["trivial"], tmp_path / "few.fmu", **{"binaries__x86_64-linux__trivial_DOT_so": so.read_bytes(),
                                                           "binaries__linux64__trivial_DOT_so": b"x", "stray_DOT_txt": b"x"})
    msgs = {m for _s, _l, m in messages(fmu)}
    assert any(m.startswith("the binary exports 1 of the 75 FMI 3.0 functions; missing: fmi3SetDebugLogging") for m in msgs)
    assert "'binaries/linux64' is an FMI 2.0 platform name; FMI 3.0 uses tuples such as 'x86_64-linux'" in msgs
    assert "'stray.txt' is outside the FMI 3.0 archive layout (use extra/ for other files)" in msgs


def test_build_description_rules(built, tmp_path):
    bd = ('<?xml version="1.0" encoding="UTF-8"?>\n<fmiBuildDescription fmiVersion="3.0">\n'
          '  <BuildConfiguration modelIdentifier="trivial">\n    <SourceFileSet language="C99">\n'
          '      <SourceFile name="trivial.c"/>\n      <SourceFile name="gone.c"/>\n'
          '      <PreprocessorDefinition name="FMI3_FUNCTION_PREFIX" value="trivial_"/>\n'
          '    </SourceFileSet>\n  </BuildConfiguration>\n</fmiBuildDescription>\n')
    fmu = rewrite(built["trivial"], tmp_path / "bd.fmu", sources__buildDescription_DOT_xml=bd)
    found = [(line, m) for s, line, m in messages(fmu) if s == "error"]
    assert (6, '<SourceFile name="gone.c"> is not in sources/') in found
    assert (7, "FMI3_FUNCTION_PREFIX must not be defined: a shared object exports unprefixed names") in found


def test_cli_exit_codes_and_location(built, tmp_path, capsys):
    assert main(["validate", str(built["relay"])]) == 0
    bad = variant(built, tmp_path, "ticker", 'intervalDecimal="0.25" ', "")
    assert main(["validate", str(bad)]) == 1
    err = capsys.readouterr().err
    assert f"{bad}/modelDescription.xml:12:1: error: constant clock 'tick' needs intervalDecimal" in err
    assert '<Clock name="tick"' in err  # the excerpt of the line inside the archive


def test_every_platform_folder_is_checked(built, tmp_path):
    """An empty platform folder, a folder that is no platform tuple, and a Linux library exporting
    more than the FMI functions; the host's binary is intact."""
    from robogen import toolchain

    (tmp_path / "leak.c").write_text('__attribute__((visibility("default"))) int helper(void);\nint helper(void) { return 1; }\n')
    with zipfile.ZipFile(built["trivial"]) as z:
        host = z.read("binaries/x86_64-linux/trivial.so")
    leak = toolchain.compile_shared([tmp_path / "leak.c"], tmp_path / "leak.so")
    fmu = rewrite(built["trivial"], tmp_path / "folders.fmu", **{
        "binaries__aarch64-linux__README_DOT_txt": b"no library here",
        "binaries__amd64-freebsd__trivial_DOT_so": host,
        "binaries__x86_64-linux__trivial_DOT_so": leak.read_bytes(),
    })
    found = messages(fmu)
    assert ("error", 1, "'binaries/aarch64-linux' holds no trivial.so, the library of modelIdentifier 'trivial' for aarch64-linux") in found
    assert ("warning", 1, "'binaries/amd64-freebsd' is not an FMI 3.0 platform tuple (<arch>-<sys>, such as 'x86_64-linux'); "
                          "its files are not checked") in found
    assert ("warning", 1, "the binary exports 1 name(s) besides the FMI 3.0 functions (helper); they can clash with other "
                          "libraries in the importer's process") in found


def test_a_program_is_not_a_library(built, tmp_path):
    """A position-independent executable is an ELF file of the library's type (DYN): its PIE flag
    tells it apart, as the dynamic loader itself does."""
    from robogen import toolchain

    (tmp_path / "main.c").write_text("int main(void) { return 0; }\n")
    program = toolchain.compile_program([tmp_path / "main.c"], tmp_path / "main", extra=["-fPIE", "-pie"])
    fmu = rewrite(built["trivial"], tmp_path / "program.fmu", **{"binaries__x86_64-linux__trivial_DOT_so": program.read_bytes()})
    assert ("error", 1, "the binary is an executable, not a shared library: an importer cannot load it") in messages(fmu)
    fmu = rewrite(built["trivial"], tmp_path / "text.fmu", **{"binaries__x86_64-linux__trivial_DOT_so": b"#!/bin/sh\n"})
    assert ("error", 1, "cannot read the binary: not an ELF, PE or Mach-O file") in messages(fmu)
