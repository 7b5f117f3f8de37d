"""An SSP component checked against its FMU, and the instance it becomes.

A component's connectors must be variables of its FMU (by name), of the kind of their causality,
of their type (SSP 1.0's generic ``Real``, ``Integer`` and ``Enumeration`` stand for any real,
integer or enumeration type), in their unit where both give one; a Clock connector must be a
clock of the FMU, of its interval variability, and a connector's ``<ssd:Clock>`` associations
must be the clocks that clock it. A fixed or tunable input clock's ``intervalDecimal`` and
``shiftDecimal`` set its timing, as ``[instances.X] clocks`` does in a system file; robogen's own
instance settings (``isolate``, a Model Exchange FMU's ``solver`` and ``solverStep``) come from a
robogen annotation of the component. Its ``implementation`` chooses the interface the FMU is used
through, as ``[instances.X] interface`` does (``any``: co-simulation where the FMU offers it).
"""

from __future__ import annotations

import math
from pathlib import Path

from robogen.cosim.ssp_flatten import Leaf
from robogen.cosim.ssp_model import ROBOGEN_NS, Connector
from robogen.cosim.system import SOLVERS, InstanceSpec
from robogen.cosim.units import UnitDef
from robogen.diagnostics import DiagnosticSink, Note, did_you_mean
from robogen.fmu.modeldesc import ModelDescription, Variable

REALS = ("Float32", "Float64")
INTEGERS = ("Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32", "Int64", "UInt64")
#: SSP 1.0's generic types: the FMI types each stands for
GENERIC = {"Real": REALS, "Integer": INTEGERS, "Enumeration": ("Enumeration",)}
#: a component's implementation: the interface its instance uses ([instances.X] interface; None: the default)
IMPLEMENTATIONS = {"any": None, "CoSimulation": "co-simulation", "ModelExchange": "model-exchange",
                   "ScheduledExecution": "scheduled-execution"}
INSTANCE_ATTRS = ("isolate", "solver", "solverStep")


def type_fits(ssp_type: str, fmi_type: str) -> bool:
    return fmi_type in GENERIC.get(ssp_type, (ssp_type,))


def instance_spec(leaf: Leaf, fmu: Path, units: dict[str, UnitDef], sink: DiagnosticSink) -> InstanceSpec:
    """The instance of ``leaf`` (its FMU loaded in ``leaf.md``), without start values; every
    problem of its connectors and settings into ``sink``."""
    c = leaf.component
    spec = InstanceSpec(leaf.instance, fmu, c.el.span, c.el.at("source"))
    spec.interface = IMPLEMENTATIONS.get(c.implementation)  # the schema's rules hold it to these
    md = leaf.md
    names = md.by_name()
    for connector in c.connectors.values():
        var = names.get(connector.name)
        if var is None:
            sink.error(f"the FMU of component '{c.name}' has no variable '{connector.name}'{did_you_mean(connector.name, names)}",
                       connector.el.at("name"), Note(f"variables are declared in {md.path}"))
            continue
        _check(connector, var, md, c.name, units, sink)
        _clock_timing(connector, var, spec, sink)
    _settings(leaf, spec, sink)
    return spec


def _check(connector: Connector, var: Variable, md: ModelDescription, component: str, units: dict[str, UnitDef],
           sink: DiagnosticSink) -> None:
    el = connector.el
    kind = connector.kind
    if not (kind in (var.causality, "unspecified") or (kind == "constant" and var.variability == "constant")):
        sink.error(f"connector '{connector.name}' of component '{component}' is of kind {kind}, but the FMU's variable "
                   f"is {var.causality}", el.at("kind"))
    if connector.type is not None and not type_fits(connector.type, var.type):
        sink.error(f"connector '{connector.name}' of component '{component}' is typed {connector.type}, but the FMU's "
                   f"variable is {var.type}", el.span)
    if connector.unit is not None and var.unit is not None and connector.unit != var.unit:
        sink.error(f"connector '{connector.name}' of component '{component}' is in unit '{connector.unit}', but the FMU's "
                   f"variable is in '{var.unit}'", el.span)
    if connector.clock is not None and var.is_clock:
        variability = connector.clock.get("intervalVariability")
        if variability is not None and variability != var.interval_variability:
            sink.error(f"clock connector '{connector.name}' of component '{component}' says intervalVariability "
                       f"\"{variability}\", but the FMU's clock is {var.interval_variability}", connector.clock.at("intervalVariability"))
    by_vr = md.by_vr()
    for name, k in connector.clocks:
        clock = md.by_name().get(name)
        if clock is None or not clock.is_clock:
            sink.error(f"connector '{connector.name}' is associated to the clock '{name}', which the FMU of component "
                       f"'{component}' does not have", k.at("name"))
        elif clock.value_reference not in var.clocks:
            mine = ", ".join(by_vr[v].name for v in var.clocks if v in by_vr) or "none"
            sink.error(f"connector '{connector.name}' is associated to the clock '{name}', but the FMU's variable is "
                       f"clocked by: {mine}", k.at("name"))


def _clock_timing(connector: Connector, var: Variable, spec: InstanceSpec, sink: DiagnosticSink) -> None:
    """A clock connector's interval and shift: the timing of a fixed or tunable input clock."""
    clock = connector.clock
    if clock is None or not var.is_clock or ("intervalDecimal" not in clock.attrib and "shiftDecimal" not in clock.attrib):
        return
    timing = {key: float(clock.get(attr)) for key, attr in (("interval", "intervalDecimal"), ("shift", "shiftDecimal"))
              if clock.get(attr) is not None}
    if var.interval_variability == "constant" and var.causality == "input":
        declared = {"interval": var.interval_decimal, "shift": var.shift_decimal or "0"}
        for key, value in timing.items():
            if declared[key] is None or not math.isclose(float(declared[key]), value, rel_tol=1e-12):
                attr = "intervalDecimal" if key == "interval" else "shiftDecimal"
                sink.error(f"clock '{connector.name}' is constant: its {key} is its FMU's ({declared[key]}), not {value!r}",
                           clock.at(attr))
        return
    if var.interval_variability not in ("fixed", "tunable") or var.causality != "input":
        sink.error(f"clock '{connector.name}' is an {var.causality} clock of "
                   f"interval variability {var.interval_variability}: only fixed and tunable input clocks take an "
                   "intervalDecimal or shiftDecimal", clock.span)
        return
    for key, value in timing.items():
        if (key == "interval" and not value > 0) or (key == "shift" and value < 0) or not math.isfinite(value):
            sink.error(f"clock '{connector.name}': the {key} must be {'positive' if key == 'interval' else 'at least 0'}",
                       clock.span)
            return
    spec.clocks[connector.name] = (timing, clock.span)


def _settings(leaf: Leaf, spec: InstanceSpec, sink: DiagnosticSink) -> None:
    """robogen's settings of an instance, in a robogen annotation: <rg:Instance isolate="true"
    solver="euler" solverStep="0.001"/> ([instances.X] isolate, solver, solver_step)."""
    for el in leaf.component.annotations:
        if el.ns != ROBOGEN_NS or el.tag != "Instance":
            sink.error(f"a robogen annotation of a component holds <rg:Instance> (namespace {ROBOGEN_NS}), not <{el.tag}>", el.span)
            continue
        for name, value in el.attrib.items():
            if name not in INSTANCE_ATTRS:
                sink.error(f"<rg:Instance> has no attribute '{name}'{did_you_mean(name, INSTANCE_ATTRS)}", el.at(name))
            elif name == "isolate" and value not in ("true", "false"):
                sink.error("'isolate' must be true or false", el.at(name))
            elif name == "isolate":
                spec.isolate = value == "true"
            elif name == "solver" and value not in SOLVERS:
                sink.error(f"'solver' must be one of {', '.join(SOLVERS)}, not '{value}'{did_you_mean(value, SOLVERS)}",
                           el.at(name))
            elif name == "solver":
                spec.solver = value
            elif (step := _positive(value)) is None:
                sink.error(f"'solverStep' must be a positive number, not '{value}'", el.at(name))
            else:
                spec.solver_step = step


def _positive(text: str) -> float | None:
    try:
        value = float(text)
    except ValueError:
        return None
    return value if math.isfinite(value) and value > 0 else None
