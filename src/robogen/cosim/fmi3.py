"""A thin cffi binding of the FMI 3.0 Co-Simulation API, named exactly as the C header.

``Library(path)`` opens an FMU's shared object (ABI mode: no compiler needed) and resolves
every function the master uses up front, so a missing symbol is reported at load time by name.
``Binding`` wraps one ``fmi3Instance``; each method is the C function of the same name with
the status turned into an exception: any status above ``fmi3Warning`` raises
:class:`FMI3Error` carrying the function name, the status and the instance name (and the last
message the FMU logged). Several output arguments come back as a named tuple
(:class:`StepResult`, :class:`DiscreteStates`).

Value arrays are cffi buffers so the hot loop allocates nothing: :func:`vr_array` and
:func:`value_array` make them once; the getters fill a caller-owned buffer. Above them,
:meth:`Binding.get_values` and :meth:`Binding.set_values` take and give Python lists of any FMI
type (Strings as ``str``, Binaries as ``bytes``, Enumerations as ``int``); they allocate, and
serve the calls made once per event or per run. An optional ``trace`` callable receives one line
per call (``fmi3DoStep(ball, 0.5, 0.5) -> fmi3OK``).

Before each call the binding notes which call it makes in its :class:`CallNotes` (a few bytes
that may live in memory shared with a watching process, :mod:`robogen.cosim.crash`), so that
a crash inside the FMU can still be reported by instance and function.

Loops that make millions of calls (the master's quiet stretches) may call the FMU's C functions
without this layer: :meth:`Binding.raw` gives the function, :attr:`Binding.handle` the instance
and :attr:`Binding.step_outputs` fmi3DoStep's output arguments; such a loop notes its calls and
checks the status itself, and raises :meth:`Binding.error`. While a trace is on there is no raw
access, so that every call is seen.
"""

from __future__ import annotations

import weakref
from typing import Callable, NamedTuple, Sequence

import cffi

from robogen.cosim import signals
from robogen.fmu.fmi import ERROR, FATAL, WARNING, status_name

ffi = cffi.FFI()
ffi.cdef(
    """
    typedef void* fmi3Instance;
    typedef void* fmi3InstanceEnvironment;
    typedef void* fmi3FMUState;
    typedef uint32_t fmi3ValueReference;
    typedef int fmi3Status;
    typedef void (*fmi3LogMessageCallback)(fmi3InstanceEnvironment, fmi3Status, const char*, const char*);
    typedef void (*fmi3IntermediateUpdateCallback)(fmi3InstanceEnvironment, double, bool, bool, bool, bool, bool*, double*);

    const char* fmi3GetVersion(void);
    fmi3Status fmi3SetDebugLogging(fmi3Instance, bool, size_t, const char* const[]);
    fmi3Instance fmi3InstantiateCoSimulation(const char*, const char*, const char*, bool, bool, bool, bool,
        const fmi3ValueReference[], size_t, fmi3InstanceEnvironment, fmi3LogMessageCallback,
        fmi3IntermediateUpdateCallback);
    void fmi3FreeInstance(fmi3Instance);
    fmi3Status fmi3EnterInitializationMode(fmi3Instance, bool, double, double, bool, double);
    fmi3Status fmi3ExitInitializationMode(fmi3Instance);
    fmi3Status fmi3EnterEventMode(fmi3Instance);
    fmi3Status fmi3Terminate(fmi3Instance);
    fmi3Status fmi3Reset(fmi3Instance);

    fmi3Status fmi3GetFloat32(fmi3Instance, const fmi3ValueReference[], size_t, float[], size_t);
    fmi3Status fmi3GetFloat64(fmi3Instance, const fmi3ValueReference[], size_t, double[], size_t);
    fmi3Status fmi3GetInt8(fmi3Instance, const fmi3ValueReference[], size_t, int8_t[], size_t);
    fmi3Status fmi3GetUInt8(fmi3Instance, const fmi3ValueReference[], size_t, uint8_t[], size_t);
    fmi3Status fmi3GetInt16(fmi3Instance, const fmi3ValueReference[], size_t, int16_t[], size_t);
    fmi3Status fmi3GetUInt16(fmi3Instance, const fmi3ValueReference[], size_t, uint16_t[], size_t);
    fmi3Status fmi3GetInt32(fmi3Instance, const fmi3ValueReference[], size_t, int32_t[], size_t);
    fmi3Status fmi3GetUInt32(fmi3Instance, const fmi3ValueReference[], size_t, uint32_t[], size_t);
    fmi3Status fmi3GetInt64(fmi3Instance, const fmi3ValueReference[], size_t, int64_t[], size_t);
    fmi3Status fmi3GetUInt64(fmi3Instance, const fmi3ValueReference[], size_t, uint64_t[], size_t);
    fmi3Status fmi3GetBoolean(fmi3Instance, const fmi3ValueReference[], size_t, bool[], size_t);
    fmi3Status fmi3GetString(fmi3Instance, const fmi3ValueReference[], size_t, const char*[], size_t);
    fmi3Status fmi3GetBinary(fmi3Instance, const fmi3ValueReference[], size_t, size_t[], const uint8_t*[], size_t);
    fmi3Status fmi3GetClock(fmi3Instance, const fmi3ValueReference[], size_t, bool[]);
    fmi3Status fmi3SetFloat32(fmi3Instance, const fmi3ValueReference[], size_t, const float[], size_t);
    fmi3Status fmi3SetFloat64(fmi3Instance, const fmi3ValueReference[], size_t, const double[], size_t);
    fmi3Status fmi3SetInt8(fmi3Instance, const fmi3ValueReference[], size_t, const int8_t[], size_t);
    fmi3Status fmi3SetUInt8(fmi3Instance, const fmi3ValueReference[], size_t, const uint8_t[], size_t);
    fmi3Status fmi3SetInt16(fmi3Instance, const fmi3ValueReference[], size_t, const int16_t[], size_t);
    fmi3Status fmi3SetUInt16(fmi3Instance, const fmi3ValueReference[], size_t, const uint16_t[], size_t);
    fmi3Status fmi3SetInt32(fmi3Instance, const fmi3ValueReference[], size_t, const int32_t[], size_t);
    fmi3Status fmi3SetUInt32(fmi3Instance, const fmi3ValueReference[], size_t, const uint32_t[], size_t);
    fmi3Status fmi3SetInt64(fmi3Instance, const fmi3ValueReference[], size_t, const int64_t[], size_t);
    fmi3Status fmi3SetUInt64(fmi3Instance, const fmi3ValueReference[], size_t, const uint64_t[], size_t);
    fmi3Status fmi3SetBoolean(fmi3Instance, const fmi3ValueReference[], size_t, const bool[], size_t);
    fmi3Status fmi3SetString(fmi3Instance, const fmi3ValueReference[], size_t, const char* const[], size_t);
    fmi3Status fmi3SetBinary(fmi3Instance, const fmi3ValueReference[], size_t, const size_t[], const uint8_t* const[], size_t);
    fmi3Status fmi3SetClock(fmi3Instance, const fmi3ValueReference[], size_t, const bool[]);

    fmi3Status fmi3GetFMUState(fmi3Instance, fmi3FMUState*);
    fmi3Status fmi3SetFMUState(fmi3Instance, fmi3FMUState);
    fmi3Status fmi3FreeFMUState(fmi3Instance, fmi3FMUState*);

    fmi3Status fmi3GetIntervalDecimal(fmi3Instance, const fmi3ValueReference[], size_t, double[], int[]);
    fmi3Status fmi3GetShiftDecimal(fmi3Instance, const fmi3ValueReference[], size_t, double[]);
    fmi3Status fmi3SetIntervalDecimal(fmi3Instance, const fmi3ValueReference[], size_t, const double[]);
    fmi3Status fmi3SetShiftDecimal(fmi3Instance, const fmi3ValueReference[], size_t, const double[]);

    fmi3Status fmi3UpdateDiscreteStates(fmi3Instance, bool*, bool*, bool*, bool*, bool*, double*);
    fmi3Status fmi3EnterStepMode(fmi3Instance);
    fmi3Status fmi3DoStep(fmi3Instance, double, double, bool, bool*, bool*, bool*, double*);
    """
)


# FMI type -> C element type of its value arrays. Enumeration values travel as Int64; a Binary
# array holds pointers, its sizes travel in a size_t array beside it.
C_TYPES = {
    "Float32": "float", "Float64": "double",
    "Int8": "int8_t", "UInt8": "uint8_t", "Int16": "int16_t", "UInt16": "uint16_t",
    "Int32": "int32_t", "UInt32": "uint32_t", "Int64": "int64_t", "UInt64": "uint64_t",
    "Boolean": "bool", "String": "const char*", "Binary": "const uint8_t*", "Clock": "bool", "Enumeration": "int64_t",
}
ACCESSOR = {t: t for t in C_TYPES}
ACCESSOR["Enumeration"] = "Int64"

#: The FMI functions a binding calls, numbered for :class:`CallNotes` (the order is the notes' code).
FUNCTIONS = (
    "fmi3InstantiateCoSimulation", "fmi3FreeInstance", "fmi3EnterInitializationMode", "fmi3ExitInitializationMode",
    "fmi3EnterEventMode", "fmi3EnterStepMode", "fmi3Terminate", "fmi3Reset", "fmi3DoStep",
    "fmi3UpdateDiscreteStates", "fmi3GetFMUState", "fmi3SetFMUState", "fmi3FreeFMUState",
    "fmi3GetIntervalDecimal", "fmi3GetShiftDecimal", "fmi3SetIntervalDecimal", "fmi3SetShiftDecimal",
    "fmi3GetClock", "fmi3SetClock",
    *sorted({f"fmi3Get{a}" for a in ACCESSOR.values() if a != "Clock"} | {f"fmi3Set{a}" for a in ACCESSOR.values() if a != "Clock"}),
)
FUNCTION_CODE = {name: code for code, name in enumerate(FUNCTIONS)}
#: The code of a function outside FUNCTIONS (a caller of Binding._call may name any).
UNLISTED = 255

REQUIRED = [name for name in (
    "fmi3GetVersion fmi3InstantiateCoSimulation fmi3FreeInstance fmi3EnterInitializationMode "
    "fmi3ExitInitializationMode fmi3EnterEventMode fmi3Terminate fmi3GetFloat64 fmi3SetFloat64 "
    "fmi3GetClock fmi3SetClock fmi3UpdateDiscreteStates fmi3EnterStepMode fmi3DoStep"
).split()]


class FMI3Error(Exception):
    """An FMI call returned fmi3Discard, fmi3Error or fmi3Fatal (or failed to instantiate)."""

    def __init__(self, function: str, status: int, instance: str = "", message: str = ""):
        self.function, self.status, self.instance, self.message = function, status, instance, message
        who = f"'{instance}': " if instance else ""
        extra = f" ({message})" if message else ""
        super().__init__(f"{who}{function} returned {status_name(status)}{extra}")


class FMUCrashed(FMI3Error):
    """The process running an FMU instance died during a call (an isolated instance: its worker
    process, :mod:`robogen.cosim.proxy`). The instance is gone: it is treated as after fmi3Fatal."""

    def __init__(self, function: str, instance: str, how: str):
        self.how = how  # "SIGSEGV", "exit status 3", ...
        super().__init__(function, FATAL, instance, f"the process running it ended: {how}")


class CallNotes:
    """Where this process notes the FMI call under way: ``call[0]`` is ``(instance << 8) | function``
    (:data:`FUNCTIONS`), ``time[0]`` the communication point or event time the master is at.

    The notes are plain memory, written before each call at the cost of one store; they live in
    ``memory`` (e.g. shared with a watching process, :mod:`robogen.cosim.crash`) or, without it,
    in memory of their own. ``instances`` lists the names the instance numbers stand for.
    """

    SIZE = 16  # bytes: int32 call, int32 spare, double time

    def __init__(self, memory=None):
        self.memory = memory if memory is not None else ffi.new("char[]", self.SIZE)
        self.call = ffi.cast("int32_t *", self.memory)
        self.time = ffi.cast("double *", self.memory + 8)
        self.instances: list[str] = []

    def base(self, instance: str) -> int:
        """The code base of a new instance's calls (its number, shifted)."""
        self.instances.append(instance)
        return (len(self.instances) - 1) << 8

    def describe(self) -> tuple[str, str, float]:
        """(instance, function, time) of the call noted last."""
        code = self.call[0]
        instance = self.instances[code >> 8] if 0 <= code >> 8 < len(self.instances) else "?"
        function = FUNCTIONS[code & 255] if (code & 255) < len(FUNCTIONS) else "?"
        return instance, function, self.time[0]


class LoadError(Exception):
    """The shared object cannot be loaded or lacks an FMI function."""


def vr_array(vrs: Sequence[int]):
    return ffi.new("fmi3ValueReference[]", list(vrs) or [0])


def value_array(fmi_type: str, n: int):
    return ffi.new(f"{C_TYPES[fmi_type]}[]", max(n, 1))


def size_array(n: int):
    """The valueSizes array of fmi3GetBinary/fmi3SetBinary."""
    return ffi.new("size_t[]", max(n, 1))


def decode_strings(values, n: int) -> list[str]:
    """The first n C strings of a ``const char*`` array (NULL reads as empty)."""
    return [ffi.string(p).decode("utf-8", "replace") if p != ffi.NULL else "" for p in values[0:n]]


def decode_binaries(sizes, values, n: int) -> list[bytes]:
    """The first n byte strings of an fmi3Binary array and its sizes."""
    return [ffi.unpack(ffi.cast("char *", p), size) if p != ffi.NULL else b"" for p, size in zip(values[0:n], sizes[0:n])]


def encode(fmi_type: str, values: Sequence) -> tuple[object, object, list]:
    """(value array, sizes array or None, the objects that must outlive the call) for a Set call."""
    if fmi_type == "String":
        keep = [ffi.new("char[]", str(v).encode()) for v in values]
        return ffi.new("const char*[]", keep or 1), None, keep
    if fmi_type == "Binary":
        keep = [ffi.from_buffer(bytes(v)) for v in values]
        pointers = ffi.new("const uint8_t*[]", [ffi.cast("const uint8_t *", k) for k in keep] or 1)
        return pointers, ffi.new("size_t[]", [len(k) for k in keep] or 1), keep
    return ffi.new(f"{C_TYPES[fmi_type]}[]", list(values) or 1), None, []


class Library:
    """An FMU's shared object, opened once per path (several instances share it)."""

    required = REQUIRED  # the functions it must export

    def __init__(self, path: str):
        self.path = path
        try:
            self.lib = ffi.dlopen(path)
        except OSError as exc:
            raise LoadError(f"cannot load the FMU binary {path}: {exc}") from None
        missing = []
        for name in self.required:
            try:
                getattr(self.lib, name)
            except AttributeError:
                missing.append(name)
        if missing:
            raise LoadError(f"the FMU binary {path} does not export {', '.join(missing)}")

    def has(self, name: str) -> bool:
        try:
            getattr(self.lib, name)
            return True
        except AttributeError:
            return False

    def close(self) -> None:
        """Unload the shared object (every instance of it must be freed first). A process that
        loads thousands of FMUs one after the other (the model fuzzer) keeps its memory bounded."""
        if self.lib is not None:
            ffi.dlclose(self.lib)
            self.lib = None

    def fmi3GetVersion(self) -> str:
        return ffi.string(self.lib.fmi3GetVersion()).decode("utf-8", "replace")


@ffi.callback("void(fmi3InstanceEnvironment, fmi3Status, const char*, const char*)")
@signals.callback
def _log_message(env, status, category, message):
    try:
        inst = ffi.from_handle(env)()  # a weak reference to the binding (see Binding.__init__)
        if inst is None:
            return
        text = ffi.string(message).decode("utf-8", "replace") if message != ffi.NULL else ""
        inst.receive_log(status, text)
    except Exception:  # a logger must never raise into C
        pass


def log_message_callback():
    """The fmi3LogMessageCallback every binding gives its instance (its environment: the binding)."""
    return _log_message


class StepResult(NamedTuple):
    """fmi3DoStep's output arguments."""

    event_handling_needed: bool
    terminate_simulation: bool
    early_return: bool
    last_successful_time: float


class DiscreteStates(NamedTuple):
    """fmi3UpdateDiscreteStates's output arguments that the master uses."""

    discrete_states_need_update: bool
    terminate_simulation: bool
    next_event_time_defined: bool
    next_event_time: float


class StepOutputs(NamedTuple):
    """Where fmi3DoStep writes its output arguments (C pointers, made once per binding)."""

    event_handling_needed: object
    terminate_simulation: object
    early_return: object
    last_successful_time: object


#: Makes a named tuple without its Python-level __new__ (a third of the cost) for the results of
#: the calls made at every step.
_tuple_new = tuple.__new__


class LogMemory:
    """What an instance logged that explains a failure: every message it logged at fmi3Error or
    worse (a generated FMU logs the cause, e.g. a machine's deadlock, before the call that fails
    says it failed), else its last message at fmi3Warning or worse, else its last message."""

    __slots__ = ("last", "errors")

    def __init__(self) -> None:
        self.last = ""
        self.errors: list[str] = []

    def note(self, status: int, text: str) -> None:
        if status >= WARNING or not self.last:
            self.last = text
        if status >= ERROR and text not in self.errors:
            self.errors.append(text)

    def message(self) -> str:
        return "; ".join(self.errors) if self.errors else self.last


class Binding:
    """One fmi3Instance. Methods are the FMI 3.0 functions; errors raise FMI3Error."""

    def __init__(self, library: Library, name: str, trace: Callable[[str], None] | None = None,
                 log: Callable[[str, int, str], None] | None = None, notes: CallNotes | None = None):
        self.library, self.lib, self.name = library, library.lib, name
        self.trace, self.log = trace, log
        self.handle = ffi.NULL
        self.logged = LogMemory()
        self.notes = notes if notes is not None else CallNotes()
        self.note_base = self.notes.base(name)
        self._note = self.notes.call
        # The instance environment: a handle to a weak reference, so that the binding and its
        # handle make no reference cycle. A run leaves nothing for Python's cyclic collector,
        # whose full collections walk the whole heap in the middle of a later run.
        self._env = ffi.new_handle(weakref.ref(self))
        self._b4 = ffi.new("bool[6]")
        self._d1 = ffi.new("double[1]")
        self._state = ffi.new("fmi3FMUState*")
        b = self._b4
        self.step_outputs = StepOutputs(b + 0, b + 1, b + 2, self._d1)
        self._code_step = self.note_base | FUNCTION_CODE["fmi3DoStep"]
        self._code_update = self.note_base | FUNCTION_CODE["fmi3UpdateDiscreteStates"]
        self._code_get_float64 = self.note_base | FUNCTION_CODE["fmi3GetFloat64"]

    @property
    def instantiated(self) -> bool:
        return self.handle != ffi.NULL

    def raw(self, function: str):
        """The FMU's C function of this name, for calls that bypass this layer; None while tracing."""
        return getattr(self.lib, function) if self.trace is None else None

    def note_code(self, function: str) -> int:
        """What a loop that bypasses this layer writes to ``notes.call[0]`` before calling ``function``."""
        return self.note_base | FUNCTION_CODE[function]

    def error(self, function: str, status: int) -> FMI3Error:
        """The error for ``function`` having returned ``status``, with the FMU's last message."""
        return FMI3Error(function, status, self.name, self.logged.message())

    # -- plumbing ------------------------------------------------------------------------
    def receive_log(self, status: int, text: str) -> None:
        self.logged.note(status, text)
        if self.log is not None:
            self.log(self.name, status, text)

    def _trace(self, function: str, args: tuple, status: int) -> None:
        shown = ", ".join(_show(a) for a in args)
        self.trace(f"{function}({self.name}{', ' if shown else ''}{shown}) -> {status_name(status)}")

    def _call(self, function: str, *args) -> int:
        self._note[0] = self.note_base | FUNCTION_CODE.get(function, UNLISTED)
        status = getattr(self.lib, function)(self.handle, *args)
        if self.trace is not None:
            self._trace(function, args, status)
        if status > WARNING:
            raise self.error(function, status)
        return status

    # -- life cycle ------------------------------------------------------------------------
    def fmi3InstantiateCoSimulation(self, instantiationToken: str, resourcePath: str | None, visible: bool = False,
                                    loggingOn: bool = False, eventModeUsed: bool = False,
                                    earlyReturnAllowed: bool = False) -> None:
        res = ffi.new("char[]", resourcePath.encode()) if resourcePath else ffi.NULL
        self._note[0] = self.note_base | FUNCTION_CODE["fmi3InstantiateCoSimulation"]
        self.handle = self.lib.fmi3InstantiateCoSimulation(
            self.name.encode(), instantiationToken.encode(), res, visible, loggingOn, eventModeUsed,
            earlyReturnAllowed, ffi.NULL, 0, self._env, _log_message, ffi.NULL)
        if self.trace is not None:
            self.trace(f"fmi3InstantiateCoSimulation({self.name}, eventModeUsed={eventModeUsed}, "
                       f"earlyReturnAllowed={earlyReturnAllowed}) -> {'NULL' if self.handle == ffi.NULL else 'instance'}")
        if self.handle == ffi.NULL:
            raise self.error("fmi3InstantiateCoSimulation", ERROR)

    def fmi3FreeInstance(self) -> None:
        if self.handle != ffi.NULL:
            self._note[0] = self.note_base | FUNCTION_CODE["fmi3FreeInstance"]
            self.lib.fmi3FreeInstance(self.handle)
            if self.trace is not None:
                self.trace(f"fmi3FreeInstance({self.name})")
            self.handle = ffi.NULL

    def fmi3EnterInitializationMode(self, tolerance: float | None, startTime: float, stopTime: float | None) -> int:
        return self._call("fmi3EnterInitializationMode", tolerance is not None, tolerance or 0.0, startTime,
                          stopTime is not None, stopTime if stopTime is not None else 0.0)

    def fmi3ExitInitializationMode(self) -> int:
        return self._call("fmi3ExitInitializationMode")

    def fmi3EnterEventMode(self) -> int:
        return self._call("fmi3EnterEventMode")

    def fmi3EnterStepMode(self) -> int:
        return self._call("fmi3EnterStepMode")

    def fmi3Terminate(self) -> int:
        return self._call("fmi3Terminate")

    def fmi3Reset(self) -> int:
        return self._call("fmi3Reset")

    # -- values ----------------------------------------------------------------------------
    def get(self, fmi_type: str, vrs, n: int, values, sizes=None, n_values: int | None = None) -> None:
        """fmi3Get<Type>(vrs, n, values, nValues) into a caller-owned buffer (Binary: and ``sizes``);
        ``n_values`` is ``n`` unless array variables are among ``vrs``."""
        if fmi_type == "Clock":
            self._call("fmi3GetClock", vrs, n, values)
        elif fmi_type == "Binary":
            self._call("fmi3GetBinary", vrs, n, sizes, values, n if n_values is None else n_values)
        else:
            self._call("fmi3Get" + ACCESSOR[fmi_type], vrs, n, values, n if n_values is None else n_values)

    def set(self, fmi_type: str, vrs, n: int, values, sizes=None, n_values: int | None = None) -> None:
        if fmi_type == "Clock":
            self._call("fmi3SetClock", vrs, n, values)
        elif fmi_type == "Binary":
            self._call("fmi3SetBinary", vrs, n, sizes, values, n if n_values is None else n_values)
        else:
            self._call("fmi3Set" + ACCESSOR[fmi_type], vrs, n, values, n if n_values is None else n_values)

    def get_values(self, fmi_type: str, vrs: Sequence[int], n_values: int | None = None) -> list:
        """The values of ``vrs`` (all of ``fmi_type``) as a Python list (``n_values`` of them where
        arrays are read: their elements in order)."""
        n = len(vrs)
        m = n if n_values is None else n_values
        values, sizes = value_array(fmi_type, m), size_array(n) if fmi_type == "Binary" else None
        self.get(fmi_type, vr_array(vrs), n, values, sizes, m)
        if fmi_type == "String":
            return decode_strings(values, n)
        if fmi_type == "Binary":
            return decode_binaries(sizes, values, n)
        return ffi.unpack(values, m)

    def set_values(self, fmi_type: str, vrs: Sequence[int], values: Sequence) -> None:
        """Set ``vrs`` (all of ``fmi_type``) to ``values``."""
        buffer, sizes, _keep = encode(fmi_type, values)
        self.set(fmi_type, vr_array(vrs), len(vrs), buffer, sizes)

    def set_array(self, fmi_type: str, vr: int, values: Sequence) -> None:
        """Set the array variable ``vr`` (of ``fmi_type``, not String or Binary) to ``values``,
        its elements in row-major order: one value reference, ``len(values)`` values."""
        buffer, _sizes, _keep = encode(fmi_type, values)
        self._call("fmi3Set" + ACCESSOR[fmi_type], vr_array([vr]), 1, buffer, len(values))

    def fmi3GetFloat64(self, vrs, n: int, values) -> int:
        if self.trace is not None:
            return self._call("fmi3GetFloat64", vrs, n, values, n)
        self._note[0] = self._code_get_float64
        status = self.lib.fmi3GetFloat64(self.handle, vrs, n, values, n)
        if status > WARNING:
            raise self.error("fmi3GetFloat64", status)
        return status

    def fmi3SetFloat64(self, vrs, n: int, values) -> int:
        return self._call("fmi3SetFloat64", vrs, n, values, n)

    def fmi3GetClock(self, vrs, n: int, values) -> int:
        return self._call("fmi3GetClock", vrs, n, values)

    def fmi3SetClock(self, vrs, n: int, values) -> int:
        return self._call("fmi3SetClock", vrs, n, values)

    def fmi3GetIntervalDecimal(self, vrs, n: int) -> tuple[list[float], list[int]]:
        intervals, qualifiers = ffi.new("double[]", max(n, 1)), ffi.new("int[]", max(n, 1))
        self._call("fmi3GetIntervalDecimal", vrs, n, intervals, qualifiers)
        return list(intervals)[:n], list(qualifiers)[:n]

    def fmi3GetShiftDecimal(self, vrs, n: int) -> list[float]:
        shifts = ffi.new("double[]", max(n, 1))
        self._call("fmi3GetShiftDecimal", vrs, n, shifts)
        return list(shifts)[:n]

    def fmi3SetIntervalDecimal(self, vrs, n: int, intervals: Sequence[float]) -> int:
        return self._call("fmi3SetIntervalDecimal", vrs, n, ffi.new("double[]", list(intervals)))

    def fmi3SetShiftDecimal(self, vrs, n: int, shifts: Sequence[float]) -> int:
        return self._call("fmi3SetShiftDecimal", vrs, n, ffi.new("double[]", list(shifts)))

    # -- FMU state -------------------------------------------------------------------------
    def fmi3GetFMUState(self):
        self._call("fmi3GetFMUState", self._state)
        return self._state[0]

    def fmi3SetFMUState(self, state) -> int:
        return self._call("fmi3SetFMUState", state)

    def fmi3FreeFMUState(self) -> None:
        if self._state[0] != ffi.NULL and self.handle != ffi.NULL:
            self._note[0] = self.note_base | FUNCTION_CODE["fmi3FreeFMUState"]
            self.lib.fmi3FreeFMUState(self.handle, self._state)

    # -- Event Mode and Step Mode ------------------------------------------------------------
    def fmi3UpdateDiscreteStates(self) -> DiscreteStates:
        b, d = self._b4, self._d1
        self._note[0] = self._code_update
        status = self.lib.fmi3UpdateDiscreteStates(self.handle, b, b + 1, b + 2, b + 3, b + 4, d)
        if self.trace is not None:
            self._trace("fmi3UpdateDiscreteStates", (), status)
        if status > WARNING:
            raise self.error("fmi3UpdateDiscreteStates", status)
        return _tuple_new(DiscreteStates, (b[0], b[1], b[4], d[0]))

    def fmi3DoStep(self, currentCommunicationPoint: float, communicationStepSize: float,
                   noSetFMUStatePriorToCurrentPoint: bool = True) -> StepResult:
        b, d = self._b4, self._d1
        self._note[0] = self._code_step
        status = self.lib.fmi3DoStep(self.handle, currentCommunicationPoint, communicationStepSize,
                                     noSetFMUStatePriorToCurrentPoint, b, b + 1, b + 2, d)
        if self.trace is not None:
            self._trace("fmi3DoStep", (currentCommunicationPoint, communicationStepSize), status)
        if status > WARNING:
            raise self.error("fmi3DoStep", status)
        return _tuple_new(StepResult, (b[0], b[1], b[2], d[0]))


def _show(value) -> str:
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, (bool, int, str)):
        return str(value)
    return "..."
