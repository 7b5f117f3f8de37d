"""The quiet stretch in C (stepper.c): :class:`CStretch`, one of the implementations of
:class:`robogen.cosim.stretch.Stretch`, for stretches in which the master only steps the FMUs
and records their outputs (no value to forward between FMUs, no pacing); it stores every FMI
type (Strings and Binaries as copies in an arena the rows point into).

The library is compiled once with the system C compiler and cached under
``$XDG_CACHE_HOME/robogen`` (or ``~/.cache/robogen``), named by the hash of its source; if there is
no compiler, or ``ROBOGEN_NO_C_STEPPER`` is set, :func:`load` returns None and the master runs
the Python stretch, which computes the same results. Rows come back as 8-byte slots and are
turned into result rows a column at a time (``memoryview`` slices), so the per-step cost is that
of the FMI calls themselves. A chunk of rows ends after :data:`~robogen.cosim.recorder.FLUSH_SECONDS`
of wall time at the latest, so slow FMUs do not hold rows back from the results file.
"""

from __future__ import annotations

import functools
import hashlib
import importlib.resources
import os
import struct
import tempfile
import time
from enum import IntEnum
from itertools import repeat
from pathlib import Path
from typing import NamedTuple

import cffi

from robogen.cosim.fmi3 import C_TYPES
from robogen.cosim.fmi3 import ffi as fmi_ffi
from robogen.cosim.recorder import FLUSH_SECONDS
from robogen.cosim.stretch import StretchEnd, StretchPlan
from robogen.cosim.wiring import CLOCK, VALUE

ffi = cffi.FFI()
ffi.cdef(
    """
    typedef int (*rg_do_step_fn)(void *, double, double, bool, bool *, bool *, bool *, double *);
    typedef int (*rg_get_fn)(void *, const uint32_t *, size_t, void *, size_t);
    typedef int (*rg_get_binary_fn)(void *, const uint32_t *, size_t, size_t *, const uint8_t **, size_t);
    typedef struct {
        int n_instances;
        rg_do_step_fn *do_step;
        void **instance;
        const bool *event_mode;
        bool *flags;
        double *last_time;
        const int32_t *step_note;
        int n_reads;
        rg_get_fn *get;
        rg_get_binary_fn *get_binary;
        void **read_instance;
        const uint32_t **vrs;
        const size_t *count;
        const int *kind;
        void **buffer;
        size_t **sizes;
        const int32_t *read_note;
        int width;
        int32_t *note_call;
        double *note_time;
        char *arena;
        size_t arena_size, arena_used;
    } rg_stretch;
    long rg_run_stretch(rg_stretch *s, double start, double h, long *n, double *t, double limit, long max_rows,
                        double deadline, double *times, uint64_t *slots, int *why, int *who, int *status);
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


#: The C element types the loop stores in its slots, as stepper.c's kinds (K_F64 ...), and how
#: Python reads a slot back: as a double, a signed or an unsigned 64-bit integer, or the offset of
#: a String's or a Binary's copy in the arena.
_KINDS = {"double": 0, "float": 1, "int64_t": 2, "uint64_t": 3, "int32_t": 4, "uint32_t": 5,
          "int16_t": 6, "uint16_t": 7, "int8_t": 8, "uint8_t": 9, "bool": 10, "const char*": 11,
          "const uint8_t*": 12}
_BOOL, _STRING, _BINARY = _KINDS["bool"], _KINDS["const char*"], _KINDS["const uint8_t*"]
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


@functools.cache
def _library():
    source = (importlib.resources.files("robogen.cosim") / "stepper.c").read_bytes()
    name = f"stepper-{hashlib.sha256(source).hexdigest()[:16]}.so"
    fallback = Path(tempfile.gettempdir()) / f"robogen-{os.getuid() if hasattr(os, 'getuid') else 'user'}"
    for folder in (_cache_dir(), fallback):  # a read-only home still gets the fast loop
        try:
            return ffi.dlopen(str(_build(source, folder / name)))
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


class CStretch:
    """The quiet stretch in C, bound to one run's instances and recorded reads."""

    name = "C"

    @classmethod
    def for_plan(cls, plan: StretchPlan) -> CStretch | None:
        """The C loop for this plan; None where it cannot run: values to forward between FMUs, or
        pacing (the Python stretch does those), a recorded type it does not store, no library."""
        if plan.values.connected or plan.pacer is not None:
            return None
        if any(kind(r.fmi_type) is None for r in plan.reads):
            return None
        lib = load()
        return cls(lib, plan) if lib is not None else None

    def __init__(self, lib, plan: StretchPlan):
        self.lib, self.plan = lib, plan
        self._keep: list = []  # the C arrays the struct points into
        struct = self._struct(plan)
        # frees the arena with the struct (the destructor holds the struct's memory until it ran)
        self.s = ffi.gc(struct, lambda pointer, _owner=struct: lib.rg_release(pointer))
        self.width = max(1, self.s.width)
        self.columns = self._columns(plan)
        self.times = ffi.new("double[]", CHUNK)
        self.slots = ffi.new("uint64_t[]", CHUNK * self.width)
        self._n, self._t = ffi.new("long *"), ffi.new("double *")
        self._why, self._who, self._status = ffi.new("int *"), ffi.new("int *"), ffi.new("int *")

    def _array(self, ctype: str, values: list):
        a = ffi.new(ctype, values)
        self._keep.append(a)
        return a

    def _struct(self, plan: StretchPlan):
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
        s.n_reads = len(plan.reads)
        binary = [r.fmi_type == "Binary" for r in plan.reads]
        s.get = pointers("rg_get_fn[]", [fmi_ffi.NULL if b else r.c_function for r, b in zip(plan.reads, binary)])
        s.get_binary = pointers("rg_get_binary_fn[]", [r.c_function if b else fmi_ffi.NULL for r, b in zip(plan.reads, binary)])
        s.read_instance = pointers("void *[]", [r.binding.handle for r in plan.reads])
        s.vrs = pointers("uint32_t *[]", [r.c_vrs for r in plan.reads])
        s.count = self._array("size_t[]", [r.count for r in plan.reads] or [0])
        s.kind = self._array("int[]", [kind(r.fmi_type) for r in plan.reads] or [0])
        s.buffer = pointers("void *[]", [r.buffer for r in plan.reads])
        s.sizes = pointers("size_t *[]", [r.sizes if r.sizes is not None else fmi_ffi.NULL for r in plan.reads])
        s.read_note = self._array("int32_t[]", [r.note_code for r in plan.reads] or [0])
        s.width = sum(r.count for r in plan.reads)
        s.note_call = ffi.cast("int32_t *", _address(plan.notes.call))
        s.note_time = ffi.cast("double *", _address(plan.notes.time))
        return s

    def _pointers(self, ctype: str, cdata: list):
        """An array of ``ctype`` holding these cffi objects of the FMI binding's FFI, as addresses."""
        item = ctype[:-2]
        return self._array(ctype, [ffi.cast(item, _address(c)) for c in cdata] or [ffi.NULL])

    def _columns(self, plan: StretchPlan) -> list:
        """Each recorded column: its slot, or the constant of a step row (clocks 0, clocked values empty)."""
        offsets, width = {}, 0
        for r in plan.reads:
            offsets[id(r)] = width
            width += r.count
        columns = []
        for c in plan.columns:
            if c.kind == VALUE:
                k = kind(c.reader.fmi_type)
                columns.append(_Slot(offsets[id(c.reader)] + c.index, _FORMAT[k], k))
            else:
                columns.append(0 if c.kind == CLOCK else None)
        return columns

    def run(self, t: float, horizon: float) -> StretchEnd:
        plan = self.plan
        n, limit, steps = plan.index(t), plan.limit(horizon), 0
        while True:
            chunk = self._chunk(n, t, limit)
            plan.recorder.append_rows(self._rows(chunk.rows))
            steps += chunk.steps
            n, t = chunk.n, chunk.t
            for u in plan.instances:
                u.time = t
            if chunk.why == Why.STEP_FAILED:
                raise plan.instances[chunk.who].binding.error("fmi3DoStep", chunk.status)
            if chunk.why == Why.GET_FAILED:
                read = plan.reads[chunk.who]
                raise read.binding.error(read.function, chunk.status)
            if chunk.why == Why.NO_MEMORY:
                raise MemoryError("no memory left for the recorded Strings and Binaries")
            if plan.progress.enabled:
                plan.progress.update(t)
            if chunk.why != Why.PAUSE:
                terminating = plan.instances[chunk.who] if chunk.who >= 0 else None
                return StretchEnd(t, steps, chunk.why == Why.EVENT, terminating)

    def _chunk(self, n: int, t: float, limit: float) -> _Chunk:
        """Steps as far as one chunk of rows, or FLUSH_SECONDS of wall time, allows."""
        self._n[0], self._t[0] = n, t
        deadline = time.monotonic() + FLUSH_SECONDS
        steps = self.lib.rg_run_stretch(self.s, self.plan.start, self.plan.step, self._n, self._t, limit, CHUNK,
                                        deadline, self.times, self.slots, self._why, self._who, self._status)
        why = Why(self._why[0])
        rows = steps - 1 if why in (Why.EVENT, Why.GET_FAILED, Why.NO_MEMORY) else steps
        return _Chunk(steps, rows, self._n[0], self._t[0], why, self._who[0], self._status[0])

    def _rows(self, count: int) -> list[list]:
        """The first ``count`` stored rows as result rows: [t, 0, values...]."""
        if count <= 0:
            return []
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
        return [list(row) for row in zip(*columns)]

    def _copies(self, offsets: list[int], text: bool) -> list:
        """The Strings (``text``) or Binaries at these offsets of the arena."""
        arena = ffi.buffer(self.s.arena, self.s.arena_used)
        out = []
        for offset in offsets:
            start = offset + _SIZE.size
            data = arena[start:start + _SIZE.unpack_from(arena, offset)[0]]
            out.append(data.decode("utf-8", "replace") if text else data)
        return out
