"""Adapters: an instance the engine cannot call directly, called through Python behind the same
C function pointers.

The engine (:mod:`robogen.cosim.engine`) calls every instance through C function pointers of
the types ``engine.h`` declares. For an instance in this process they are its FMU's own
functions (:meth:`robogen.cosim.fmi3.Binding.raw`). For one whose binding gives none (an instance
in a worker process, :mod:`robogen.cosim.proxy`, or one traced: every call is seen) they are the
callbacks of this module, whose first argument is the handle of an :class:`Adapter` holding the
binding: each callback makes the binding's call and writes its results where the engine expects
them. A call that fails keeps its exception (an :class:`~robogen.cosim.fmi3.FMUCrashed` stays one)
and returns its status; the engine then stops and Python raises it. The callbacks are the
master's (:func:`robogen.cosim.signals.callback`): a signal that arrives in one stops the
engine as the callback returns, and Python raises :class:`~robogen.cosim.signals.Interrupted`.
"""

from __future__ import annotations

from robogen.cosim import signals
from robogen.cosim.fmi3 import ACCESSOR, C_TYPES, FMI3Error, value_array, vr_array
from robogen.fmu.fmi import ERROR


class Adapter:
    """One instance's binding, called by the engine through this module's callbacks."""

    def __init__(self, binding, ffi):
        self.binding, self.ffi = binding, ffi
        self.handle = ffi.new_handle(self)
        self.failure: BaseException | None = None
        self.kept: dict[str, list] = {}  # per type: what the last Get of Strings or Binaries points to

    def fail(self, exc: BaseException) -> int:
        self.failure = exc
        return exc.status if isinstance(exc, FMI3Error) else ERROR

    def function(self, name: str):
        """The callback the engine calls for ``name`` (an FMI function) on this adapter's handle."""
        return _callbacks(self.ffi)[name]


_MADE: dict[int, dict[str, object]] = {}


def _callbacks(ffi) -> dict[str, object]:
    """The callbacks of every function the engine calls, made once per FFI."""
    made = _MADE.get(id(ffi))
    if made is None:
        made = _MADE[id(ffi)] = _make(ffi)
    return made


def _adapter(ffi, handle) -> Adapter:
    return ffi.from_handle(handle)


def _make(ffi) -> dict[str, object]:  # noqa: C901 - one small closure per function
    made: dict[str, object] = {}

    def callback(ctype: str, name: str):
        def register(body):
            marked = signals.callback(body)

            def call(handle, *args):
                adapter = _adapter(ffi, handle)
                try:
                    status = marked(adapter, *args)
                except BaseException as exc:  # never into C: the engine stops, Python raises it
                    return adapter.fail(exc)
                if signals.caught() is not None:  # a signal came during the call: stop the run here
                    return adapter.fail(signals.Interrupted(signals.caught()))
                return status

            made[name] = ffi.callback(ctype, signals.callback(call))
            return body
        return register

    @callback("rg_do_step_fn", "fmi3DoStep")
    def do_step(adapter, t, h, no_set, event, terminate, early, last):
        result = adapter.binding.fmi3DoStep(t, h, no_set)
        event[0], terminate[0], early[0], last[0] = result
        return 0

    for mode in ("fmi3EnterEventMode", "fmi3EnterStepMode"):
        callback("rg_mode_fn", mode)(lambda adapter, _mode=mode: getattr(adapter.binding, _mode)() and 0)

    @callback("rg_update_fn", "fmi3UpdateDiscreteStates")
    def update(adapter, need, terminate, nominals, values, next_defined, next_time):
        states = adapter.binding.fmi3UpdateDiscreteStates()
        need[0], terminate[0], nominals[0], values[0] = states.discrete_states_need_update, states.terminate_simulation, False, False
        next_defined[0], next_time[0] = states.next_event_time_defined, states.next_event_time
        return 0

    @callback("rg_get_clock_fn", "fmi3GetClock")
    def get_clock(adapter, vrs, n, values):
        buffer = value_array("Clock", n)
        adapter.binding.fmi3GetClock(vr_array(ffi.unpack(vrs, n)), n, buffer)
        for i in range(n):
            values[i] = bool(buffer[i])
        return 0

    @callback("rg_set_clock_fn", "fmi3SetClock")
    def set_clock(adapter, vrs, n, values):
        from robogen.cosim.fmi3 import ffi as fmi_ffi

        adapter.binding.fmi3SetClock(vr_array(ffi.unpack(vrs, n)), n, fmi_ffi.new("bool[]", ffi.unpack(values, n) or 1))
        return 0

    @callback("rg_get_interval_fn", "fmi3GetIntervalDecimal")
    def get_interval(adapter, vrs, n, intervals, qualifiers):
        got, kinds = adapter.binding.fmi3GetIntervalDecimal(vr_array(ffi.unpack(vrs, n)), n)
        for i in range(n):
            intervals[i], qualifiers[i] = got[i], kinds[i]
        return 0

    for fmi_type in sorted(set(ACCESSOR) - {"Clock", "Enumeration"}):
        _values(ffi, callback, fmi_type)
    return made


def _values(ffi, callback, fmi_type: str) -> None:
    """The Get and Set callbacks of one FMI type."""
    if fmi_type == "Binary":
        @callback("rg_get_binary_fn", "fmi3GetBinary")
        def get_binary(adapter, vrs, n, sizes, values, _n):
            got = adapter.binding.get_values("Binary", ffi.unpack(vrs, n))
            kept = adapter.kept["Binary"] = [ffi.new("char[]", bytes(v)) for v in got]
            for i, (v, data) in enumerate(zip(got, kept)):
                sizes[i], values[i] = len(v), ffi.cast("uint8_t *", data)
            return 0

        @callback("rg_set_binary_fn", "fmi3SetBinary")
        def set_binary(adapter, vrs, n, sizes, values, _n):
            data = [ffi.unpack(ffi.cast("char *", values[i]), sizes[i]) for i in range(n)]
            adapter.binding.set_values("Binary", ffi.unpack(vrs, n), data)
            return 0
        return
    accessor = ACCESSOR[fmi_type]
    pointer = C_TYPES[fmi_type] + " *"

    @callback("rg_get_fn", f"fmi3Get{accessor}")
    def get(adapter, vrs, n, values, n_values):
        got = adapter.binding.get_values(fmi_type, ffi.unpack(vrs, n), *((n_values,) if n_values != n else ()))
        if fmi_type == "String":
            kept = adapter.kept["String"] = [ffi.new("char[]", v.encode()) for v in got]
            out = ffi.cast("const char **", values)
            for i, data in enumerate(kept):
                out[i] = data
        else:
            ffi.cast(pointer, values)[0:n_values] = got
        return 0

    @callback("rg_set_fn", f"fmi3Set{accessor}")
    def set_(adapter, vrs, n, values, _n):
        if fmi_type == "String":
            texts = ffi.cast("const char **", values)
            data = [ffi.string(texts[i]).decode("utf-8", "replace") for i in range(n)]
        else:
            data = ffi.unpack(ffi.cast(pointer, values), n)
        adapter.binding.set_values(fmi_type, ffi.unpack(vrs, n), data)
        return 0
