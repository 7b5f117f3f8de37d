"""The C programs built on tests/harness/misuse_harness.h: building them with the house flags
(optionally under the sanitizers), running them, and reading their per-case verdicts."""

from __future__ import annotations

import os
import re
import subprocess
from pathlib import Path
from typing import Sequence

from robogen import toolchain
from robogen.fmu.headers import include_dir
from support import ROOT

HARNESS = ROOT / "tests" / "harness"  # misuse_harness.h

SANITIZER_ENV = {
    "ASAN_OPTIONS": "detect_leaks=1:halt_on_error=1:abort_on_error=0",
    "UBSAN_OPTIONS": "halt_on_error=1:print_stacktrace=1",
    "LSAN_OPTIONS": "",
}
CASE = re.compile(r"(not )?ok (\d+) - (misuse|check): (.*)$")


def build_program(sources: Sequence[Path], output: Path, *, sanitize: bool) -> Path:
    """Compile a harness program: the house flags, FMI headers from fmpy, misuse_harness.h."""
    toolchain.run_compiler([
        *toolchain.CFLAGS, "-O1", *(toolchain.SANITIZE_FLAGS if sanitize else ()),
        "-I", str(include_dir()), "-I", str(HARNESS), *map(str, sources), "-o", str(output), "-ldl", "-lm",
    ], f"test program {output.name}")
    return output


def run(program: Path, *args: object, sanitize: bool, timeout: float = 120) -> subprocess.CompletedProcess:
    """Run ``program`` with the sanitizers' options only when asked for."""
    env = {key: value for key, value in os.environ.items() if key not in SANITIZER_ENV and key != "LD_PRELOAD"}
    if sanitize:
        env.update(SANITIZER_ENV)
    return subprocess.run([str(program), *map(str, args)], capture_output=True, text=True, timeout=timeout, env=env)


def verdicts(result: subprocess.CompletedProcess) -> dict[int, tuple[str, bool, str]]:
    """Case number -> (kind, passed, the rest of its line: name, and why it failed) from a run's
    output, after checking the closing count. A program runs its cases in a fixed order, so the
    number names a case across runs (a name may itself contain ': ')."""
    found = {}
    for line in result.stdout.splitlines():
        match = CASE.match(line)
        if match:
            found[int(match.group(2))] = (match.group(3), match.group(1) is None, match.group(4))
    failures = sum(1 for _, passed, _ in found.values() if not passed)
    misuse = sum(1 for kind, _, _ in found.values() if kind == "misuse")
    assert result.stdout.splitlines()[-1:] == [f"# cases {len(found)} misuse {misuse} failures {failures}"], \
        result.stdout[-2000:] + result.stderr[-2000:]
    return found
