"""The API-misuse suite (misuse.c): a C importer that calls the test FMUs wrongly on purpose.

Run twice: against the normal binaries, and with AddressSanitizer + UndefinedBehaviorSanitizer +
LeakSanitizer (FMUs and harness both instrumented), so that any invalid memory access, undefined
behaviour or leak in the runtime - including in 1,000 instantiate/free cycles - fails the test.
Sanitizers cannot run inside this Python process, hence the separate C program.
"""

from __future__ import annotations

import os
import re
import subprocess
from pathlib import Path

import pytest

from robogen import toolchain
from robogen.fmu.headers import include_dir

HERE = Path(__file__).resolve().parent

SANITIZER_ENV = {
    "ASAN_OPTIONS": "detect_leaks=1:halt_on_error=1:abort_on_error=0",
    "UBSAN_OPTIONS": "halt_on_error=1:print_stacktrace=1",
    "LSAN_OPTIONS": "",
}

# Calls with a NULL or dead instance cannot reach a logMessage callback: the runtime reports
# them on stderr (one line each, in this order in misuse.c).
BAD_HANDLE_REPORTS = [
    "fmi3DoStep called with a NULL instance",
    "fmi3GetFloat64 called with a NULL instance",
    "fmi3FreeInstance called with an instance that is not live",
    "fmi3DoStep called with an instance that is not live",
    "fmi3GetFloat64 called with an instance that is not live",
    "fmi3Reset called with an instance that is not live",
]


def build_program(sources: list[Path], output: Path, *, sanitize: bool) -> Path:
    args = [
        *toolchain.CFLAGS,
        "-O1",
        *(toolchain.SANITIZE_FLAGS if sanitize else ()),
        "-I",
        str(include_dir()),
        "-I",
        str(HERE.parent / "harness"),  # misuse_harness.h, shared with tests/codegen/misuse_generated.c
        *map(str, sources),
        "-o",
        str(output),
        "-ldl",
        "-lm",
    ]
    toolchain.run_compiler(args, f"test program {output.name}")
    return output


def run(program: Path, *args: Path, sanitize: bool) -> subprocess.CompletedProcess:
    env = {key: value for key, value in os.environ.items() if key not in SANITIZER_ENV and key != "LD_PRELOAD"}
    if sanitize:
        env.update(SANITIZER_ENV)
    return subprocess.run([str(program), *map(str, args)], capture_output=True, text=True, timeout=120, env=env)


def check_suite(result: subprocess.CompletedProcess) -> None:
    lines = result.stdout.splitlines()
    cases = [line for line in lines if re.match(r"(not )?ok \d+ - (misuse|check): ", line)]
    failed = [line for line in cases if line.startswith("not ok")]
    assert result.returncode == 0, "\n".join(failed + lines[-3:] + result.stderr.splitlines()[-40:])
    assert not failed
    misuse = [line for line in cases if " - misuse: " in line]
    assert lines[-1] == f"# cases {len(cases)} misuse {len(misuse)} failures 0"
    assert len(misuse) >= 30
    reports = [line for line in result.stderr.splitlines() if line.startswith("robogen FMU ")]
    assert len(reports) == len(BAD_HANDLE_REPORTS)
    for report, expected in zip(reports, BAD_HANDLE_REPORTS):
        assert expected in report


def test_misuse_suite(counter_fmu, plain_fmu, tmp_path):
    program = build_program([HERE / "misuse.c"], tmp_path / "misuse", sanitize=False)
    check_suite(run(program, counter_fmu.library, plain_fmu.library, sanitize=False))


def test_leak_sanitizer_is_effective_here(tmp_path):
    """Canary: a program that leaks must fail under the same flags and environment."""
    source = tmp_path / "leak.c"
    source.write_text(
        "#include <stdlib.h>\n"
        "void *volatile sink;\n"
        "int main(void) { sink = malloc(32); sink = NULL; return 0; }\n"
    )
    result = run(build_program([source], tmp_path / "leak", sanitize=True), sanitize=True)
    assert result.returncode != 0
    assert "LeakSanitizer: detected memory leaks" in result.stderr


@pytest.mark.slow
def test_misuse_suite_under_sanitizers(sanitized_fmus, tmp_path):
    counter, plain = sanitized_fmus
    program = build_program([HERE / "misuse.c"], tmp_path / "misuse_sanitized", sanitize=True)
    result = run(program, counter.library, plain.library, sanitize=True)
    check_suite(result)
    for finding in ("AddressSanitizer", "LeakSanitizer", "runtime error:"):
        assert finding not in result.stderr
