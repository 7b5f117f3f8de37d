"""The quiet stretch in C (stepper.c): :class:`CStretch`, one of the implementations of
:class:`robogen.cosim.stretch.Stretch`, for stretches without pacing. It steps every FMU, forwards
the connected non-clocked values (one fmi3Get<Type> call per FMU and type, one fmi3Set<Type> call
per target FMU and type for the inputs whose value changed, in dependency order) and records every
point, of every FMI type (Strings and Binaries as copies in an arena).

The library is compiled once with the system C compiler and cached under
``$XDG_CACHE_HOME/robogen`` (or ``~/.cache/robogen``), named by the hash of its source; if there is
no compiler, or ``ROBOGEN_NO_C_STEPPER`` is set, :func:`load` returns None and the master runs
the Python stretch, which computes the same results. Where the rows only go to a CSV file, the
loop writes the CSV lines itself (:attr:`Mode.TEXT`: floats in the shortest form that reads back,
as Python's repr); where they are kept, they come back as 8-byte slots turned into result rows a
column at a time (``memoryview`` slices). A chunk of rows ends by the recorder's next flush, at
most :data:`~robogen.cosim.recorder.FLUSH_SECONDS` of wall time away, so slow FMUs do not hold
rows back from the results file. While the loop runs it holds the values last set to the
connected inputs (:attr:`robogen.cosim.wiring.ValueExchange.last_set`), and hands them back when
it returns: an input is set only when its value changed, whichever loop set it last.
"""

from __future__ import annotations

import functools
import hashlib
import importlib.resources
import os
import re
import struct
import tempfile
import time
from enum import IntEnum
from itertools import repeat
from pathlib import Path
from typing import NamedTuple

import cffi

from robogen.cosim.fmi3 import ACCESSOR, C_TYPES
from robogen.cosim.fmi3 import ffi as fmi_ffi
from robogen.cosim.recorder import FLUSH_SECONDS
from robogen.cosim.stretch import StretchEnd, StretchPlan
from robogen.cosim.instances import FmuInstance, Reader
from robogen.cosim.wiring import CLOCK, UNSET, VALUE

_INCLUDE = re.compile(r'#include "(\w+\.h)"')


def package_file(name: str) -> str:
    """A file of the library: a C file, or a header of the C types shared with Python (read into
    cffi's declarations as well as compiled)."""
    return (importlib.resources.files("robogen.cosim") / name).read_text(encoding="utf-8")


ffi = cffi.FFI()
ffi.cdef(
    package_file("stepper.h")
    + """
    long rg_run_stretch(rg_stretch *s, double start, double h, long *n, double *t, double limit, long max_rows,
                        double deadline, double *times, uint64_t *slots, int *why, int *who, int *status);
    int rg_keep_last(rg_stretch *s, int link, const char *data, size_t size);
    size_t rg_format_double(char *out, double x);
    void rg_release(rg_stretch *s);
    """
)


#: Rows the loop stores before it hands them to the recorder.
CHUNK = 4096


class Why(IntEnum):
    """Why rg_run_stretch returned (stepper.c's enum of the same names)."""

    LIMIT = 0  # the next grid point is the horizon's
    EVENT = 1
    TERMINATE = 2
    STEP_FAILED = 3
    GET_FAILED = 4
    NO_MEMORY = 5  # no memory left for the Strings and Binaries of a chunk
    PAUSE = 6  # the chunk is full, or its wall-clock deadline passed: the rows go to the recorder
    SET_FAILED = 7


class Mode(IntEnum):
    """How the loop stores the rows (stepper.c's MODE_*), by where the recorder sends them."""

    SLOTS = 0  # 8-byte values: the rows are kept (Python builds them)
    TEXT = 1  # the CSV lines: the rows only go to a CSV file
    NONE = 2  # nothing: the rows go nowhere


#: The C element types the loop stores in its slots, as stepper.c's kinds (K_F64 ...), and how
#: Python reads a slot back: as a double, a signed or an unsigned 64-bit integer, or the offset of
#: a String's or a Binary's copy in the arena.
_KINDS = {"double": 0, "float": 1, "int64_t": 2, "uint64_t": 3, "int32_t": 4, "uint32_t": 5,
          "int16_t": 6, "uint16_t": 7, "int8_t": 8, "uint8_t": 9, "bool": 10, "const char*": 11,
          "const uint8_t*": 12}
_F64, _F32, _BOOL, _STRING, _BINARY = 0, 1, _KINDS["bool"], _KINDS["const char*"], _KINDS["const uint8_t*"]
_SIGNED = {_KINDS[t] for t in ("int64_t", "int32_t", "int16_t", "int8_t")}
_FORMAT = {0: "d", 1: "d", 2: "q", 3: "Q", 4: "q", 5: "Q", 6: "q", 7: "Q", 8: "q", 9: "Q", 10: "q", 11: "Q", 12: "Q"}
_SIZE = struct.Struct("N")  # the length before each copy in the arena (size_t)


def kind(fmi_type: str) -> int | None:
    """The slot kind of an FMI type's values, or None if the C loop does not store it (clocks)."""
    return _KINDS.get(C_TYPES.get(fmi_type, "")) if fmi_type != "Clock" else None


def load():
    """The compiled stretch library, or None: switched off by ROBOGEN_NO_C_STEPPER, or no
    compiler here (checked once per process)."""
    if os.environ.get("ROBOGEN_NO_C_STEPPER"):
        return None
    return _library()


def _cache_dir() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "robogen"


#: The C files of the library, compiled as one unit in this order (the run loop uses the stretch's
#: functions).
SOURCES = ("stepper.c", "runloop.c", "instants.c")


def source() -> bytes:
    """The library's C source: its files, each from its own line 1 for the compiler's messages,
    with the headers they include (the types cffi reads too) in place of their #include lines."""
    parts = []
    for name in SOURCES:
        parts.append(f'#line 1 "{name}"\n')
        for number, line in enumerate(package_file(name).splitlines(keepends=True), 1):
            included = _INCLUDE.fullmatch(line.strip())
            if included:
                parts += [f'#line 1 "{included[1]}"\n', package_file(included[1]), f'#line {number + 1} "{name}"\n']
            else:
                parts.append(line)
    return "".join(parts).encode()


@functools.cache
def _library():
    source_ = source()
    name = f"stepper-{hashlib.sha256(source_).hexdigest()[:16]}.so"
    fallback = Path(tempfile.gettempdir()) / f"robogen-{os.getuid() if hasattr(os, 'getuid') else 'user'}"
    for folder in (_cache_dir(), fallback):  # a read-only home still gets the fast loop
        try:
            return ffi.dlopen(str(_build(source_, folder / name)))
        except Exception:  # no compiler, folder not writable, ...: the Python loop does the same work
            continue
    return None


def _build(source: bytes, target: Path) -> Path:
    if not target.is_file():
        from robogen import toolchain

        target.parent.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryDirectory(dir=target.parent) as tmp:
            c_file, so = Path(tmp) / "stepper.c", Path(tmp) / "stepper.so"
            c_file.write_bytes(source)
            toolchain.compile_shared([c_file], so, libs=(), what="the master's C stepper")
            os.replace(so, target)  # atomic: concurrent runs never load a half-written file
    return target


def _address(cdata) -> int:
    return int(fmi_ffi.cast("uintptr_t", cdata))


class _Chunk(NamedTuple):
    """What one call of rg_run_stretch did."""

    steps: int
    rows: int  # rows stored: steps, less the last step's when it ended in an event or a failed read
    n: int  # grid index reached
    t: float  # time reached
    why: Why
    who: int  # the instance (or read) concerned: failing, or the first asking to terminate; else -1
    status: int  # the failing call's status


class _Slot(NamedTuple):
    """Where a recorded column's value is in a row of slots, and how to read it back."""

    slot: int
    format: str
    kind: int


class _Group(NamedTuple):
    """The links of one source FMU to one target FMU's inputs of one type: one Set call."""

    target: FmuInstance
    fmi_type: str
    links: list  # (read, index in the read, target value reference) of each link


class _Layout(NamedTuple):
    """What the C loop does after a step, as indices: reads, set groups, the order of both, columns."""

    reads: list[Reader]
    ops: list[int]  # r >= 0: reads[r]; -1 - g: groups[g]
    groups: list[_Group]
    columns: list[tuple[int, int, str]]  # (read or -1, index, the constant's cell)

    @classmethod
    def of(cls, plan: StretchPlan) -> _Layout:
        """In dependency order, each connected FMU's reads then its Set calls; then the reads of the
        recorded FMUs that forward nothing (the Python stretch's order)."""
        links = plan.values.links
        connected = [u for u in plan.instances if links[u.name]]
        reads = [r for u in connected for r in u.readers] + list(plan.reads)
        number = {id(r): i for i, r in enumerate(reads)}
        ops: list[int] = []
        groups: list[_Group] = []
        for u in connected:
            ops += [number[id(r)] for r in u.readers]
            mine: dict[tuple[str, str], _Group] = {}
            for vr, target, variable in links[u.name]:
                reader, index = u.reader_of[vr]
                key = (target.name, ACCESSOR[variable.type])
                if key not in mine:
                    mine[key] = _Group(target, variable.type, [])
                    ops.append(-1 - len(groups))
                    groups.append(mine[key])
                mine[key].links.append((number[id(reader)], index, variable.value_reference))
        ops += [number[id(r)] for r in plan.reads]
        columns = [(number[id(c.reader)], c.index, "") if c.kind == VALUE else (-1, 0, "0" if c.kind == CLOCK else "")
                   for c in plan.columns]
        return cls(reads, ops, groups, columns)


def _mode(recorder) -> Mode:
    if recorder.takes_text:
        return Mode.TEXT
    return Mode.NONE if recorder.discards else Mode.SLOTS


class CStretch:
    """The quiet stretch in C, bound to one run's instances, exchange and recorded reads."""

    name = "C"

    @classmethod
    def for_plan(cls, plan: StretchPlan) -> CStretch | None:
        """The C loop for this plan; None where it cannot run: pacing (the Python stretch does it),
        a type it does not read, no library."""
        if plan.pacer is not None:
            return None
        layout = _Layout.of(plan)
        if any(kind(r.fmi_type) is None or r.c_function is None for r in layout.reads):
            return None
        if any(g.target.binding.raw("fmi3Set" + ACCESSOR[g.fmi_type]) is None for g in layout.groups):
            return None
        lib = load()
        return cls(lib, plan, layout) if lib is not None else None

    def __init__(self, lib, plan: StretchPlan, layout: _Layout):
        self.lib, self.plan, self.layout = lib, plan, layout
        self.mode = _mode(plan.recorder)
        self._keep: list = []  # the C arrays the struct points into
        struct = self._struct(plan, layout)
        # frees the arena, the text and the last values with the struct (the destructor holds the
        # struct's memory, and the arrays it points into, until it ran)
        self.s = ffi.gc(struct, lambda pointer, _owner=struct, _keep=self._keep: lib.rg_release(pointer))
        self.width = max(1, self.s.width)
        self.columns = self._columns(plan)
        self.times = ffi.new("double[]", CHUNK)
        self.slots = ffi.new("uint64_t[]", CHUNK * self.width if self.mode == Mode.SLOTS else 1)
        self._n, self._t = ffi.new("long *"), ffi.new("double *")
        self._why, self._who, self._status = ffi.new("int *"), ffi.new("int *"), ffi.new("int *")
        # each link's input, as the exchange knows it, and its slot kind
        self._inputs = [((g.target.name, vr), kind(g.fmi_type)) for g in layout.groups for _r, _i, vr in g.links]

    def _array(self, ctype: str, values: list):
        a = ffi.new(ctype, values)
        self._keep.append(a)
        return a

    def _struct(self, plan: StretchPlan, layout: _Layout):
        s = ffi.new("rg_stretch *")
        self._keep.append(s)
        pointers = self._pointers
        n = len(plan.instances)
        s.n_instances = n
        s.do_step = pointers("rg_do_step_fn[]", [u.binding.raw("fmi3DoStep") for u in plan.instances])
        s.instance = pointers("void *[]", [u.binding.handle for u in plan.instances])
        s.event_mode = self._array("bool[]", [u.event_mode for u in plan.instances] or [False])
        s.flags = self._array("bool[]", 4 * max(1, n))
        s.last_time = self._array("double[]", max(1, n))
        s.step_note = self._array("int32_t[]", [u.binding.note_code("fmi3DoStep") for u in plan.instances] or [0])
        self._reads(s, layout.reads)
        s.n_ops = len(layout.ops)
        s.op = self._array("int[]", layout.ops or [0])
        self._groups(s, layout.groups)
        s.n_columns = len(layout.columns)
        s.column_read = self._array("int[]", [r for r, _i, _c in layout.columns] or [0])
        s.column_index = self._array("int[]", [i for _r, i, _c in layout.columns] or [0])
        texts = [self._array("char[]", c.encode()) for _r, _i, c in layout.columns]
        s.column_text = self._array("char *[]", texts or [ffi.NULL])
        s.mode = int(self.mode)
        s.width = sum(1 for r, _i, _c in layout.columns if r >= 0)
        s.note_call = ffi.cast("int32_t *", _address(plan.notes.call))
        s.note_time = ffi.cast("double *", _address(plan.notes.time))
        return s

    def _reads(self, s, reads: list[Reader]) -> None:
        pointers = self._pointers
        s.n_reads = len(reads)
        binary = [r.fmi_type == "Binary" for r in reads]
        s.get = pointers("rg_get_fn[]", [fmi_ffi.NULL if b else r.c_function for r, b in zip(reads, binary)])
        s.get_binary = pointers("rg_get_binary_fn[]", [r.c_function if b else fmi_ffi.NULL for r, b in zip(reads, binary)])
        s.read_instance = pointers("void *[]", [r.binding.handle for r in reads])
        s.vrs = pointers("uint32_t *[]", [r.c_vrs for r in reads])
        s.count = self._array("size_t[]", [r.count for r in reads] or [0])
        s.kind = self._array("int[]", [kind(r.fmi_type) for r in reads] or [0])
        s.buffer = pointers("void *[]", [r.buffer for r in reads])
        s.sizes = pointers("size_t *[]", [r.sizes if r.sizes is not None else fmi_ffi.NULL for r in reads])
        s.read_note = self._array("int32_t[]", [r.note_code for r in reads] or [0])
        copies = [self._array("uint64_t[]", r.count) if r.decodes else ffi.NULL for r in reads]
        s.copies = self._array("uint64_t *[]", copies or [ffi.NULL])

    def _groups(self, s, groups: list[_Group]) -> None:
        pointers = self._pointers
        functions = ["fmi3Set" + ACCESSOR[g.fmi_type] for g in groups]
        binary = [g.fmi_type == "Binary" for g in groups]
        raw = [g.target.binding.raw(f) for g, f in zip(groups, functions)]
        s.n_sets = len(groups)
        s.set = pointers("rg_set_fn[]", [fmi_ffi.NULL if b else f for f, b in zip(raw, binary)])
        s.set_binary = pointers("rg_set_binary_fn[]", [f if b else fmi_ffi.NULL for f, b in zip(raw, binary)])
        s.set_instance = pointers("void *[]", [g.target.binding.handle for g in groups])
        s.set_kind = self._array("int[]", [kind(g.fmi_type) for g in groups] or [0])
        s.set_note = self._array("int32_t[]", [g.target.binding.note_code(f) for g, f in zip(groups, functions)] or [0])
        counts = [len(g.links) for g in groups]
        s.set_first = self._array("int[]", [sum(counts[:i]) for i in range(len(groups))] or [0])
        s.set_count = self._array("int[]", counts or [0])
        links = [link for g in groups for link in g.links]
        s.n_links = n = len(links)
        s.link_read = self._array("int[]", [r for r, _i, _vr in links] or [0])
        s.link_index = self._array("int[]", [i for _r, i, _vr in links] or [0])
        s.link_vr = self._array("uint32_t[]", [vr for _r, _i, vr in links] or [0])
        s.last = self._array("rg_value[]", max(1, n))
        s.last_valid = self._array("bool[]", max(1, n))
        s.last_bytes = self._array("char *[]", max(1, n))
        s.last_size = self._array("size_t[]", max(1, n))
        widest = max(counts, default=1)
        s.set_vrs = self._array("uint32_t[]", widest)
        s.set_values = self._array("rg_value[]", widest)
        s.set_pointers = self._array("uint8_t *[]", widest)
        s.set_sizes = self._array("size_t[]", widest)
        self._set_functions = functions

    def _pointers(self, ctype: str, cdata: list):
        """An array of ``ctype`` holding these cffi objects of the FMI binding's FFI, as addresses."""
        item = ctype[:-2]
        return self._array(ctype, [ffi.cast(item, _address(c)) for c in cdata] or [ffi.NULL])

    def _columns(self, plan: StretchPlan) -> list:
        """Each recorded column: its slot, or the constant of a step row (clocks 0, clocked values empty)."""
        columns, width = [], 0
        for c in plan.columns:
            if c.kind == VALUE:
                k = kind(c.reader.fmi_type)
                columns.append(_Slot(width, _FORMAT[k], k))
                width += 1
            else:
                columns.append(0 if c.kind == CLOCK else None)
        return columns

    # -- the run -------------------------------------------------------------------------------
    def run(self, t: float, horizon: float) -> StretchEnd:
        plan = self.plan
        n, limit, steps = plan.index(t), plan.limit(horizon), 0
        self._lend_inputs()
        try:
            while True:
                chunk = self._chunk(n, t, limit)
                self._record(chunk.rows)
                steps += chunk.steps
                n, t = chunk.n, chunk.t
                for u in plan.instances:
                    u.time = t
                self._raise_failure(chunk)
                if plan.progress.enabled:
                    plan.progress.update(t)
                if chunk.why != Why.PAUSE:
                    terminating = plan.instances[chunk.who] if chunk.who >= 0 else None
                    return StretchEnd(t, steps, chunk.why == Why.EVENT, terminating)
        finally:
            self._take_inputs_back()

    def _raise_failure(self, chunk: _Chunk) -> None:
        if chunk.why == Why.STEP_FAILED:
            raise self.plan.instances[chunk.who].binding.error("fmi3DoStep", chunk.status)
        if chunk.why == Why.GET_FAILED:
            read = self.layout.reads[chunk.who]
            raise read.binding.error(read.function, chunk.status)
        if chunk.why == Why.SET_FAILED:
            raise self.layout.groups[chunk.who].target.binding.error(self._set_functions[chunk.who], chunk.status)
        if chunk.why == Why.NO_MEMORY:
            raise MemoryError("no memory left for the recorded Strings and Binaries")

    def _lend_inputs(self) -> None:
        """The values last set to the connected inputs, from the exchange to the loop."""
        last_set, s = self.plan.values.last_set, self.s
        for k, (key, slot_kind) in enumerate(self._inputs):
            value = last_set.get(key, UNSET)
            s.last_valid[k] = value is not UNSET
            if value is UNSET:
                continue
            if slot_kind in (_F64, _F32):
                s.last[k].d = value
            elif slot_kind in (_STRING, _BINARY):
                data = value.encode() if isinstance(value, str) else bytes(value)
                if self.lib.rg_keep_last(s, k, data, len(data)) != 0:
                    raise MemoryError("no memory left for the connected Strings and Binaries")
            elif slot_kind in _SIGNED:
                s.last[k].i = value
            else:
                s.last[k].u = int(value)

    def _take_inputs_back(self) -> None:
        """The values the loop set to the connected inputs, back to the exchange."""
        last_set, s = self.plan.values.last_set, self.s
        for k, (key, slot_kind) in enumerate(self._inputs):
            if not s.last_valid[k]:
                continue
            if slot_kind in (_F64, _F32):
                last_set[key] = s.last[k].d
            elif slot_kind in (_STRING, _BINARY):
                data = ffi.unpack(s.last_bytes[k], s.last_size[k])
                last_set[key] = data.decode("utf-8", "replace") if slot_kind == _STRING else data
            elif slot_kind in _SIGNED:
                last_set[key] = s.last[k].i
            else:
                last_set[key] = bool(s.last[k].u) if slot_kind == _BOOL else s.last[k].u

    def _chunk(self, n: int, t: float, limit: float) -> _Chunk:
        """Steps as far as one chunk of rows, or the recorder's next flush, allows."""
        self._n[0], self._t[0] = n, t
        deadline = min(time.monotonic() + FLUSH_SECONDS, self.plan.recorder.flush_due)
        steps = self.lib.rg_run_stretch(self.s, self.plan.start, self.plan.step, self._n, self._t, limit, CHUNK,
                                        deadline, self.times, self.slots, self._why, self._who, self._status)
        why = Why(self._why[0])
        rows = steps - 1 if why in (Why.EVENT, Why.GET_FAILED, Why.SET_FAILED, Why.NO_MEMORY) else steps
        return _Chunk(steps, rows, self._n[0], self._t[0], why, self._who[0], self._status[0])

    def _record(self, count: int) -> None:
        """The chunk's rows to the recorder, as the mode stored them."""
        if count <= 0 or self.mode == Mode.NONE:
            return
        if self.mode == Mode.TEXT:
            text = ffi.buffer(self.s.text.data, self.s.text.used)[:]
            self.plan.recorder.append_text(text.decode("utf-8", "replace"), count)
        else:
            self.plan.recorder.append_rows(self._rows(count))

    def _rows(self, count: int) -> list[list]:
        """The first ``count`` stored rows as result rows: [t, 0, values...]."""
        raw = memoryview(ffi.buffer(self.slots, count * self.width * 8))
        views = {f: raw.cast(f) for f in ("d", "q", "Q")}
        columns = [ffi.unpack(self.times, count), repeat(0, count)]
        for c in self.columns:
            if isinstance(c, _Slot):
                values = views[c.format][c.slot:count * self.width:self.width].tolist()
                if c.kind == _BOOL:
                    values = list(map(bool, values))
                elif c.kind in (_STRING, _BINARY):
                    values = self._copies(values, c.kind == _STRING)
                columns.append(values)
            else:
                columns.append(repeat(c, count))
        return list(map(list, zip(*columns)))

    def _copies(self, offsets: list[int], text: bool) -> list:
        """The Strings (``text``) or Binaries at these offsets of the arena."""
        arena = ffi.buffer(self.s.arena.data, self.s.arena.used)
        out = []
        for offset in offsets:
            start = offset + _SIZE.size
            data = arena[start:start + _SIZE.unpack_from(arena, offset)[0]]
            out.append(data.decode("utf-8", "replace") if text else data)
        return out
