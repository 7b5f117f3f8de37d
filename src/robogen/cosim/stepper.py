"""The plain-step loop in C (stepper.c), for stretches of time in which the master only steps the
FMUs and records their outputs: no event, no early return, no value to forward, no pacing.

The library is compiled once with the system C compiler and cached under
``$XDG_CACHE_HOME/robogen`` (or ``~/.cache/robogen``), named by the hash of its source; if there is
no compiler, :func:`load` returns None and the master keeps its Python loop, which computes the
same results. Rows come back as 8-byte slots and are turned into result rows a column at a time
(``memoryview`` slices), so the per-step cost is that of the FMI calls themselves.
"""

from __future__ import annotations

import hashlib
import importlib.resources
import os
import tempfile
from itertools import repeat
from pathlib import Path

import cffi

from robogen.cosim.fmi3 import ffi as fmi_ffi

ffi = cffi.FFI()
ffi.cdef(
    """
    typedef int (*rg_do_step_fn)(void *, double, double, bool, bool *, bool *, bool *, double *);
    typedef int (*rg_get_fn)(void *, const uint32_t *, size_t, void *, size_t);
    typedef struct {
        int n_units;
        rg_do_step_fn *do_step;
        void **instance;
        const bool *event_mode;
        bool *flags;
        double *last_time;
        int n_reads;
        rg_get_fn *get;
        void **read_instance;
        const uint32_t **vrs;
        const size_t *count;
        const int *kind;
        void **buffer;
        int width;
    } rg_stepper;
    long rg_plain_steps(const rg_stepper *s, double start, double h, long *n, double *t, double limit,
                        long max_rows, double *times, uint64_t *slots, int *why, int *who, int *status);
    """
)

WHY_LIMIT, WHY_EVENT, WHY_TERMINATE, WHY_STEP_FAILED, WHY_GET_FAILED = range(5)
KINDS = {"Float64": 0, "Float32": 1, "Int64": 2, "UInt64": 3, "Int32": 4, "UInt32": 5, "Int16": 6,
         "UInt16": 7, "Int8": 8, "UInt8": 9, "Boolean": 10}
_FORMAT = {0: "d", 1: "d", 2: "q", 3: "Q", 4: "q", 5: "Q", 6: "q", 7: "Q", 8: "q", 9: "Q", 10: "q"}
CHUNK = 4096  # rows per call

_lib = None
_tried = False


def _cache_dir() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "robogen"


def load():
    """The compiled stepper library, or None if it cannot be built here."""
    global _lib, _tried
    if _tried:
        return _lib
    _tried = True
    if os.environ.get("ROBOGEN_NO_C_STEPPER"):
        return None
    source = (importlib.resources.files("robogen.cosim") / "stepper.c").read_bytes()
    name = f"stepper-{hashlib.sha256(source).hexdigest()[:16]}.so"
    fallback = Path(tempfile.gettempdir()) / f"robogen-{os.getuid() if hasattr(os, 'getuid') else 'user'}"
    for folder in (_cache_dir(), fallback):  # a read-only home still gets the fast loop
        try:
            _lib = ffi.dlopen(str(_build(source, folder / name)))
            return _lib
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


class Stepper:
    """The C loop bound to a master's instances and recorded reads."""

    def __init__(self, lib, units, reads, event_mode, cols):
        """``units``: (do_step function, instance handle); ``reads``: (get function, handle,
        value-reference array, count, buffer, fmi type); ``cols``: for each recorded column,
        (index of the read, index in it) or ('const', value)."""
        self.lib = lib
        n_units, n_reads = len(units), len(reads)
        keep = self._keep = []

        def new(ctype, values):
            a = ffi.new(ctype, values)
            keep.append(a)
            return a

        s = ffi.new("rg_stepper *")
        keep.append(s)
        s.n_units = n_units
        s.do_step = new("rg_do_step_fn[]", [ffi.cast("rg_do_step_fn", _address(f)) for f, _ in units] or [ffi.NULL])
        s.instance = new("void *[]", [ffi.cast("void *", _address(h)) for _, h in units] or [ffi.NULL])
        s.event_mode = new("bool[]", list(event_mode) or [False])
        s.flags = new("bool[]", 4 * max(1, n_units))
        s.last_time = new("double[]", max(1, n_units))
        s.n_reads = n_reads
        s.get = new("rg_get_fn[]", [ffi.cast("rg_get_fn", _address(r[0])) for r in reads] or [ffi.NULL])
        s.read_instance = new("void *[]", [ffi.cast("void *", _address(r[1])) for r in reads] or [ffi.NULL])
        s.vrs = new("uint32_t *[]", [ffi.cast("uint32_t *", _address(r[2])) for r in reads] or [ffi.NULL])
        s.count = new("size_t[]", [r[3] for r in reads] or [0])
        kinds = [KINDS[r[5]] for r in reads]
        s.kind = new("int[]", kinds or [0])
        s.buffer = new("void *[]", [ffi.cast("void *", _address(r[4])) for r in reads] or [ffi.NULL])
        offsets, width = [], 0
        for r in reads:
            offsets.append(width)
            width += r[3]
        s.width = width
        self.s = s
        self.width = max(1, width)
        # each recorded column: its slot and how to read it, or a constant
        self.columns = []
        for c in cols:
            if c[0] == "const":
                self.columns.append(("const", c[1]))
            else:
                read, index = c
                kind = kinds[read]
                self.columns.append(("slot", offsets[read] + index, _FORMAT[kind], kind == KINDS["Boolean"]))
        self.times = ffi.new("double[]", CHUNK)
        self.slots = ffi.new("uint64_t[]", CHUNK * self.width)
        self.n = ffi.new("long *")
        self.t = ffi.new("double *")
        self.why = ffi.new("int *")
        self.who = ffi.new("int *")
        self.status = ffi.new("int *")

    def run(self, start: float, h: float, n: int, t: float, limit: float):
        """Steps as far as possible in one chunk: (steps, rows, n, t, why, who, status)."""
        self.n[0], self.t[0] = n, t
        steps = self.lib.rg_plain_steps(self.s, start, h, self.n, self.t, limit, CHUNK, self.times, self.slots,
                                        self.why, self.who, self.status)
        why = self.why[0]
        rows = steps - 1 if why in (WHY_EVENT, WHY_GET_FAILED) else steps
        return steps, rows, self.n[0], self.t[0], why, self.who[0], self.status[0]

    def rows(self, count: int) -> list[list]:
        """The first ``count`` stored rows as result rows: [t, 0, values...]."""
        if count <= 0:
            return []
        raw = memoryview(ffi.buffer(self.slots, count * self.width * 8))
        views = {f: raw.cast(f) for f in ("d", "q", "Q")}
        columns = [ffi.unpack(self.times, count), repeat(0, count)]
        for c in self.columns:
            if c[0] == "const":
                columns.append(repeat(c[1], count))
            else:
                _, slot, fmt, boolean = c
                values = views[fmt][slot:count * self.width:self.width].tolist()
                columns.append(list(map(bool, values)) if boolean else values)
        return [list(row) for row in zip(*columns)]
