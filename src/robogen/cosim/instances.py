"""One FMU instance as the master sees it: its binding, its clocks' timing, its value buffers.

A :class:`FmuInstance` owns the :class:`~robogen.cosim.fmi3.Binding`, the schedule of its time-based
input clocks (:class:`Periodic`, :class:`Aperiodic`), the value references it reads after a step
(grouped per type into one cffi buffer each, so a step costs one Get call per type) and the set
of its clocks active in the current super-dense instant.
"""

from __future__ import annotations

import math
import shutil
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from robogen.cosim.fmi3 import ffi, Binding, Library, LoadError, value_array, vr_array
from robogen.diagnostics import Note, RobogenError, Span
from robogen.fmu.extract import extract_fmu
from robogen.fmu.fmi import tolerance  # noqa: F401 (the master's)
from robogen.fmu.headers import PLATFORM_TUPLE
from robogen.fmu.modeldesc import ModelDescription, Variable, load_model_description

PERIODIC = ("constant", "fixed", "tunable")
APERIODIC = ("changing", "countdown")


@dataclass
class Periodic:
    """A time-based periodic input clock: tick k at start + shift + k * interval (no running sum)."""

    var: Variable
    start: float
    interval: float
    shift: float
    k: int = 0

    def next_time(self) -> float:
        return self.start + self.shift + self.k * self.interval


@dataclass
class Aperiodic:
    """A changing or countdown input clock: next tick known from fmi3GetIntervalDecimal."""

    var: Variable
    next: float | None = None


@dataclass
class Reader:
    """One fmi3Get<Type> call that fills a buffer with several variables."""

    fmi_type: str
    vrs: list[int]
    index: dict[int, int] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.index = {vr: i for i, vr in enumerate(self.vrs)}
        self.c_vrs = vr_array(self.vrs)
        self.n = len(self.vrs)
        self.buffer = value_array(self.fmi_type, self.n)
        self.values = self.buffer if self.fmi_type != "String" else [""] * self.n

    def bind(self, inst: Binding) -> None:
        from robogen.cosim.fmi3 import ACCESSOR

        self.binding = inst
        self.function = "fmi3Get" + ACCESSOR[self.fmi_type]
        self.c_function = getattr(inst.lib, self.function)

    def read(self, inst: Binding) -> None:
        if inst.trace is not None:
            inst.get(self.fmi_type, self.c_vrs, self.n, self.buffer)
        else:
            status = self.c_function(inst.handle, self.c_vrs, self.n, self.buffer, self.n)
            if status > 1:
                inst._fail(self.function, status)
        if self.fmi_type == "String":
            self.values[:] = [ffi.string(p).decode("utf-8", "replace") if p != ffi.NULL else "" for p in self.buffer[0:self.n]]


class FmuCache:
    """Extracts each distinct .fmu once per run and loads each binary once."""

    def __init__(self) -> None:
        self.root = Path(tempfile.mkdtemp(prefix="robogen-sim-"))
        self.folders: dict[Path, Path] = {}
        self.models: dict[Path, ModelDescription] = {}
        self.libraries: dict[str, Library] = {}

    def load(self, fmu: Path, span: Span) -> tuple[Path, ModelDescription]:
        key = fmu.resolve()
        if key not in self.folders:
            if not fmu.is_file():
                raise RobogenError.at(f"FMU file not found: {fmu}", span)
            folder = extract_fmu(fmu, self.root / str(len(self.folders)))
            self.folders[key] = folder
            self.models[key] = load_model_description(folder, f"{fmu}/modelDescription.xml")
        return self.folders[key], self.models[key]

    def library(self, folder: Path, md: ModelDescription, span: Span) -> Library:
        ident = md.co_simulation.model_identifier
        path = folder / "binaries" / PLATFORM_TUPLE / f"{ident}.so"
        if not path.is_file():
            found = sorted(p.name for p in (folder / "binaries").iterdir()) if (folder / "binaries").is_dir() else []
            raise RobogenError.at(f"the FMU has no binary for this platform: binaries/{PLATFORM_TUPLE}/{ident}.so is missing",
                                  span, Note(f"platforms in the archive: {', '.join(found) or 'none'}"))
        key = str(path)
        if key not in self.libraries:
            try:
                self.libraries[key] = Library(key)
            except LoadError as exc:
                raise RobogenError.at(str(exc), span) from None
        return self.libraries[key]

    def close(self) -> None:
        shutil.rmtree(self.root, ignore_errors=True)


class FmuInstance:
    def __init__(self, name: str, md: ModelDescription, folder: Path, library: Library, span: Span, trace=None, log=None):
        self.name, self.md, self.folder, self.span = name, md, folder, span
        cs = md.co_simulation
        self.event_mode = cs.has_event_mode
        self.early = cs.might_return_early
        self.variable_step = cs.can_handle_variable_step
        self.can_state = cs.can_get_and_set_state
        self.binding = Binding(library, name, trace=trace, log=log)
        self.vars = md.by_name()
        self.by_vr = md.by_vr()
        self.time = 0.0
        self.periodic: list[Periodic] = []
        self.aperiodic: list[Aperiodic] = []
        self.next_event_time: float | None = None
        self.active: set[int] = set()  # clock vrs active in the current instant
        self.readers: list[Reader] = []
        self.reader_of: dict[int, tuple[Reader, int]] = {}
        self.out_clocks: list[int] = []
        self.out_clock_buffer = None
        self.failed_status: int | None = None  # set when a call returned Error/Fatal
        self.flags = (False, False, False, 0.0)

    def resource_path(self) -> str | None:
        res = self.folder / "resources"
        return str(res.resolve()) + "/" if res.is_dir() else None

    def observe(self, variables: list[Variable]) -> None:
        """Read these non-clocked variables (one call per type) after every step and instant."""
        by_type: dict[str, list[int]] = {}
        for v in variables:
            if not v.is_clock and not v.is_clocked and v.value_reference not in by_type.get(v.type, []):
                by_type.setdefault(v.type, []).append(v.value_reference)
        self.readers = [Reader(t, vrs) for t, vrs in sorted(by_type.items())]
        for r in self.readers:
            r.bind(self.binding)
        self.reader_of = {vr: (r, i) for r in self.readers for vr, i in r.index.items()}

    def watch_clocks(self, vrs: list[int]) -> None:
        self.out_clocks = sorted(set(vrs))
        self.out_clock_vrs = vr_array(self.out_clocks)
        self.out_clock_buffer = value_array("Clock", len(self.out_clocks))

    def read_outputs(self) -> None:
        inst = self.binding
        for r in self.readers:
            r.read(inst)

    def value(self, vr: int):
        r, i = self.reader_of[vr]
        return r.values[i]

    def read_clocks(self) -> list[int]:
        """Output clocks (of those watched) that read active now."""
        n = len(self.out_clocks)
        if not n:
            return []
        buf = self.out_clock_buffer
        self.binding.fmi3GetClock(self.out_clock_vrs, n, buf)
        return [vr for i, vr in enumerate(self.out_clocks) if buf[i]]

    def get_one(self, var: Variable):
        buf = value_array(var.type, 1)
        self.binding.get(var.type, vr_array([var.value_reference]), 1, buf)
        if var.type == "String":
            return ffi.string(buf[0]).decode("utf-8", "replace") if buf[0] != ffi.NULL else ""
        return buf[0]

    def set_values(self, fmi_type: str, vrs: list[int], values: list) -> None:
        if fmi_type == "String":
            keep = [ffi.new("char[]", str(v).encode()) for v in values]
            buf = ffi.new("const char*[]", keep)
        else:
            buf = ffi.new(f"{_ctype(fmi_type)}[]", values)
        self.binding.set(fmi_type, vr_array(vrs), len(vrs), buf)

    def set_clocks(self, vrs: list[int]) -> None:
        self.binding.fmi3SetClock(vr_array(vrs), len(vrs), ffi.new("bool[]", [True] * len(vrs)))
        self.active.update(vrs)

    def next_tick(self) -> float:
        times = [p.next_time() for p in self.periodic] + [a.next for a in self.aperiodic if a.next is not None]
        return min(times) if times else math.inf


def _ctype(fmi_type: str) -> str:
    from robogen.cosim.fmi3 import C_TYPES

    return C_TYPES[fmi_type]
