"""The interfaces an FMU offers, and the adapters that put each behind the one instance interface.

The master's loops know one kind of instance: FMI 3.0 Co-Simulation (:mod:`robogen.cosim.fmi3`).
Every other kind of FMU is put behind it by an adapter (``adapt.h``, ``adapt*.c``): a C library
that exports the FMI 3.0 Co-Simulation functions and makes each call of the adapted FMU's own
interface:

====================  =====================================================================
FMI 2.0 CS            the fmi2 calls; Real, Integer, Boolean, String, Enumeration as Float64,
                      Int32, Boolean, String, Int64; no Event Mode, no early return
Model Exchange        integrated by CVode (SUNDIALS, as fmpy ships it) or explicit Euler; an
(FMI 2.0 and 3.0)     event (state, step) returns early from fmi3DoStep with eventHandlingNeeded,
                      and the FMU's event iteration is the master's
FMI 3.0 SE            input clocks' ticks activate their model partitions, in priority order
====================  =====================================================================

:func:`view` gives the description the master works with (the chosen interface's flags as
``<CoSimulation>``: what the adapter offers), :func:`bind` the binding of an adapted instance: a
:class:`~robogen.cosim.fmi3.Binding` on the adapter library, whose C functions the engine calls
as it calls any FMU's. The Python reference loop calls the same C functions, so both loops see the
same integrator.

The library is compiled once (the FMI 2.0 and 3.0 headers of the installed fmpy) and cached like
the engine, named by the hash of its source.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, replace
from pathlib import Path

import cffi

from robogen.cosim.cbuild import cached_library, package_source
from robogen.cosim.fmi3 import REQUIRED, Binding, Library, LoadError, log_message_callback
from robogen.cosim.fmi3 import ffi as fmi_ffi
from robogen.cosim.schema import package_file
from robogen.cosim.system import INTERFACES, SOLVERS
from robogen.diagnostics import Note, RobogenError, Span
from robogen.fmu.fmi import ERROR
from robogen.fmu.modeldesc import CoSimulation, ModelDescription

CO_SIMULATION, MODEL_EXCHANGE, SCHEDULED_EXECUTION = INTERFACES
#: CVode's relative tolerance where neither the system file nor the FMU's default experiment gives one (fmpy's).
DEFAULT_TOLERANCE = 1e-5

HEADER = "adapt.h"
SOURCES = ("adapt.c", "adapt_values.c", "adapt_me.c")

ffi = cffi.FFI()
ffi.cdef(package_file(HEADER))
_KIND = {k.removeprefix("RGA_"): v for k, v in ffi.typeof("enum rga_kind").relements.items()}
_SOLVER = {"cvode": ffi.typeof("enum rga_solver").relements["RGA_CVODE"],
           "euler": ffi.typeof("enum rga_solver").relements["RGA_EULER"]}


@dataclass(frozen=True)
class Choice:
    """How one instance uses its FMU: the interface, and for Model Exchange the integrator."""

    interface: str = CO_SIMULATION
    solver: str = "cvode"
    tolerance: float = DEFAULT_TOLERANCE
    solver_step: float | None = None  # Euler's step (None: the communication step)


def default_interface(md: ModelDescription) -> str | None:
    """Co-simulation where offered, else the first interface the FMU offers."""
    offered = md.interfaces()
    return offered[0] if offered else None


def adapted(md: ModelDescription, interface: str) -> bool:
    """Whether an instance of this FMU through this interface needs an adapter."""
    return md.is_fmi2 or interface != CO_SIMULATION


def view(md: ModelDescription, interface: str, span: Span | None) -> ModelDescription:
    """The description the master works with: ``md`` with the chosen interface as the
    ``<CoSimulation>`` the adapter offers. A located error where the FMU does not offer it."""
    offered = md.interfaces()
    if interface not in offered:
        version = "FMI 2.0" if md.is_fmi2 else "FMI 3.0"
        raise RobogenError.at(f"the FMU does not offer {version} {interface.replace('-', ' ')}", span,
                              Note(f"it offers: {', '.join(offered) or 'no interface'}"))
    if not adapted(md, interface):
        return md
    if interface == CO_SIMULATION:
        cs = md.co_simulation
        return replace(md, co_simulation=CoSimulation(cs.model_identifier, can_handle_variable_step=cs.can_handle_variable_step,
                                                      can_get_and_set_state=cs.can_get_and_set_state, line=cs.line))
    if interface == MODEL_EXCHANGE:
        me = md.model_exchange
        return replace(md, co_simulation=CoSimulation(me.model_identifier, can_handle_variable_step=True,
                                                      can_get_and_set_state=me.can_get_and_set_state, has_event_mode=True,
                                                      might_return_early=True, line=me.line))
    se = md.scheduled_execution
    return replace(md, co_simulation=CoSimulation(se.model_identifier, can_handle_variable_step=True,
                                                  can_get_and_set_state=se.can_get_and_set_state, has_event_mode=True,
                                                  line=se.line))


def _kind(md: ModelDescription, interface: str) -> int:
    if md.is_fmi2:
        return _KIND["FMI2_CS" if interface == CO_SIMULATION else "FMI2_ME"]
    return _KIND["FMI3_ME" if interface == MODEL_EXCHANGE else "FMI3_SE"]


# ------------------------------------------------------------------------------------------------
# The adapter library

def source() -> bytes:
    """The adapters' C source: its files in order, the schema in place of its #include line."""
    return package_source(SOURCES, package_file)


@functools.cache
def library_path() -> Path:
    """The compiled adapter library (built at first use, kept by the hash of its source)."""
    def compile_to(c_file: Path, so: Path) -> None:
        from robogen import toolchain
        from robogen.fmu.headers import include_dir

        toolchain.compile_shared([c_file], so, includes=[include_dir(fmi2=True)], libs=("-lm", "-ldl"),
                                 what="the master's interface adapters")

    try:
        return cached_library("adapt", source(), compile_to)
    except RobogenError:
        raise
    except Exception as exc:
        raise RobogenError.at(f"cannot build the master's interface adapters: {exc}", None) from None


class AdapterLibrary(Library):
    """The adapter library as an FMU's shared object: the FMI 3.0 Co-Simulation functions (an
    adapter is made by rga_instantiate, not fmi3InstantiateCoSimulation)."""

    required = [name for name in REQUIRED if name != "fmi3InstantiateCoSimulation"]

    def __init__(self, path: str):
        super().__init__(path)
        self.adapter = ffi.dlopen(path)


@functools.cache
def _adapter_library() -> AdapterLibrary:
    return AdapterLibrary(str(library_path()))


def _address(cdata, from_ffi, to_ffi, ctype: str = "void *"):
    """A pointer of one FFI as a pointer of another."""
    return to_ffi.cast(ctype, int(from_ffi.cast("uintptr_t", cdata)))


class AdaptedBinding(Binding):
    """The binding of an instance behind an adapter (its FMU's binary and configuration)."""

    def __init__(self, config: dict, name: str, trace=None, log=None, notes=None):
        super().__init__(_adapter_library(), name, trace=trace, log=log, notes=notes)
        self._keep = [ffi.new("char[]", str(config[k]).encode()) for k in ("binary", "core", "cvode")]
        vrs, priorities = config.get("partitions", ([], []))
        self._keep += [ffi.new("uint32_t[]", vrs or [0]), ffi.new("uint32_t[]", priorities or [0])]
        self.config = ffi.new("rga_config *", {
            "kind": config["kind"], "binary": self._keep[0], "sundials_core": self._keep[1], "sundials_cvode": self._keep[2],
            "solver": _SOLVER[config["solver"]], "tolerance": config["tolerance"], "euler_step": config["euler_step"],
            "n_states": config["states"], "n_indicators": config["indicators"], "completed_step": config["completed"],
            "n_partitions": len(vrs), "partition_vr": self._keep[3], "partition_priority": self._keep[4]})

    def fmi3InstantiateCoSimulation(self, instantiationToken: str, resourcePath: str | None, visible: bool = False,
                                    loggingOn: bool = False, eventModeUsed: bool = False,
                                    earlyReturnAllowed: bool = False) -> None:
        error = ffi.new("char[1024]")
        resources = ffi.new("char[]", resourcePath.encode()) if resourcePath else ffi.NULL
        self._note[0] = self.note_code("fmi3InstantiateCoSimulation")
        handle = self.library.adapter.rga_instantiate(
            self.config, self.name.encode(), instantiationToken.encode(), resources, visible, loggingOn,
            _address(self._env, fmi_ffi, ffi), _address(log_message_callback(), fmi_ffi, ffi), error, len(error))
        if self.trace is not None:
            self.trace(f"fmi3InstantiateCoSimulation({self.name}, eventModeUsed={eventModeUsed}, "
                       f"earlyReturnAllowed={earlyReturnAllowed}) -> {'NULL' if handle == ffi.NULL else 'instance'}")
        if handle == ffi.NULL:
            self.receive_log(ERROR, ffi.string(error).decode("utf-8", "replace"))
            raise self.error("fmi3InstantiateCoSimulation", ERROR)
        self.handle = _address(handle, ffi, fmi_ffi)

    def statistics(self) -> tuple[int, int, int]:
        """The integrator's steps, right-hand sides and root-finding calls (Model Exchange)."""
        out = ffi.new("long[3]")
        self.library.adapter.rga_statistics(_address(self.handle, fmi_ffi, ffi), out, out + 1, out + 2)
        return out[0], out[1], out[2]


def config(md: ModelDescription, choice: Choice, binary: Path, step: float) -> dict:
    """The adapter's configuration for an instance of ``md`` through ``choice``."""
    from robogen.fmu.headers import sundials_libraries

    me = choice.interface == MODEL_EXCHANGE
    core, cvode = sundials_libraries() if me and choice.solver == "cvode" else ("", "")
    clocks = [v for v in md.variables if v.is_clock and v.causality == "input"]
    return {
        "kind": _kind(md, choice.interface), "binary": binary, "core": core, "cvode": cvode,
        "solver": choice.solver, "tolerance": choice.tolerance,
        "euler_step": choice.solver_step if choice.solver_step is not None else step,
        "states": md.number_of_states() if me else 0, "indicators": md.number_of_event_indicators() if me else 0,
        "completed": bool(me and md.model_exchange.needs_completed_integrator_step),
        "partitions": ([c.value_reference for c in clocks], [c.priority or 0 for c in clocks])
        if choice.interface == SCHEDULED_EXECUTION else ([], []),
    }


def bind(md: ModelDescription, choice: Choice, binary: Path, step: float, name: str, span: Span, *, trace=None,
         notes=None) -> AdaptedBinding:
    """The binding of a new adapted instance (see the module's docstring)."""
    try:
        return AdaptedBinding(config(md, choice, binary, step), name, trace=trace, notes=notes)
    except LoadError as exc:
        raise RobogenError.at(str(exc), span) from None


def tolerance(system_tolerance: float | None, md: ModelDescription) -> float:
    """CVode's relative tolerance: the system file's, else the FMU's default experiment's, else fmpy's default."""
    if system_tolerance is not None:
        return system_tolerance
    experiment = md.default_experiment
    if experiment is not None and experiment.tolerance is not None:
        return float(experiment.tolerance)
    return DEFAULT_TOLERANCE


__all__ = ["INTERFACES", "SOLVERS", "Choice", "default_interface", "adapted", "view", "bind", "config", "tolerance",
           "AdaptedBinding", "library_path", "source"]
