"""The boundary of an FMU: the module, or the one state machine, that one FMU holds."""

from __future__ import annotations

import re
from collections import Counter
from dataclasses import dataclass, replace

from robogen.diagnostics import Note, RobogenError, Span, did_you_mean
from robogen.semantics.model import Controller, MachineScope, Module, SemanticModel
from robogen.syntax import ast


@dataclass(frozen=True)
class Boundary:
    """What one FMU holds: a module (its controllers' machines) or one state machine.

    ``label`` is the name that selects it unambiguously (``--module``/``--machine``), ``names``
    every spelling that selects it: its name, its qualified name, and for a machine the
    controller-qualified names and instance paths of the controllers that hold it."""

    kind: str  # module | machine
    name: str
    qname: str
    module: Module | None = None
    machine: MachineScope | None = None
    names: tuple[str, ...] = ()
    label: str = ""

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

    @property
    def machine_names(self) -> list[str]:
        """The name of each machine inside (in FMU order) in the FMU's variables: the machine's
        own name, or, where two machines inside have one name (two instances of one definition,
        or two definitions of one name in different controllers), its instance path
        ``controller.machine`` (the names the module and the controller use)."""
        if self.machine is not None:
            return [self.machine.name]
        assert self.module is not None
        own = [(m.name, f"{cu}.{used}") for cu, c in self.module.controllers for used, m in c.machines]
        count = Counter(name for name, _ in own)
        return [name if count[name] == 1 else path for name, path in own]


def boundaries(model: SemanticModel) -> tuple[list[Boundary], list[Boundary]]:
    """Every module and every state machine of the model that an FMU can hold, each with the
    names that select it and a label unique among its kind."""
    modules = [Boundary("module", m.name, m.qname, module=m, names=(m.name, m.qname)) for m in model.modules]
    spellings: dict[int, list[str]] = {id(s.node): [s.name, s.qname] for s in model.machines}
    for c in model.controllers:
        for used, s in c.machines:
            names = spellings.get(id(s.node))
            if names is None:
                continue
            names += [f"{c.name}::{used}", f"{c.qname}::{used}", f"{c.name}.{used}"]
            if any(member is s.node for member in c.node.members):  # defined inside the controller
                names += [f"{c.name}::{s.name}", f"{c.qname}::{s.name}"]
    for m in model.modules:
        for cu, c in m.controllers:
            for used, s in c.machines:
                if id(s.node) in spellings:
                    spellings[id(s.node)] += [f"{cu}.{used}", f"{m.name}.{cu}.{used}", f"{m.qname}.{cu}.{used}"]
    machines = [Boundary("machine", s.name, s.qname, machine=s, names=tuple(dict.fromkeys(spellings[id(s.node)])))
                for s in model.machines]
    return _labelled(modules), _labelled(machines)


def _labelled(candidates: list[Boundary]) -> list[Boundary]:
    """Each candidate with its label: the first of its names that selects it alone."""
    out = []
    for b in candidates:
        unique = [n for n in b.names if _matching(candidates, n) == [b]]
        out.append(replace(b, label=unique[0] if unique else b.qname))
    return out


def _matching(candidates: list[Boundary], name: str) -> list[Boundary]:
    """The candidates ``name`` selects: those whose qualified name it is, if any, else every one
    it is a name of."""
    exact = [b for b in candidates if b.qname == name]
    return exact if len(exact) == 1 else [b for b in candidates if name in b.names]


def select_boundary(model: SemanticModel, module: str | None = None, machine: str | None = None) -> Boundary:
    """The module or machine to compile: named, or the only one in the model."""
    modules, machines = boundaries(model)
    if module is not None:
        return _named(modules, module, "module")
    if machine is not None:
        return _named(machines, machine, "state machine")
    if len(modules) == 1:
        return modules[0]
    if not modules and len(machines) == 1:
        return machines[0]
    if modules:
        raise RobogenError.at("the model has several modules; choose one with --module: " + _listed(modules), None)
    if not machines:
        raise RobogenError.at(_nothing_to_compile(model), _first_place(model))
    raise RobogenError.at("the model has several state machines and no module; choose one with --machine: " + _listed(machines), None)


def _listed(candidates: list[Boundary]) -> str:
    return ", ".join(sorted(c.label for c in candidates))


def _nothing_to_compile(model: SemanticModel) -> str:
    """Why a model without a module and without a state machine gives no FMU: what it holds."""
    operations = [s for s in model.scopes if s.is_operation]
    held = [f"{len(operations)} operation definition{'s' if len(operations) != 1 else ''}"] if operations else []
    return ("the model has no module and no state machine, so there is nothing to compile into an FMU"
            + (f" (it holds {', '.join(held)}; an FMU holds a module or a state machine that uses them)" if held else
               " (it declares only types, interfaces or functions)"))


def _first_place(model: SemanticModel) -> Span | None:
    """Where a message about the whole model points: its first operation definition, else its first file."""
    operations = [s for s in model.scopes if s.is_operation]
    if operations:
        return getattr(operations[0].node, "name_span", None)
    return Span.whole_file(model.files[0].path) if model.files else None


def _named(candidates: list[Boundary], name: str, what: str) -> Boundary:
    found = _matching(candidates, name)
    if not found:
        raise RobogenError.at(
            f"no {what} '{name}' in the model" + did_you_mean(name, [n for c in candidates for n in c.names]),
            None,
            *(Note(f"{what}s: " + _listed(candidates)),) if candidates else (),
        )
    if len(found) > 1:
        raise RobogenError.at(f"several {what}s are named '{name}'; choose one of: " + _listed(found), None,
                              *(Note(f"'{c.label}' is declared here", getattr(c.node, "name_span", None)) for c in found))
    return found[0]


def model_identifier(name: str) -> str:
    """The FMI modelIdentifier of a boundary named ``name``: FMI requires a name usable as a file
    name and as the prefix of the binary's functions."""
    ident = re.sub(r"[^A-Za-z0-9_]", "_", name)
    if not ident or ident[0].isdigit():
        ident = "m_" + ident
    return ident


__all__ = ["Boundary", "boundaries", "select_boundary", "model_identifier"]
