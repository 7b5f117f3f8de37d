"""The model description of a Python-implemented FMU, built from the class's declarations.

Rules followed (FMI 3.0, the modelDescription schema and its clock rules): Co-Simulation only, ``hasEventMode`` whenever the
model has clocks, one independent ``time``, constant clocks with ``intervalDecimal`` and an
explicit ``shiftDecimal``, one clock per clocked variable, every output (output clocks
included) under ``<Output>``, unclocked output clocks and calculated outputs as
``<InitialUnknown>``, clocked variables never. The instantiation token hashes the rest of the
description, so identical declarations give a byte-identical file.
"""

from __future__ import annotations

from typing import Any

from robogen import __version__
from robogen.fmu.fmi import PYTHON_FMU_LOG_CATEGORIES
from robogen.fmu.modeldesc import (
    CoSimulation, DefaultExperiment, LogCategory, ModelDescription, Unit, Unknown, Variable,
)
from robogen.fmu.modeldesc_writer import with_content_token
from robogen.pyfmu.model import Clock, Model, Var

# SI base-unit exponents of the units models commonly declare; others are listed without.
_BASE_UNITS = {
    "s": (("s", 1),),
    "m": (("m", 1),),
    "kg": (("kg", 1),),
    "rad": (("rad", 1),),
    "rad/s": (("s", -1), ("rad", 1)),
    "rad/s2": (("s", -2), ("rad", 1)),
    "m/s": (("m", 1), ("s", -1)),
    "N.m": (("kg", 1), ("m", 2), ("s", -2)),
}

TIME = Variable("time", 0, "Float64", "independent", "continuous", description="simulation time")


def _text(value: Any) -> str:
    """A start value or a time as FMI writes it: true/false, the shortest exact decimal."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    return str(value)


def model_description(model: type[Model], model_identifier: str) -> ModelDescription:
    """The model description of ``model`` (a configured Model subclass), its token included."""
    variables = model.variables()
    return with_content_token(ModelDescription(
        model_name=model.model_name or model.__name__,
        instantiation_token="",
        description=model.description,
        generation_tool=f"robogen {__version__} package-py",
        variable_naming_convention="structured",
        co_simulation=CoSimulation(
            model_identifier, can_handle_variable_step=True, has_event_mode=any(isinstance(v, Clock) for v in variables),
            might_return_early=model.might_return_early),
        unit_definitions=tuple(Unit(u, _BASE_UNITS.get(u)) for u in sorted(
            {v.unit for v in variables if v.unit is not None and v.type_name == "Float64"})),
        log_categories=tuple(LogCategory(name) for name in PYTHON_FMU_LOG_CATEGORIES),
        default_experiment=_default_experiment(model),
        variables=(TIME, *(_variable(model, var) for var in variables)),
        unknowns=_model_structure(model),
    ))


def _default_experiment(model: type[Model]) -> DefaultExperiment | None:
    if not model.default_experiment:
        return None
    texts = {key: _text(float(value)) for key, value in model.default_experiment.items()}
    return DefaultExperiment(texts.get("startTime"), texts.get("stopTime"), texts.get("tolerance"),
                             texts.get("stepSize"))


def _variable(model: type[Model], var: Var) -> Variable:
    common = dict(name=var.name, value_reference=var.vr, type=var.type_name, causality=var.causality,
                  description=var.description)
    if isinstance(var, Clock):
        periodic = dict(interval_decimal=_text(model.clock_seconds(var.interval)),  # type: ignore[arg-type]
                        shift_decimal=_text(model.clock_seconds(var.shift))) if var.periodic else {}
        return Variable(**common, variability="discrete", interval_variability=var.kind, **periodic)
    return Variable(
        **common,
        variability=var.variability or "",
        initial=var.initial if var.causality != "input" else None,
        clocks=(model.variable(var.clock).vr,) if var.clock is not None else (),
        start=(_text(var.start),) if var.start is not None and var.needs_start else (),
        unit=var.unit if var.type_name == "Float64" else None,
    )


def _model_structure(model: type[Model]) -> tuple[Unknown, ...]:
    """Every output under <Output> with its dependencies, then the initial unknowns."""
    variables = model.variables()
    outputs = tuple(Unknown("Output", var.vr, _dependencies(model, var)) for var in variables
                    if var.causality == "output")
    initial = tuple(Unknown("InitialUnknown", var.vr) for var in variables if var.clock is None and (
        (var.causality == "output" and (isinstance(var, Clock) or var.initial in ("approx", "calculated")))
        or var.causality == "calculatedParameter"))
    return outputs + initial


def _dependencies(model: type[Model], var: Var) -> tuple[int, ...] | None:
    """The declared dependencies; a clocked output depends on its clock; otherwise on everything."""
    if var.depends_on is not None:
        return tuple(model.variable(name).vr for name in var.depends_on)
    if var.clock is not None:
        return (model.variable(var.clock).vr,)
    return None
