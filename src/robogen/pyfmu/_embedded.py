"""The Python half of the cffi embedding: binds the ``pyfmu_py_*`` functions of bridge.h.

``build.py`` appends a call ``bind(ffi, lib, CONFIG)`` to this source and passes the whole text
to ``ffi.embedding_init_code``, so it runs once per FMU binary, inside the FMU's own cffi module,
at the first call into Python (``fmi3InstantiateCoSimulation``). It imports only the standard
library at that point; the model class and :mod:`robogen.pyfmu.slave` are imported at
instantiation from the FMU's ``resources/python`` folder, known only then.

Every bound function catches every exception: an FMI usage error is logged as its message, any
other exception with its traceback, and the call returns fmi3Error (instantiation: NULL). The
``error=`` values below are cffi's last resort should that handling itself fail.
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


def bind(ffi: Any, lib: Any, config: dict) -> None:
    _add_site_dirs(config["site_dirs"])
    instances: dict[int, "_Instance"] = {}
    counter = [0]
    loaded: dict[str, tuple[type, Any]] = {}

    class _Instance:
        __slots__ = ("slave", "c_instance", "strings", "usage_error")

        def __init__(self, slave: Any, c_instance: Any, usage_error: type) -> None:
            self.slave = slave
            self.c_instance = c_instance
            self.strings: list[Any] = []
            self.usage_error = usage_error

    def logger(c_instance: Any):
        def log(status: int, category: str, message: str) -> None:
            lib.pyfmu_log(c_instance, status, category.encode("utf-8"), message.encode("utf-8", "replace"))
        return log

    def report(c_instance: Any, function: str, exc: BaseException, usage_error: type | None) -> None:
        if usage_error is not None and isinstance(exc, usage_error):
            text = str(exc)
        else:
            text = f"{function}: Python exception in the FMU\n" + "".join(
                traceback.format_exception(type(exc), exc, exc.__traceback__))
        logger(c_instance)(ERROR, "logStatusError", text)

    def load(resources: Path) -> tuple[type, Any]:
        key = str(resources)
        if key not in loaded:
            meta = json.loads((resources / "pyfmu.json").read_text(encoding="utf-8"))
            python_dir = resources / "python"
            if str(python_dir) not in sys.path:
                sys.path.insert(0, str(python_dir))
            _extend_imported_packages(python_dir)
            slave_module = importlib.import_module("robogen.pyfmu.slave")
            model_class = getattr(importlib.import_module(meta["module"]), meta["class"])
            loaded[key] = (model_class.configured(meta["settings"]), slave_module)
        return loaded[key]

    def call(handle: int, function: str, method: Any, *args: Any) -> int:
        inst = instances.get(handle)
        if inst is None:
            return ERROR
        try:
            method(inst, *args)
        except BaseException as exc:  # noqa: BLE001 - nothing may escape into the host
            report(inst.c_instance, function, exc, inst.usage_error)
            inst.slave.failed()
            return ERROR
        return 0

    def text(value: Any) -> str:
        return ffi.string(value).decode("utf-8") if value != ffi.NULL else ""

    # -- creation -----------------------------------------------------------------------------

    @ffi.def_extern(error=0)
    def pyfmu_py_instantiate(c_instance, name, token, resource_path, visible, logging_on, event_mode_used,
                             early_return_allowed):
        usage_error = None
        try:
            if text(token) != config["token"]:
                logger(c_instance)(ERROR, "logStatusError",
                                   f"wrong instantiationToken {text(token)!r}; this FMU's is {config['token']!r}")
                return 0
            if resource_path == ffi.NULL:
                logger(c_instance)(ERROR, "logStatusError",
                                   "resourcePath is NULL: this FMU's Python code lives in its resources/ folder")
                return 0
            resources = _resource_folder(text(resource_path))
            model_class, slave_module = load(resources)
            usage_error = slave_module.FmiUsageError
            slave = slave_module.Slave(
                model_class, instance_name=text(name), resource_path=resources,
                event_mode_used=bool(event_mode_used), early_return_allowed=bool(early_return_allowed),
                logger=logger(c_instance))
        except BaseException as exc:  # noqa: BLE001
            report(c_instance, "fmi3InstantiateCoSimulation", exc, usage_error)
            return 0
        counter[0] += 1
        instances[counter[0]] = _Instance(slave, c_instance, usage_error)
        return counter[0]

    @ffi.def_extern()
    def pyfmu_py_free_instance(handle):
        inst = instances.pop(handle, None)
        if inst is not None:
            try:
                inst.slave.free()
            except BaseException as exc:  # noqa: BLE001
                report(inst.c_instance, "fmi3FreeInstance", exc, inst.usage_error)

    def export(c_name: str, function: str, method: Any) -> None:
        """Bind the bridge function ``c_name`` to ``method(instance, *C arguments)``."""
        def entry(handle, *args):
            return call(handle, function, method, *args)
        ffi.def_extern(name=c_name, error=ERROR)(entry)

    # -- life cycle ---------------------------------------------------------------------------

    export("pyfmu_py_enter_initialization_mode", "fmi3EnterInitializationMode",
           lambda i, tol_defined, tol, start, stop_defined, stop: i.slave.enter_initialization_mode(
               tol if tol_defined else None, start, stop if stop_defined else None))
    export("pyfmu_py_exit_initialization_mode", "fmi3ExitInitializationMode",
           lambda i: i.slave.exit_initialization_mode())
    export("pyfmu_py_enter_event_mode", "fmi3EnterEventMode", lambda i: i.slave.enter_event_mode())
    export("pyfmu_py_enter_step_mode", "fmi3EnterStepMode", lambda i: i.slave.enter_step_mode())
    export("pyfmu_py_terminate", "fmi3Terminate", lambda i: i.slave.terminate())
    export("pyfmu_py_reset", "fmi3Reset", lambda i: i.slave.reset())

    # -- values -------------------------------------------------------------------------------

    def check_counts(inst, function: str, nvr: int, nvalues: int) -> None:
        if nvalues != nvr:
            raise inst.usage_error(f"{function}: nValues ({nvalues}) must equal nValueReferences ({nvr}): "
                                   "the FMU has no arrays")

    def getter(function: str, type_name: str):
        def get(inst, vr, nvr, values, nvalues):
            check_counts(inst, function, nvr, nvalues)
            for k, value in enumerate(inst.slave.get(function, type_name, ffi.unpack(vr, nvr))):
                values[k] = value
        return get

    def setter(function: str, type_name: str):
        def set_(inst, vr, nvr, values, nvalues):
            check_counts(inst, function, nvr, nvalues)
            inst.slave.set(function, type_name, ffi.unpack(vr, nvr), ffi.unpack(values, nvalues))
        return set_

    def get_strings(inst, vr, nvr, values, nvalues):
        check_counts(inst, "fmi3GetString", nvr, nvalues)
        result = inst.slave.get("fmi3GetString", "String", ffi.unpack(vr, nvr))
        inst.strings = [ffi.new("char[]", s.encode("utf-8")) for s in result]  # valid until the next call
        for k, buffer in enumerate(inst.strings):
            values[k] = buffer

    def set_strings(inst, vr, nvr, values, nvalues):
        check_counts(inst, "fmi3SetString", nvr, nvalues)
        inst.slave.set("fmi3SetString", "String", ffi.unpack(vr, nvr), [text(values[k]) for k in range(nvalues)])

    for type_name in ("Float64", "Int32", "Int64", "Boolean"):
        export(f"pyfmu_py_get_{type_name.lower()}", f"fmi3Get{type_name}", getter(f"fmi3Get{type_name}", type_name))
        export(f"pyfmu_py_set_{type_name.lower()}", f"fmi3Set{type_name}", setter(f"fmi3Set{type_name}", type_name))
    export("pyfmu_py_get_string", "fmi3GetString", get_strings)
    export("pyfmu_py_set_string", "fmi3SetString", set_strings)

    # -- clocks -------------------------------------------------------------------------------

    def get_clock(inst, vr, nvr, values):
        for k, active in enumerate(inst.slave.get_clock(ffi.unpack(vr, nvr))):
            values[k] = active

    def get_intervals(inst, vr, nvr, intervals, qualifiers):
        values, kinds = inst.slave.get_interval_decimal(ffi.unpack(vr, nvr))
        for k in range(nvr):
            intervals[k], qualifiers[k] = values[k], kinds[k]

    def get_shifts(inst, vr, nvr, shifts):
        for k, value in enumerate(inst.slave.get_shift_decimal(ffi.unpack(vr, nvr))):
            shifts[k] = value

    export("pyfmu_py_get_clock", "fmi3GetClock", get_clock)
    export("pyfmu_py_set_clock", "fmi3SetClock",
           lambda i, vr, nvr, values: i.slave.set_clock(ffi.unpack(vr, nvr), ffi.unpack(values, nvr)))
    export("pyfmu_py_get_interval_decimal", "fmi3GetIntervalDecimal", get_intervals)
    export("pyfmu_py_get_shift_decimal", "fmi3GetShiftDecimal", get_shifts)

    # -- event instants and steps -------------------------------------------------------------

    def update(inst, flags, next_event_time):
        result = inst.slave.update_discrete_states()
        flags[0] = result.discrete_states_need_update
        flags[1] = result.terminate
        flags[2] = result.next_event_time_defined
        next_event_time[0] = result.next_event_time

    def step(inst, t, h, flags, last_successful_time):
        result = inst.slave.do_step(t, h)
        flags[0] = result.event_handling_needed
        flags[1] = result.terminate
        flags[2] = result.early_return
        last_successful_time[0] = result.last_successful_time

    export("pyfmu_py_update_discrete_states", "fmi3UpdateDiscreteStates", update)
    export("pyfmu_py_do_step", "fmi3DoStep", step)
