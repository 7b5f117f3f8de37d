"""The API-misuse suite (misuse.c): a C importer that calls the test FMUs wrongly on purpose.

Run twice: against the normal binaries, and with AddressSanitizer + UndefinedBehaviorSanitizer +
LeakSanitizer (FMUs and harness both instrumented), so that any invalid memory access, undefined
behaviour or leak in the runtime - including in 1,000 instantiate/free cycles - fails the test.
Sanitizers cannot run inside this Python process, hence the separate C program.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from support.harness import build_program, run, verdicts

HERE = Path(__file__).resolve().parent

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


def check_suite(result) -> None:
    cases = verdicts(result)
    failed = [text for _, passed, text in cases.values() if not passed]
    assert result.returncode == 0, "\n".join(failed + result.stderr.splitlines()[-40:])
    assert not failed
    assert sum(1 for kind, _, _ in cases.values() if kind == "misuse") >= 30
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
