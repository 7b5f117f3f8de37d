"""Lowering: a checked model and a boundary (a module or one state machine) become one
:class:`~robogen.ir.model.Fmu`.

The steps, in order: the FMU's header (name, period, options); one machine lowering per state
machine inside the boundary, which declares the machine's storage and input events; the ports
(which need every machine's events, :mod:`robogen.ir.ports`); then each machine's blocks (which
need the ports, to route what the machine sends; :mod:`robogen.ir.machines`).

Lowering reads only the resolved model (:mod:`robogen.semantics.model`) and keeps model names:
C identifiers and prototypes are the code generator's business. Constructs that have no
code-generation meaning yet (sets, sequences, quantifiers, strings, probabilistic junctions) are
reported as located errors, never silently dropped.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction

from robogen.diagnostics import Note, RobogenError, working_on
from robogen.ir import model as ir
from robogen.ir.boundary import Boundary, model_identifier
from robogen.ir.machines import FmuContext, MachineLowering
from robogen.ir.ports import Ports
from robogen.ir.supported import ENUM_DEPTH, Shapes, normalise
from robogen.semantics.model import SemanticModel


@dataclass
class LoweringOptions:
    semantics: str = "exhaustive"  # exhaustive | stepwise
    trigger: str = "cycle"  # cycle | on-input (RoboSim)
    time_unit: Fraction = Fraction(1)  # seconds per model time unit
    settings: dict[str, str] = field(default_factory=dict)  # constant name -> value text (--set)
    given: str = "int"  # the scalar type of given types
    max_steps: int = 1000
    capacity: int = 32  # the most elements a set or sequence holds
    capacities: tuple[int, ...] = ()  # per nesting level, outermost first (--capacity 32,8); empty: capacity at every level
    enum_depth: int = ENUM_DEPTH  # the levels of a recursive enumeration's values (robogen.ir.supported.Shapes)
    time: str = "skip"  # RoboChart: skip (the FMU announces its next event time) | tick (the tock clock)


def lower(model: SemanticModel, boundary: Boundary, options: LoweringOptions | None = None) -> ir.Fmu:
    """The IR of the FMU that holds ``boundary`` (raises RobogenError on any problem)."""
    if model.errors:
        raise RobogenError(model.errors)
    options = options or LoweringOptions()
    fmu = _header(model, boundary, options)
    lowerings: list[MachineLowering] = []
    shapes = Shapes(model.tables.declared, options.enum_depth, fmu.levels)
    ports = Ports(fmu, boundary, lowerings, lambda t: normalise(t, options.given, shapes))  # type: ignore[arg-type]
    ctx = FmuContext(model, boundary, fmu, options.given, options.settings, ports, shapes)
    for i, ((used_name, scope, ctrl), name) in enumerate(zip(boundary.machines, boundary.machine_names)):
        with working_on(scope.node.span):
            ml = MachineLowering(ctx, scope, ctrl, i, used_name, name)
            fmu.machines.append(ml.machine)
            lowerings.append(ml)
    ports.create()
    for ml in lowerings:
        with working_on(ml.scope.node.span):
            ml.build()
    ctx.check_settings()
    ctx.sink.raise_if_errors()
    fmu.warnings += ctx.sink.warnings
    return fmu


def _header(model: SemanticModel, b: Boundary, options: LoweringOptions) -> ir.Fmu:
    language = b.file.language
    return ir.Fmu(
        name=b.name,
        model_identifier=model_identifier(b.name),
        language=language,
        semantics=options.semantics,
        trigger=options.trigger,
        period=_period(b) if language == "robosim" else Fraction(1),
        time_unit=options.time_unit,
        sources=tuple(sorted({f.path for f in model.files})),
        span=getattr(b.node, "name_span", None),
        max_steps=options.max_steps,
        capacity=options.capacities[0] if options.capacities else options.capacity,
        capacities=options.capacities if len(set(options.capacities)) > 1 else (),
        root=model.root,
        time=options.time if language == "robochart" else "tick",
    )


def _period(b: Boundary) -> Fraction:
    """The cycle period of a RoboSim boundary (the module's one period, or the machine's)."""
    period = b.module.period if b.module is not None else b.machine.period  # type: ignore[union-attr]
    if period is None:
        raise RobogenError.at(
            f"RoboSim {b.kind} '{b.name}' has no cycle period",
            getattr(b.node, "name_span", None),
            Note("declare it with 'cycleDef cycle == p'"),
        )
    return period


__all__ = ["LoweringOptions", "lower"]
