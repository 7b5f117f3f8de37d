"""Property 5: the generated C runs the model's scenarios clean under AddressSanitizer and
UndefinedBehaviorSanitizer.

The FMU's unity source is compiled together with ``replay.c`` (a small FMI host that replays
scenarios from a script, making the same calls as :class:`robogen.differential.FmuRunner`) into
one program with the sanitizer flags of :mod:`robogen.toolchain`. The program must exit 0 with no
sanitizer report, and each scenario must take as many super-dense steps, and stop at the same
error, as it did in the differential test.
"""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

from robogen import differential, toolchain
from robogen.codegen import binary
from robogen.fmu.headers import include_dir

HARNESS = Path(__file__).resolve().parent / "replay.c"
ENV = {
    "ASAN_OPTIONS": "detect_leaks=1:halt_on_error=1:abort_on_error=0",
    "UBSAN_OPTIONS": "halt_on_error=1:print_stacktrace=1",
}
TYPES = {"Float64": "f64", "Int64": "i64", "Enumeration": "i64", "UInt64": "u64", "Boolean": "bool", "String": "str"}


def _value(kind: str, v) -> str:
    if kind == "f64":
        return float(v).hex()
    if kind == "bool":
        return "1" if v else "0"
    if kind == "str":
        return str(v).encode("utf-8").hex() or "-"
    return str(int(v))


def _group(prefix: str, vars_: list[differential.Var]) -> list[str]:
    by: dict[str, list[differential.Var]] = {}
    for v in vars_:
        by.setdefault(TYPES[v.type], []).append(v)
    return [f"{prefix} {kind} {sum(v.size for v in vs)} {' '.join(str(v.vr) for v in vs)}" for kind, vs in by.items()]


def script(desc: differential.Description, scenarios: list[differential.Scenario]) -> str:
    """The replay script of ``scenarios`` (see replay.c)."""
    lines = [f"token {desc.token}"]
    lines += _group("get", desc.states + desc.observed + [desc.by_name[n] for n in differential.COUNTERS])
    for c in desc.output_clocks:
        lines.append(f"clock {desc.by_name[c].vr}")
        lines += _group("clocked", desc.clocked[c])
    # a time-free RoboChart FMU (--time skip) has no periodic clock: its tocks are due by time, on
    # the grid the replay steps on, and nothing is set for them (vr 0 stands for the clock unused)
    ticking = desc.periodic is not None
    for scenario in scenarios:
        lines.append(f"periodic {desc.by_name[desc.periodic].vr if ticking else 0} {float(desc.interval).hex()} {int(scenario.half)}")
        lines.append("scenario")
        for instant in scenario:
            lines.append(f"instant {int(instant.periodic and ticking)}")
            for tick, at in [(t, -1) for t in instant.early] + [(t, t.at) for t in instant.late]:
                lines.append(f"tick {at} {desc.by_name[tick.clock].vr}")
                for name, value in tick.payload.items():
                    var = desc.by_name[name]
                    values = value if isinstance(value, list) else [value]
                    kind = TYPES[var.type]
                    lines.append(f"set {at} {kind} {var.vr} {len(values)} " + " ".join(_value(kind, x) for x in values))
        lines.append("end")
    return "\n".join(lines) + "\n"


def expected(trace: differential.Trace) -> str:
    """The line replay.c prints for a run with this trace."""
    error = trace.error
    return f"run {len(trace.steps)} {error.instant if error else -1} {error.k if error else -1}"


def sanitize(folder: Path, traces: list[differential.Trace], scenarios: list[differential.Scenario], work: Path) -> str | None:
    """Build the FMU unpacked in ``folder`` with the sanitizers, replay ``scenarios`` (whose FMU
    traces are ``traces``): None when clean, else what went wrong."""
    work.mkdir(parents=True, exist_ok=True)
    desc = differential.Description(folder)
    sources = folder / "sources"
    program = toolchain.compile_program([HARNESS, sources / f"{desc.identifier}.c"], work / "replay",
                                        includes=[sources, binary.runtime_dir(), include_dir()], libs=["-lm"],
                                        sanitize=True, what=f"the sanitized replay of FMU '{desc.identifier}'")
    path = work / "scenarios.txt"
    path.write_text(script(desc, scenarios), encoding="utf-8")
    env = {k: v for k, v in os.environ.items() if k not in ENV and k != "LD_PRELOAD"}
    env.update(ENV)
    try:
        result = subprocess.run([str(program), str(path)], capture_output=True, text=True, timeout=120, env=env)
    except subprocess.TimeoutExpired:
        return "the sanitized replay did not finish in 120 s"
    if result.returncode != 0 or "runtime error" in result.stderr or "Sanitizer" in result.stderr:
        return f"the sanitized replay failed (exit {result.returncode}):\n{result.stderr[-3000:]}"
    got = [line for line in result.stdout.splitlines() if line.startswith(("run", "runaway"))]
    want = [expected(t) for t in traces]
    if got != want:
        first = next((i for i, (a, b) in enumerate(zip(got, want)) if a != b), min(len(got), len(want)))
        return f"the sanitized replay ran scenario {first} otherwise: {got[first:first + 1]} (expected {want[first:first + 1]})"
    return None


__all__ = ["sanitize", "script"]
