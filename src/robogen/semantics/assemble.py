"""Assembling the containers: the checker's records of controllers and modules become the frozen
:class:`~robogen.semantics.model.Controller` and :class:`~robogen.semantics.model.Module`.

This runs after every declaration is checked, because a container refers to machines and
operations declared anywhere in the workspace: their scopes exist only then. Assembling also
resolves what the containers expose (the events of controllers and platforms, the operations a
platform provides) and decides each module's one cycle period.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from types import MappingProxyType

from robogen.diagnostics import Span
from robogen.semantics.model import Controller, MachineScope, Module, Platform
from robogen.semantics.periods import one_period
from robogen.semantics.scope import ScopeBuilder
from robogen.syntax import ast


@dataclass
class ControllerParts:
    """What the checker found in a controller: its references and declarations, by name used."""

    node: ast.Controller
    file: ast.File
    qname: str
    machines: list[tuple[str, ast.StateMachine]] = field(default_factory=list)
    operations: list[tuple[str, ast.OperationDef]] = field(default_factory=list)
    period: Fraction | None = None


@dataclass
class ModuleParts:
    """What the checker found in a module."""

    node: ast.Module
    file: ast.File
    qname: str
    platform: tuple[str, ast.Platform, ast.File] | None = None  # (name used, declaration, its file)
    controllers: list[tuple[str, ast.Controller]] = field(default_factory=list)
    period: Fraction | None = None


def _connections(node: ast.Controller | ast.Module) -> tuple[ast.Connection, ...]:
    return tuple(m for m in node.members if isinstance(m, ast.Connection))


def assemble_controller(parts: ControllerParts, scopes: dict[int, MachineScope], builder: ScopeBuilder) -> Controller:
    return Controller(
        parts.node, parts.file, parts.qname,
        machines=tuple((used, scopes[id(m)]) for used, m in parts.machines if id(m) in scopes),
        operations=tuple((used, scopes[id(o)]) for used, o in parts.operations if id(o) in scopes),
        events=MappingProxyType(builder.container_events(parts.node, parts.file)),
        connections=_connections(parts.node),
        period=parts.period,
    )


def assemble_module(parts: ModuleParts, controllers: dict[int, Controller], builder: ScopeBuilder) -> Module:
    platform = None
    if parts.platform is not None:
        name, node, file = parts.platform
        platform = Platform(name, node, file, MappingProxyType(builder.container_events(node, file)),
                            MappingProxyType(builder.platform_operations(node, file)))
    used = tuple((name, controllers[id(c)]) for name, c in parts.controllers if id(c) in controllers)
    return Module(parts.node, parts.file, parts.qname, platform, used, _connections(parts.node),
                  one_period(_periods(parts, used), builder.sink))


def _periods(parts: ModuleParts, controllers: tuple[tuple[str, Controller], ...]) -> list[tuple[Fraction, str, Span | None]]:
    """The periods the parts of a module declare: the module's, then each controller's followed by
    its machines'."""
    periods: list[tuple[Fraction, str, Span | None]] = []
    if parts.period is not None:
        periods.append((parts.period, f"module '{parts.node.name}'", parts.node.name_span))
    for _, c in controllers:
        if c.period is not None:
            periods.append((c.period, f"controller '{c.name}'", c.node.name_span))
        for _, m in c.machines:
            if m.period is not None:
                periods.append((m.period, f"state machine '{m.name}'", m.node.name_span))  # type: ignore[attr-defined]
    return periods


__all__ = ["ControllerParts", "ModuleParts", "assemble_controller", "assemble_module"]
