"""ECOS, the C++ co-simulation engine of the ``ecospy`` package, as the peer of robogen's master in
bench/bench_master.py: the chain of trivial FMUs as an SSP 1.0 archive, and ECOS's command line
run on it in a process of its own.

The ``bench`` extra installs ECOS and TBB (``make bench``); nothing is installed here. The wheel
ships the ``ecos`` program without its execute bit, so it runs from a copy in the benchmark's
folder, with TBB's library folder on ``LD_LIBRARY_PATH`` (set for that process only). ECOS's
limits (docs/benchmarks.md): no clocks, and its progress counter divides by zero under 10 steps.
"""

from __future__ import annotations

import importlib.metadata
import importlib.util
import os
import shutil
import stat
import subprocess
import time
import zipfile
from pathlib import Path

#: ECOS's progress counter divides by zero for runs of fewer steps.
MIN_STEPS = 10


class Ecos:
    """The ECOS program and the environment it runs in."""

    def __init__(self, program: Path, env: dict[str, str]):
        self.program, self.env = program, env

    @classmethod
    def find(cls, folder: Path) -> Ecos | str:
        """ECOS, copied into ``folder``; or why it cannot run (a sentence)."""
        spec = importlib.util.find_spec("ecospy")
        if spec is None or spec.origin is None:
            return "ecospy is not installed (make bench installs the bench extra)"
        binaries = Path(spec.origin).parent / "binaries"
        try:
            tbb = next((f for f in importlib.metadata.files("tbb") or () if f.name.startswith("libtbb.so")), None)
        except importlib.metadata.PackageNotFoundError:
            tbb = None
        if tbb is None or not (binaries / "ecos").is_file():
            return "tbb is not installed, or ecospy has no ecos program (make bench installs the bench extra)"
        program = folder / "ecos"
        shutil.copyfile(binaries / "ecos", program)
        program.chmod(program.stat().st_mode | stat.S_IXUSR)
        paths = [str(Path(tbb.locate()).resolve().parent), str(binaries), os.environ.get("LD_LIBRARY_PATH", "")]
        return cls(program, dict(os.environ, LD_LIBRARY_PATH=os.pathsep.join(p for p in paths if p)))

    def version(self) -> str:
        done = subprocess.run([str(self.program), "--version"], env=self.env, capture_output=True, text=True, check=False)
        return (done.stdout or done.stderr).strip().splitlines()[-1] if (done.stdout or done.stderr) else "?"

    def simulate(self, ssp: Path, stop: float, step: float, csv: bool, folder: Path, parallel: bool = True) -> float:
        """Wall seconds of one ``ecos simulate`` of the archive (in ``folder``, where its CSV goes);
        ``parallel``: ECOS's default, its FMUs stepped by TBB's threads (else --noParallel)."""
        if round(stop / step) < MIN_STEPS:
            raise ValueError(f"ECOS needs at least {MIN_STEPS} steps")
        folder.mkdir(parents=True, exist_ok=True)
        args = [str(self.program), "simulate", "--path", str(ssp), "--stopTime", repr(stop), "--stepSize", repr(step),
                "--logLevel", "off", *([] if csv else ["--noCsv"]), *([] if parallel else ["--noParallel"])]
        t0 = time.perf_counter()
        done = subprocess.run(args, cwd=folder, env=self.env, capture_output=True, text=True, check=False)
        elapsed = time.perf_counter() - t0
        if done.returncode != 0:
            raise RuntimeError(f"ecos failed ({done.returncode}): {done.stderr[-2000:]}")
        return elapsed


def chain_ssp(fmu: Path, n: int, target: Path) -> Path:
    """An SSP 1.0 archive of ``n`` copies of the trivial FMU, ``y`` of each to ``u`` of the next."""
    components = "".join(
        f'      <ssd:Component name="t{i}" source="resources/{fmu.name}">\n'
        '        <ssd:Connectors>\n'
        '          <ssd:Connector name="u" kind="input"><ssc:Real/></ssd:Connector>\n'
        '          <ssd:Connector name="y" kind="output"><ssc:Real/></ssd:Connector>\n'
        '        </ssd:Connectors>\n'
        '      </ssd:Component>\n' for i in range(n))
    connections = "".join(f'      <ssd:Connection startElement="t{i}" startConnector="y" endElement="t{i + 1}" '
                          'endConnector="u"/>\n' for i in range(n - 1))
    ssd = ('<?xml version="1.0" encoding="UTF-8"?>\n'
           '<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription"\n'
           '    xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" version="1.0" name="chain">\n'
           '  <ssd:System name="chain">\n    <ssd:Elements>\n' + components + '    </ssd:Elements>\n'
           '    <ssd:Connections>\n' + connections + '    </ssd:Connections>\n  </ssd:System>\n'
           '</ssd:SystemStructureDescription>\n')
    with zipfile.ZipFile(target, "w") as archive:
        archive.writestr("SystemStructure.ssd", ssd)
        archive.write(fmu, f"resources/{fmu.name}")
    return target


def chain_system(fmu: Path, n: int, stop: float, step: float) -> str:
    """The same chain as a robogen system file."""
    text = "connections = [\n" + "".join(f'  "t{i}.y -> t{i + 1}.u",\n' for i in range(n - 1)) + "]\n"
    text += f"[experiment]\nstop = {stop!r}\nstep = {step!r}\n"
    return text + "".join(f'[instances.t{i}]\nfmu = "{fmu}"\n' for i in range(n))
