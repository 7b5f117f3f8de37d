"""The API-misuse suite (misuse_generated.c) against generated FMUs, under the sanitizers.

The UR5e d-model and arith.rst are generated, then their unity sources are compiled with
AddressSanitizer + UndefinedBehaviorSanitizer (+ LeakSanitizer) together with the C harness,
which calls them wrongly in more than 30 ways, reaches every run-time error of arith.rst, and
runs 1,000 instantiate/drive/free cycles. Any finding of a sanitizer fails the test. The value
references and tokens come from the FMUs' modelDescription.xml, through a generated header.
strings.rct's String variables have a program of their own (misuse_strings.c): the importer's
texts up to the capacity and beyond, in FMU states and serialised, and called wrongly.
"""

from __future__ import annotations

import os
import re
import subprocess
from pathlib import Path

import pytest

from support.codegen_driver import Description
from robogen import toolchain
from robogen.codegen import binary
from robogen.fmu.headers import include_dir

HERE = Path(__file__).resolve().parent

SANITIZER_ENV = {
    "ASAN_OPTIONS": "detect_leaks=1:halt_on_error=1:abort_on_error=0",
    "UBSAN_OPTIONS": "halt_on_error=1:print_stacktrace=1",
}


def header(ur5e: Description, arith: Description, ur5e_fmu) -> str:
    def vr(desc: Description, name: str) -> int:
        return desc.by_name[name].vr

    idle = next(n.id for n in ur5e_fmu.machines[0].nodes if n.label == "Idle")
    command_x = vr(ur5e, "moveDiscreteCommand.target_X")
    move_x = vr(ur5e, "movediscrete.target_X")
    # the harness reads the three arguments as consecutive value references
    assert [vr(ur5e, f"moveDiscreteCommand.target_{c}") for c in "XYZ"] == [command_x, command_x + 1, command_x + 2]
    assert [vr(ur5e, f"movediscrete.target_{c}") for c in "XYZ"] == [move_x, move_x + 1, move_x + 2]
    defines = {
        "UR5E_TOKEN": f'"{ur5e.token}"',
        "UR5E_VR_CYCLE": vr(ur5e, "cycle"),
        "UR5E_VR_COMMAND": vr(ur5e, "moveDiscreteCommand"),
        "UR5E_VR_COMMAND_X": command_x,
        "UR5E_VR_FEASIBLE": vr(ur5e, "feasibleMoveDiscreteCommand"),
        "UR5E_VR_COMPLETED": vr(ur5e, "moveCompleted"),
        "UR5E_VR_STOPPED": vr(ur5e, "robotStopped"),
        "UR5E_VR_MOVE": vr(ur5e, "movediscrete"),
        "UR5E_VR_MOVE_X": move_x,
        "UR5E_VR_STOP": vr(ur5e, "stop"),
        "UR5E_VR_STATE": vr(ur5e, "SimDiscreteGrippingArmMovement.state"),
        "UR5E_VR_LOCAL": vr(ur5e, "SimDiscreteGrippingArmMovement.margs.target_X"),
        "UR5E_IDLE": idle,
        "ARITH_TOKEN": f'"{arith.token}"',
        "ARITH_VR_CYCLE": vr(arith, "cycle"),
    }
    for operand in "abnx":
        defines[f"ARITH_VR_{operand.upper()}"] = vr(arith, operand)
        defines[f"ARITH_VR_{operand.upper()}_VALUE"] = vr(arith, f"{operand}.value")
    return "".join(f"#define {k} {v}\n" for k, v in defines.items())


def build_program(source: Path, extra_header: Path, output: Path, *, sanitize: bool) -> Path:
    args = [*toolchain.CFLAGS, "-O1", *(toolchain.SANITIZE_FLAGS if sanitize else ()), "-include", str(extra_header),
            "-I", str(include_dir()),
            "-I", str(Path(__file__).resolve().parent.parent / "harness"), str(source), "-o", str(output), "-ldl", "-lm"]
    toolchain.run_compiler(args, f"test program {output.name}")
    return output


def run(program: Path, *args: Path, sanitize: bool) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k not in SANITIZER_ENV and k != "LD_PRELOAD"}
    if sanitize:
        env.update(SANITIZER_ENV)
    return subprocess.run([str(program), *map(str, args)], capture_output=True, text=True, timeout=300, env=env)


def check_suite(result: subprocess.CompletedProcess) -> list[str]:
    lines = result.stdout.splitlines()
    cases = [line for line in lines if re.match(r"(not )?ok \d+ - (misuse|check): ", line)]
    failed = [line for line in cases if line.startswith("not ok")]
    assert result.returncode == 0, "\n".join(failed + lines[-3:] + result.stderr.splitlines()[-40:])
    assert not failed
    misuse = [line for line in cases if " - misuse: " in line]
    assert lines[-1] == f"# cases {len(cases)} misuse {len(misuse)} failures 0"
    assert len(misuse) >= 30
    for finding in ("AddressSanitizer", "LeakSanitizer", "runtime error:"):
        assert finding not in result.stderr
    # calls with a NULL or freed handle have no logger: one line each on stderr
    reports = [line for line in result.stderr.splitlines() if line.startswith("robogen FMU DiscreteGrippingArm: ")]
    assert [r.split(": ")[1].split(" called")[0] for r in reports] == \
        ["fmi3DoStep", "fmi3GetInt64", "fmi3FreeInstance", "fmi3DoStep", "fmi3GetClock", "fmi3Reset"]
    return cases


@pytest.mark.parametrize("sanitize", [False, pytest.param(True, marks=pytest.mark.slow)], ids=["plain", "sanitized"])
def test_misuse_of_generated_fmus(built, tmp_path, sanitize):
    ur5e, arith = built("ur5e", "exhaustive"), built("arith", "stepwise")
    libraries = []
    for b in (ur5e, arith):
        ident = b.fmu.model_identifier
        libraries.append(binary.compile_fmu_binary(b.folder / "sources", ident, tmp_path / f"{ident}.so", sanitize=sanitize))
    defines = tmp_path / "misuse_fmus.h"
    defines.write_text(header(ur5e.desc, arith.desc, ur5e.fmu))
    program = build_program(HERE / "misuse_generated.c", defines, tmp_path / "misuse_generated", sanitize=sanitize)
    cases = check_suite(run(program, *libraries, sanitize=sanitize))
    assert any("model error: division by zero" in c for c in cases)
    assert any("1000 instantiate/free cycles" in c for c in cases)


@pytest.mark.parametrize("sanitize", [False, pytest.param(True, marks=pytest.mark.slow)], ids=["plain", "sanitized"])
def test_string_variables_called_rightly_and_wrongly(built, tmp_path, sanitize):
    strings = built("strings", "exhaustive")
    ident = strings.fmu.model_identifier
    library = binary.compile_fmu_binary(strings.folder / "sources", ident, tmp_path / f"{ident}.so", sanitize=sanitize)
    desc = strings.desc
    defines = {"STRINGS_TOKEN": f'"{desc.token}"', "STRINGS_CAPACITY": strings.fmu.capacity,
               **{f"STRINGS_VR_{key}": desc.by_name[name].vr for key, name in (
                   ("NAME", "name.value"), ("GREETING", "Greeter.greeting"), ("REPLY", "reply.value"),
                   ("STATE", "Greeter.state"))}}
    header_file = tmp_path / "strings_fmu.h"
    header_file.write_text("".join(f"#define {k} {v}\n" for k, v in defines.items()))
    program = build_program(HERE / "misuse_strings.c", header_file, tmp_path / "misuse_strings", sanitize=sanitize)
    result = run(program, library, sanitize=sanitize)
    lines = result.stdout.splitlines()
    failed = [line for line in lines if line.startswith("not ok")]
    assert result.returncode == 0 and not failed, "\n".join(failed + lines[-3:] + result.stderr.splitlines()[-40:])
    cases = [line for line in lines if line.startswith("ok ")]
    assert len(cases) == 16 and lines[-1] == "# cases 16 misuse 7 failures 0"
    for finding in ("AddressSanitizer", "LeakSanitizer", "runtime error:"):
        assert finding not in result.stderr
