"""The Python half of the cffi embedding: binds the ``pyfmu_py_*`` functions of bridge.h.

``build.py`` appends a call ``bind(ffi, lib, CONFIG)`` to this source and passes the whole text
to ``ffi.embedding_init_code``, so it runs once per FMU binary, inside the FMU's own cffi module,
at the first call into Python (``fmi3InstantiateCoSimulation``). It imports only the standard
library at that point; the model class and :mod:`robogen.pyfmu.slave` are imported at
instantiation from the FMU's ``resources/python`` folder, known only then.

Every bound function catches every exception: an FMI usage error is logged as its message, any
other exception as its type, message and place in the model's code with the model's frames of
its traceback, a KeyboardInterrupt (a signal the host turned into one while the model ran) as an
interruption; the call returns fmi3Error (instantiation: NULL). Errors are logged whether
logging is on or not (shim.c). An exception can still escape a bound function outside its
``try``: a signal the host's Python handler turns into one at the function's first bytecode, or
while a failure is reported. cffi then calls the ``onerror`` given here, which handles it the
same way, where it would otherwise print a traceback on the host's stderr; the ``error=`` values
are the last resort should that fail too.
"""

from __future__ import annotations

import importlib
import json
import site
import sys
import traceback
from pathlib import Path
from typing import Any

ERROR = 3  # fmi3Error, as robogen.fmu.fmi.ERROR (this code runs before robogen is importable)


def _add_site_dirs(dirs: list[str]) -> None:
    """Make the environment the FMU was built in importable (cffi, numpy, pybullet, ...)."""
    for folder in dirs:
        if folder not in sys.path and Path(folder).is_dir():
            site.addsitedir(folder)  # also runs its .pth files (editable installs)


def _extend_imported_packages(python_dir: Path) -> None:
    """Packages of the FMU's code that the process already imported (from the host or another
    FMU) get this FMU's folder on their ``__path__``, so their modules that only this FMU ships
    are found too (pkgutil.extend_path does the same for namespace packages)."""
    for init in sorted(python_dir.rglob("__init__.py")):
        package = ".".join(init.parent.relative_to(python_dir).parts)
        module = sys.modules.get(package)
        path = getattr(module, "__path__", None)
        if path is not None and str(init.parent) not in list(path):
            path.append(str(init.parent))


def _resource_folder(raw: str) -> Path:
    if raw.startswith("file://"):  # tolerate FMI 2-style URIs
        from urllib.parse import unquote, urlparse
        raw = unquote(urlparse(raw).path)
    return Path(raw)


def _describe(function: str, exc: BaseException) -> str:
    """The report of an exception from the model: its traceback as Python prints it, but with the
    frames of the model's own code only (not robogen's runtime), the last line naming where in
    the model it was raised: ``RuntimeError: ... (at model.py:50 in do_step)``."""
    frames = [f for f in traceback.extract_tb(exc.__traceback__)
              if "/robogen/pyfmu/" not in f.filename and not f.filename.startswith("<")]
    last = "".join(traceback.format_exception_only(type(exc), exc)).rstrip("\n")
    if frames:
        where = frames[-1]
        shown = where.filename.split("/resources/python/", 1)[-1]  # the module as the user knows it
        last += f" (at {shown}:{where.lineno} in {where.name})"
    return "\n".join([f"{function}: Python exception in the FMU", "Traceback (most recent call last):",
                      *(line.rstrip("\n") for line in traceback.format_list(frames)), last])


def bind(ffi: Any, lib: Any, config: dict) -> None:
    """Bind every ``pyfmu_py_*`` function of bridge.h to Python (once per FMU binary)."""
    _add_site_dirs(config["site_dirs"])
    embedding = _Embedding(ffi, lib, config)
    embedding.bind_creation()
    embedding.bind_life_cycle()
    embedding.bind_values()
    embedding.bind_clocks()
    embedding.bind_steps()


class _Log:
    """The importer's logMessage callback for one C instance, as the slave and the model call it;
    ``enabled`` tells whether a message would reach the importer (logging on for its category, or
    an error), so that none is formatted in vain."""

    __slots__ = ("lib", "c_instance")

    def __init__(self, lib: Any, c_instance: Any) -> None:
        self.lib, self.c_instance = lib, c_instance

    def __call__(self, status: int, category: str, message: str) -> None:
        self.lib.pyfmu_log(self.c_instance, status, category.encode("utf-8"), message.encode("utf-8", "replace"))

    def enabled(self, status: int, category: str) -> bool:
        return bool(self.lib.pyfmu_log_enabled(self.c_instance, status, category.encode("utf-8")))


class _Instance:
    """One live FMU instance: its slave, the C instance it logs through, and the strings the
    last fmi3GetString returned (valid until the next call, as FMI 3.0 requires)."""

    __slots__ = ("slave", "c_instance", "strings", "usage_error")

    def __init__(self, slave: Any, c_instance: Any, usage_error: type) -> None:
        self.slave = slave
        self.c_instance = c_instance
        self.strings: list[Any] = []
        self.usage_error = usage_error


class _Embedding:
    """The FMU binary's Python side: its live instances by handle (the integer the C shim keeps),
    the model classes loaded per resources folder, and the bound functions."""

    def __init__(self, ffi: Any, lib: Any, config: dict) -> None:
        self.ffi = ffi
        self.lib = lib
        self.token = config["token"]
        self.instances: dict[int, _Instance] = {}
        self.last_handle = 0
        self.loaded: dict[str, tuple[type, Any]] = {}

    # -- helpers ----------------------------------------------------------------------------

    def logger(self, c_instance: Any) -> "_Log":
        return _Log(self.lib, c_instance)

    def report(self, c_instance: Any, function: str, exc: BaseException, usage_error: type | None) -> None:
        """Log an exception (always: the FMU returns fmi3Error): a usage error as its message, an
        interruption (Ctrl-C in the host) as such, anything else as its type, message and place
        in the model's code, then the traceback of the model's frames."""
        if usage_error is not None and isinstance(exc, usage_error):
            text = str(exc)
        elif isinstance(exc, KeyboardInterrupt):
            text = f"{function}: interrupted ({exc or type(exc).__name__})"
        else:
            text = _describe(function, exc)
        self.logger(c_instance)(ERROR, "logStatusError", text)

    def load(self, resources: Path) -> tuple[type, Any]:
        """The configured model class and the slave module of the FMU unpacked at ``resources``."""
        key = str(resources)
        if key not in self.loaded:
            meta = json.loads((resources / "pyfmu.json").read_text(encoding="utf-8"))
            python_dir = resources / "python"
            if str(python_dir) not in sys.path:
                sys.path.insert(0, str(python_dir))
            _extend_imported_packages(python_dir)
            slave_module = importlib.import_module("robogen.pyfmu.slave")
            model_class = getattr(importlib.import_module(meta["module"]), meta["class"])
            self.loaded[key] = (model_class.configured(meta["settings"]), slave_module)
        return self.loaded[key]

    def text(self, value: Any) -> str:
        return self.ffi.string(value).decode("utf-8") if value != self.ffi.NULL else ""

    def failed(self, inst: _Instance, function: str, exc: BaseException) -> int:
        """An exception from ``function`` becomes fmi3Error, its log message, and the Terminated
        state FMI 3.0 leaves an instance in after an error."""
        self.report(inst.c_instance, function, exc, inst.usage_error)
        inst.slave.failed()
        return ERROR

    def export(self, c_name: str, function: str, method: Any) -> None:
        """Bind the bridge function ``c_name`` to ``method(instance, *C arguments)``: 0 (fmi3OK),
        or fmi3Error for an unknown instance or any exception (:meth:`failed`). One Python
        frame of its own per call: the entry is on every FMI call's path."""
        instances, failed = self.instances, self.failed

        def entry(handle, *args):
            inst = instances.get(handle)
            if inst is None:
                return ERROR
            try:
                method(inst, *args)
            except BaseException as exc:  # noqa: BLE001 - nothing may escape into the host
                return failed(inst, function, exc)
            return 0

        def escaped(_type, exc, tb):
            """An exception outside ``entry``'s ``try``: a signal the host handles at entry's
            first bytecode, or while the failure is reported. It is the call's failure all the
            same (cffi would print its traceback to the host's stderr)."""
            inst = instances.get(tb.tb_frame.f_locals.get("handle")) if tb is not None else None
            if inst is not None:
                try:
                    return failed(inst, function, exc)
                except BaseException:  # noqa: BLE001 - a second signal: the host knows already
                    pass
            return ERROR
        self.ffi.def_extern(name=c_name, error=ERROR, onerror=escaped)(entry)

    # -- creation ---------------------------------------------------------------------------

    def instantiate(self, c_instance, name, token, resource_path, visible, logging_on, event_mode_used,
                    early_return_allowed) -> int:
        """A new instance's handle, or 0 after logging why there is none."""
        log = self.logger(c_instance)
        usage_error = None
        try:
            if self.text(token) != self.token:
                log(ERROR, "logStatusError",
                    f"wrong instantiationToken {self.text(token)!r}; this FMU's is {self.token!r}")
                return 0
            if resource_path == self.ffi.NULL:
                log(ERROR, "logStatusError",
                    "resourcePath is NULL: this FMU's Python code lives in its resources/ folder")
                return 0
            resources = _resource_folder(self.text(resource_path))
            model_class, slave_module = self.load(resources)
            usage_error = slave_module.FmiUsageError
            slave = slave_module.Slave(
                model_class, instance_name=self.text(name), resource_path=resources,
                event_mode_used=bool(event_mode_used), early_return_allowed=bool(early_return_allowed), logger=log)
        except BaseException as exc:  # noqa: BLE001
            self.report(c_instance, "fmi3InstantiateCoSimulation", exc, usage_error)
            return 0
        self.last_handle += 1
        self.instances[self.last_handle] = _Instance(slave, c_instance, usage_error)
        return self.last_handle

    def free_instance(self, handle) -> None:
        inst = self.instances.pop(handle, None)
        if inst is not None:
            try:
                inst.slave.free()
            except BaseException as exc:  # noqa: BLE001
                self.report(inst.c_instance, "fmi3FreeInstance", exc, inst.usage_error)

    def bind_creation(self) -> None:
        self.ffi.def_extern(name="pyfmu_py_instantiate", error=0, onerror=self.escaped_instantiation)(self.instantiate)
        self.ffi.def_extern(name="pyfmu_py_free_instance", onerror=self.escaped_free)(self.free_instance)

    def escaped_instantiation(self, _type, exc, tb) -> int:
        """As ``escaped`` in :meth:`export`, for an exception outside instantiate's ``try``: no
        instance (NULL), and the reason logged."""
        c_instance = tb.tb_frame.f_locals.get("c_instance") if tb is not None else None
        if c_instance is not None:
            try:
                self.report(c_instance, "fmi3InstantiateCoSimulation", exc, None)
            except BaseException:  # noqa: BLE001
                pass
        return 0

    def escaped_free(self, _type, _exc, tb) -> None:
        """As ``escaped`` in :meth:`export`, for fmi3FreeInstance: the instance is freed all the same."""
        inst = self.instances.pop(tb.tb_frame.f_locals.get("handle"), None) if tb is not None else None
        if inst is not None:
            try:
                inst.slave.free()
            except BaseException:  # noqa: BLE001
                pass

    # -- life cycle -------------------------------------------------------------------------

    def bind_life_cycle(self) -> None:
        export = self.export
        export("pyfmu_py_enter_initialization_mode", "fmi3EnterInitializationMode",
               lambda i, tol_defined, tol, start, stop_defined, stop: i.slave.enter_initialization_mode(
                   tol if tol_defined else None, start, stop if stop_defined else None))
        export("pyfmu_py_exit_initialization_mode", "fmi3ExitInitializationMode",
               lambda i: i.slave.exit_initialization_mode())
        export("pyfmu_py_enter_event_mode", "fmi3EnterEventMode", lambda i: i.slave.enter_event_mode())
        export("pyfmu_py_enter_step_mode", "fmi3EnterStepMode", lambda i: i.slave.enter_step_mode())
        export("pyfmu_py_terminate", "fmi3Terminate", lambda i: i.slave.terminate())
        export("pyfmu_py_reset", "fmi3Reset", lambda i: i.slave.reset())

    # -- values -----------------------------------------------------------------------------

    @staticmethod
    def check_counts(inst: _Instance, function: str, nvr: int, nvalues: int) -> None:
        if nvalues != nvr:
            raise inst.usage_error(f"{function}: nValues ({nvalues}) must equal nValueReferences ({nvr}): "
                                   "the FMU has no arrays")

    def getter(self, function: str, type_name: str):
        unpack, check_counts = self.ffi.unpack, self.check_counts

        def get(inst, vr, nvr, values, nvalues):
            if nvalues != nvr:
                check_counts(inst, function, nvr, nvalues)
            values[0:nvr] = inst.slave.get(function, type_name, unpack(vr, nvr))
        return get

    def setter(self, function: str, type_name: str):
        def set_(inst, vr, nvr, values, nvalues):
            self.check_counts(inst, function, nvr, nvalues)
            inst.slave.set(function, type_name, self.ffi.unpack(vr, nvr), self.ffi.unpack(values, nvalues))
        return set_

    def get_strings(self, inst, vr, nvr, values, nvalues) -> None:
        self.check_counts(inst, "fmi3GetString", nvr, nvalues)
        result = inst.slave.get("fmi3GetString", "String", self.ffi.unpack(vr, nvr))
        inst.strings = [self.ffi.new("char[]", s.encode("utf-8")) for s in result]  # valid until the next call
        for k, buffer in enumerate(inst.strings):
            values[k] = buffer

    def set_strings(self, inst, vr, nvr, values, nvalues) -> None:
        self.check_counts(inst, "fmi3SetString", nvr, nvalues)
        inst.slave.set("fmi3SetString", "String", self.ffi.unpack(vr, nvr),
                       [self.text(values[k]) for k in range(nvalues)])

    def bind_values(self) -> None:
        for type_name in ("Float64", "Int32", "Int64", "Boolean"):
            get, set_ = f"fmi3Get{type_name}", f"fmi3Set{type_name}"
            self.export(f"pyfmu_py_get_{type_name.lower()}", get, self.getter(get, type_name))
            self.export(f"pyfmu_py_set_{type_name.lower()}", set_, self.setter(set_, type_name))
        self.export("pyfmu_py_get_string", "fmi3GetString", self.get_strings)
        self.export("pyfmu_py_set_string", "fmi3SetString", self.set_strings)

    # -- clocks -----------------------------------------------------------------------------

    def get_clock(self, inst, vr, nvr, values) -> None:
        values[0:nvr] = inst.slave.get_clock(self.ffi.unpack(vr, nvr))

    def set_clock(self, inst, vr, nvr, values) -> None:
        inst.slave.set_clock(self.ffi.unpack(vr, nvr), self.ffi.unpack(values, nvr))

    def get_intervals(self, inst, vr, nvr, intervals, qualifiers) -> None:
        values, kinds = inst.slave.get_interval_decimal(self.ffi.unpack(vr, nvr))
        for k in range(nvr):
            intervals[k], qualifiers[k] = values[k], kinds[k]

    def get_shifts(self, inst, vr, nvr, shifts) -> None:
        for k, value in enumerate(inst.slave.get_shift_decimal(self.ffi.unpack(vr, nvr))):
            shifts[k] = value

    def bind_clocks(self) -> None:
        self.export("pyfmu_py_get_clock", "fmi3GetClock", self.get_clock)
        self.export("pyfmu_py_set_clock", "fmi3SetClock", self.set_clock)
        self.export("pyfmu_py_get_interval_decimal", "fmi3GetIntervalDecimal", self.get_intervals)
        self.export("pyfmu_py_get_shift_decimal", "fmi3GetShiftDecimal", self.get_shifts)

    # -- event instants and steps -----------------------------------------------------------

    @staticmethod
    def update(inst, flags, next_event_time) -> None:
        result = inst.slave.update_discrete_states()
        flags[0] = result.discrete_states_need_update
        flags[1] = result.terminate
        flags[2] = result.next_event_time_defined
        next_event_time[0] = result.next_event_time

    @staticmethod
    def step(inst, t, h, flags, last_successful_time) -> None:
        result = inst.slave.do_step(t, h)
        flags[0] = result.event_handling_needed
        flags[1] = result.terminate
        flags[2] = result.early_return
        last_successful_time[0] = result.last_successful_time

    def bind_steps(self) -> None:
        self.export("pyfmu_py_update_discrete_states", "fmi3UpdateDiscreteStates", self.update)
        self.export("pyfmu_py_do_step", "fmi3DoStep", self.step)
