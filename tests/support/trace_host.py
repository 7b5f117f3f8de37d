"""The cross-platform test host (trace_host.c): built with robogen's toolchain for each platform
it runs on here, fed a scenario of :mod:`support.codegen_driver` as its script, run natively, under
wine (Windows) or under qemu-user (aarch64 Linux), and its transcript read back as a trace.

- :func:`build_host` compiles the host for a platform (the same source and house flags as every
  C program of ours; zig for the platforms other than the host's);
- :func:`script` writes the commands of a scenario for an FMU's description;
- :class:`Runner` runs a host on a binary of its platform, or says why it cannot here
  (``Runner.missing``: wine or qemu-user not installed), for the tests to skip with that reason;
- :func:`parse` turns a transcript into the comparable form of :class:`codegen_driver.Trace`.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

from robogen import toolchain
from robogen.fmu.headers import include_dir
from robogen.fmu.platforms import HOST, Platform

from support.codegen_driver import COUNTERS, Description, Scenario

HERE = Path(__file__).resolve().parent
SOURCE = HERE / "trace_host.c"
ACCESS = {"Int64": "Int64", "Enumeration": "Int64", "UInt64": "UInt64", "Float64": "Float64", "Boolean": "Boolean"}
#: Debian's aarch64 C library (the libc6-arm64-cross package), the root qemu-user loads it from
AARCH64_ROOT = Path("/usr/aarch64-linux-gnu")


def build_host(platform: Platform, folder: Path) -> Path:
    name = "trace_host.exe" if platform.system == "windows" else "trace_host"
    libs = ["-ldl"] if platform.system == "linux" else []
    return toolchain.compile_program([SOURCE], folder / platform.name / name, platform=platform,
                                     system_includes=[include_dir()], libs=libs, what=f"the trace host for {platform}")


def _ref(var) -> str:
    if var.type not in ACCESS or var.size != 1:
        raise ValueError(f"the trace host reads scalar {', '.join(ACCESS)} values, not {var.name} ({var.type}[{var.size}])")
    return f"{ACCESS[var.type]}:{var.vr}"


def script(desc: Description, scenario: Scenario) -> str:
    """The host's commands for ``scenario`` (early ticks only), after a ``load`` line the runner adds.
    Every super-dense step reads the ticking output clocks with their values, the machine states,
    the observed variables and the counters, as :class:`codegen_driver.FmuRunner` does."""
    lines = [f"instantiate {desc.token}"]
    for clock in desc.output_clocks:
        lines.append(" ".join(["watch", str(desc.by_name[clock].vr), *(_ref(v) for v in desc.clocked[clock])]))
    observed = [*desc.states, *desc.observed, *(desc.by_name[n] for n in COUNTERS)]
    lines += [" ".join(["observe", *(_ref(v) for v in observed)]), "init", "exit_init"]
    h = desc.interval / 2 if scenario.half else desc.interval
    for i, instant in enumerate(scenario):
        if instant.late:
            raise ValueError("the trace host sets inputs before an instant's first read only")
        if i > 0:
            lines.append(f"step {(i - 1) * h!r} {h!r}")
        if instant.periodic:
            lines.append(f"clock {desc.by_name[desc.periodic].vr}")
        for tick in instant.early:
            lines.append(f"clock {desc.by_name[tick.clock].vr}")
            for name, value in tick.payload.items():
                var = desc.by_name[name]
                text = str(int(value)) if var.type == "Boolean" else repr(value)
                lines.append(f"set {ACCESS[var.type]} {var.vr} {text}")
        lines.append(f"settle {i}")
    return "\n".join([*lines, "free", ""])


@dataclass
class Runner:
    """How to run a host of ``platform`` here: a command prefix, or why there is none."""

    platform: Platform
    prefix: list[str] = field(default_factory=list)
    env: dict[str, str] = field(default_factory=dict)
    missing: str | None = None

    def run(self, host: Path, library: Path, commands: str, timeout: float = 300) -> str:
        """The transcript of ``commands`` run by ``host`` on ``library`` (a binary of this platform)."""
        if self.platform.system == "windows":  # LoadLibrary finds the DLL beside the program
            shutil.copyfile(library, host.parent / library.name)
            target = library.name
        else:
            target = str(library)
        result = subprocess.run([*self.prefix, str(host)], input=f"load {target}\n{commands}", capture_output=True,
                                text=True, timeout=timeout, cwd=host.parent, env={**os.environ, **self.env})
        assert result.returncode == 0, (result.returncode, result.stdout[-2000:], result.stderr[-2000:])
        return result.stdout


def runner(platform: Platform, wine_prefix: Path) -> Runner:
    """The runner of ``platform``: natively on the host, wine for Windows, qemu-user for aarch64 Linux."""
    if platform == HOST:
        return Runner(platform)
    if platform.name == "x86_64-windows":
        wine = shutil.which("wine64") or shutil.which("wine") or _existing("/usr/lib/wine/wine64")
        if wine is None:
            return Runner(platform, missing="wine is not installed (Debian: apt-get install wine64)")
        # a private prefix; no Mono or Gecko installer prompts, no debug chatter
        return Runner(platform, [wine], {"WINEPREFIX": str(wine_prefix), "WINEDEBUG": "-all",
                                         "WINEDLLOVERRIDES": "mscoree,mshtml="})
    if platform.name == "aarch64-linux":
        qemu = shutil.which("qemu-aarch64") or shutil.which("qemu-aarch64-static")
        if qemu is None:
            return Runner(platform, missing="qemu-user is not installed (Debian: apt-get install qemu-user)")
        if not (AARCH64_ROOT / "lib" / "libc.so.6").is_file():
            return Runner(platform, missing=f"no aarch64 C library in {AARCH64_ROOT} (Debian: apt-get install libc6-arm64-cross)")
        return Runner(platform, [qemu, "-L", str(AARCH64_ROOT)])
    return Runner(platform, missing=f"robogen's tests cannot run {platform} binaries on this machine")


def end_wineserver(prefix: Path) -> None:
    """End the wineserver of ``prefix`` (the tests' own), if one was started, instead of
    leaving it to time out."""
    server = shutil.which("wineserver") or _existing("/usr/lib/wine/wineserver")
    if server is not None and (prefix / "system.reg").exists():
        subprocess.run([server, "-k"], env={**os.environ, "WINEPREFIX": str(prefix)}, capture_output=True, timeout=60,
                       check=False)


def _existing(path: str) -> str | None:
    return path if Path(path).is_file() else None


def parse(transcript: str, desc: Description) -> list:
    """The transcript as :meth:`codegen_driver.Trace.comparable` gives a trace: per super-dense
    step (instant, k, outputs, states, variables, cycles, dropped, misses, need)."""
    by_vr = {v.vr: v for v in desc.vars}
    state_names = {v.name for v in desc.states}
    steps: list = []
    current: dict | None = None
    clock: str | None = None
    for line in transcript.splitlines():
        words = line.split()
        if words[0] == "instant":
            current = {"instant": int(words[1]), "k": int(words[3]), "outputs": {}, "values": {}}
            clock = None
        elif words[0] == "tick":
            clock = by_vr[int(words[1])].name
            current["outputs"][clock] = {}
        elif ":" in words[0] and "=" in words[0]:
            ref, text = words[0].split("=", 1)
            var = by_vr[int(ref.split(":")[1])]
            value = _value(var.type, text)
            if clock is not None and var.clock == clock:
                current["outputs"][clock][var.name] = value
            else:
                clock = None
                current["values"][var.name] = value
        elif words[0] == "need":
            values = current["values"]
            states = {n: values.pop(n) for n in list(values) if n in state_names}
            counters = [values.pop(n) for n in COUNTERS]
            outputs = {c: dict(sorted(v.items())) for c, v in sorted(current["outputs"].items())}
            steps.append((current["instant"], current["k"], outputs, states, dict(sorted(values.items())), *counters,
                          words[1] == "1"))
    return steps


def _value(fmi_type: str, text: str):
    if fmi_type == "Float64":
        return float(text)
    if fmi_type == "Boolean":
        return text == "1"
    return int(text)


__all__ = ["build_host", "script", "Runner", "runner", "parse", "end_wineserver", "AARCH64_ROOT"]
