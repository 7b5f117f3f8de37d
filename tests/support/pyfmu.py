"""Helpers for driving FMUs in the pyfmu and platforms tests: fmpy's FMU3Slave with captured log
messages, and the C host of host.c (dlopen with RTLD_LOCAL, in a separate clean process)."""

from __future__ import annotations

import os
import subprocess
import zipfile
from ctypes import c_uint32
from pathlib import Path
from typing import Iterable, Sequence

from fmpy import extract, read_model_description
from fmpy.fmi3 import FMU3Slave, fmi3Float64, fmi3IntervalQualifier

from robogen import toolchain
from robogen.fmu.headers import include_dir

HERE = Path(__file__).resolve().parent


def compile_host(directory: Path) -> Path:
    target = directory / "fmi3host"
    toolchain.compile_program([HERE / "host.c"], target, includes=[include_dir()], libs=["-ldl"], what="the C host")
    return target


def unzip(fmu: Path, directory: Path) -> Path:
    directory.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(fmu) as z:
        z.extractall(directory)
    return directory


def run_host(host: Path, script: Sequence[str], timeout: float = 120) -> str:
    """Run the C host on a script in a clean environment (no PYTHONPATH, no virtualenv)."""
    env = {"PATH": "/usr/bin:/bin", "HOME": os.environ.get("HOME", "/tmp")}
    result = subprocess.run([str(host)], input="\n".join(script) + "\n", capture_output=True, text=True, env=env,
                            timeout=timeout)
    return result.stdout + result.stderr


class Fmu:
    """One FMU instance through fmpy, by variable name, with the log messages kept."""

    def __init__(self, path: Path, name: str = "instance", *, early_return: bool = True, logging: bool = True,
                 event_mode: bool = True, unzip_dir: Path | None = None) -> None:
        self.description = read_model_description(str(path))
        self.vr = {v.name: v.valueReference for v in self.description.modelVariables}
        self.directory = str(unzip(path, unzip_dir)) if unzip_dir else extract(str(path))
        self.logs: list[tuple[int, str, str]] = []
        self.slave = FMU3Slave(guid=self.description.guid, unzipDirectory=self.directory,
                               modelIdentifier=self.description.coSimulation.modelIdentifier, instanceName=name)
        self.slave.instantiate(loggingOn=logging, eventModeUsed=event_mode, earlyReturnAllowed=early_return,
                               logMessage=self._log)

    def _log(self, env, status, category, message) -> None:
        self.logs.append((int(status), category.decode(), message.decode()))

    def messages(self, status: int | None = None) -> list[str]:
        return [m for s, _, m in self.logs if status is None or s == status]

    def vrs(self, names: Iterable[str]) -> list[int]:
        return [self.vr[n] for n in names]

    def clocks(self, *names: str) -> dict[str, bool]:
        return dict(zip(names, self.slave.getClock(self.vrs(names))))

    def active(self, *names: str) -> set[str]:
        return {n for n, on in self.clocks(*names).items() if on}

    def set_clocks(self, *names: str) -> None:
        self.slave.setClock(self.vrs(names), [True] * len(names))

    def f64(self, *names: str) -> list[float]:
        return list(self.slave.getFloat64(self.vrs(names)))

    def i64(self, *names: str) -> list[int]:
        return list(self.slave.getInt64(self.vrs(names)))

    def set_f64(self, **values: float) -> None:
        self.slave.setFloat64(self.vrs(values), list(values.values()))

    def set_i64(self, values: dict[str, int]) -> None:
        self.slave.setInt64(self.vrs(values), list(values.values()))

    def interval(self, name: str) -> tuple[float, int]:
        vrs = (c_uint32 * 1)(self.vr[name])
        intervals = (fmi3Float64 * 1)()
        qualifiers = (fmi3IntervalQualifier * 1)()
        self.slave.getIntervalDecimal(vrs, intervals, qualifiers)
        return intervals[0], qualifiers[0]

    def close(self) -> None:
        """Terminate and free the instance; after an fmi3Error (logged with status 3) the FMU is
        Terminated already, and fmi3Terminate would be refused."""
        if not self.messages(3):
            self.slave.terminate()
        self.slave.freeInstance()
