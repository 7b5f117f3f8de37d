"""The engine (engine_values.c, engine_run.c, engine_events.c) under AddressSanitizer and UndefinedBehaviorSanitizer:
the library built with the sanitizers, loaded into a Python process of its own (libasan preloaded),
runs systems with events, connections, early return, a failing FMU and Zeno behaviour in every
way it stores rows, and gives the Python loop's results; any finding ends that process."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from robogen import toolchain
from robogen.cosim import engine

from test_cosim_engine import RELAYS, SUFFIXES, SYSTEMS

DRIVER = textwrap.dedent("""
    import os, sys
    from pathlib import Path
    from robogen.cosim import engine, simulate_system, schema
    from robogen.diagnostics import RobogenError
    library = schema.ffi.dlopen(sys.argv[1])
    engine._library = lambda: library
    def run(path, loop, **kwargs):
        if loop == "Python":
            os.environ["ROBOGEN_REFERENCE_LOOP"] = "1"
        else:
            os.environ.pop("ROBOGEN_REFERENCE_LOOP", None)
        try:
            result = simulate_system(path, **kwargs)
            return result.rows, (result.stats.steps, result.stats.instants, result.stats.terminated_by)
        except RobogenError as exc:
            return None, exc.diagnostics[0].message
    for path in sys.argv[2:]:
        python = run(path, "Python", output=path + ".py.csv")
        assert run(path, "C", output=path + ".c.csv") == python, path
        assert Path(path + ".c.csv").read_bytes() == Path(path + ".py.csv").read_bytes(), path
        assert run(path, "C", output=path + ".text.csv", keep_rows=False)[1] == python[1], path
        assert Path(path + ".text.csv").read_bytes() == Path(path + ".py.csv").read_bytes(), path
        assert run(path, "C", keep_rows=False)[1] == python[1], path
        print("ok", path)
""")


def _libasan() -> str | None:
    result = subprocess.run([*toolchain.compiler(), "-print-file-name=libasan.so"], capture_output=True, text=True)
    path = result.stdout.strip()
    return path if result.returncode == 0 and os.path.isabs(path) and os.path.exists(path) else None


def test_the_c_loops_run_clean_under_the_sanitizers(tmp_path, write_system):
    libasan = _libasan()
    if libasan is None:
        pytest.skip("no AddressSanitizer runtime for this compiler")
    source = tmp_path / "engine_all.c"
    source.write_bytes(engine.source())
    library = toolchain.compile_shared([source], tmp_path / "engine_sanitized.so", sanitize=True,
                                       what="the engine under the sanitizers")
    links = ", ".join(['"a.out -> b.tin"'] + [f'"a.c_{x} -> b.ci_{x}", "a.y_{x} -> b.u_{x}"' for x in SUFFIXES])
    systems = {**{name: SYSTEMS[name] for name in ("stair", "ticker", "ball", "relay-chain-stepwise", "ticker-setcount")},
               "types": f"connections = [{links}]\n[experiment]\nstop = 1.2\nstep = 0.1\n"
                        '[instances.a]\nfmu = "{alltypes}"\n[instances.b]\nfmu = "{alltypes}"\n',
               "relay-chain": RELAYS.format(stepwise="false"),
               "fail": '[experiment]\nstop = 2.0\nstep = 0.1\n[instances.k]\nfmu = "{ticker}"\n[instances.f]\nfmu = "{failer}"\n',
               "zeno": '[experiment]\nstop = 3.0\nstep = 0.1\nmax_event_iterations = 20\n[instances.z]\nfmu = "{zeno}"\n'}
    paths = [str(write_system(text, name=f"{name}.toml")) for name, text in systems.items()]
    # PYTHONMALLOC=malloc: the cffi arrays the loops work in are malloc'd, where ASan sees past their ends
    env = {**os.environ, "LD_PRELOAD": libasan, "ASAN_OPTIONS": "detect_leaks=0:halt_on_error=1", "PYTHONMALLOC": "malloc",
           "UBSAN_OPTIONS": "halt_on_error=1:print_stacktrace=1", "PYTHONPATH": str(Path(__file__).parent)}
    proc = subprocess.run([sys.executable, "-c", DRIVER, str(library), *paths], capture_output=True, text=True,
                          timeout=600, env=env)
    assert proc.returncode == 0, proc.stderr[-4000:]
    assert proc.stdout.count("ok ") == len(paths)
    assert "runtime error" not in proc.stderr and "AddressSanitizer" not in proc.stderr
