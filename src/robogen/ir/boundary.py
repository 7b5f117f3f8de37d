"""The boundary of an FMU: the module, or the one state machine, that one FMU holds."""

from __future__ import annotations

import re
from dataclasses import dataclass

from robogen.diagnostics import Note, RobogenError, did_you_mean
from robogen.semantics.model import Controller, MachineScope, Module, SemanticModel
from robogen.syntax import ast


@dataclass(frozen=True)
class Boundary:
    """What one FMU holds: a module (its controllers' machines) or one state machine."""

    kind: str  # module | machine
    name: str
    qname: str
    module: Module | None = None
    machine: MachineScope | None = None

    @property
    def node(self) -> ast.Node:
        return self.module.node if self.module is not None else self.machine.node  # type: ignore[union-attr]

    @property
    def file(self) -> ast.File:
        return self.module.file if self.module is not None else self.machine.file  # type: ignore[union-attr]

    @property
    def machines(self) -> list[tuple[str, MachineScope, Controller | None]]:
        """The state machines inside, in FMU order: (name used, scope, controller or None)."""
        if self.machine is not None:
            return [(self.name, self.machine, None)]
        assert self.module is not None
        return [(used, m, c) for _, c in self.module.controllers for used, m in c.machines]


def select_boundary(model: SemanticModel, module: str | None = None, machine: str | None = None) -> Boundary:
    """The module or machine to compile: named, or the only one in the model."""
    modules = [Boundary("module", m.name, m.qname, module=m) for m in model.modules]
    machines = [Boundary("machine", s.name, s.qname, machine=s) for s in model.machines]
    if module is not None:
        return _named(modules, module, "module")
    if machine is not None:
        return _named(machines, machine, "state machine")
    if len(modules) == 1:
        return modules[0]
    if not modules and len(machines) == 1:
        return machines[0]
    if modules:
        raise RobogenError.at("the model has several modules; choose one with --module: " + ", ".join(sorted(m.qname for m in modules)), None)
    if not machines:
        raise RobogenError.at("the model has no module and no state machine to compile", None)
    raise RobogenError.at("the model has several state machines and no module; choose one with --machine: " + ", ".join(sorted(m.qname for m in machines)), None)


def _named(candidates: list[Boundary], name: str, what: str) -> Boundary:
    found = [c for c in candidates if c.name == name or c.qname == name]
    if not found:
        raise RobogenError.at(
            f"no {what} '{name}' in the model" + did_you_mean(name, [c.name for c in candidates]),
            None,
            *(Note(f"{what}s: " + ", ".join(sorted(c.qname for c in candidates))),) if candidates else (),
        )
    if len(found) > 1:
        raise RobogenError.at(f"several {what}s are named '{name}': " + ", ".join(c.qname for c in found) + "; give the qualified name", None)
    return found[0]


def model_identifier(name: str) -> str:
    """The FMI modelIdentifier of a boundary named ``name``: FMI requires a name usable as a file
    name and as the prefix of the binary's functions."""
    ident = re.sub(r"[^A-Za-z0-9_]", "_", name)
    if not ident or ident[0].isdigit():
        ident = "m_" + ident
    return ident


__all__ = ["Boundary", "select_boundary", "model_identifier"]
