"""Symbols and scopes: what a state machine or software operation can name.

A :class:`MachineScope` is built for every ``stm`` and every ``operation`` definition. It holds
the variables, constants, clocks, events and operations visible in its body, each as a symbol
that remembers where it was declared. Later stages (checks, IR lowering) resolve names through
these scopes, so there is one lookup logic.

Visibility (docs/robosim-robochart.md §2.3–§3.2):

- own declarations (``var``/``const`` lists, ``clock``, ``event``; operation parameters);
- members of interfaces the container ``uses``, ``requires`` or ``provides`` (variables,
  constants, clocks, operations, events);
- RoboSim: the events of ``input context`` are inputs, those of ``output context`` outputs;
  operations required by the output context are the platform operations called with ``$op``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Iterator

from robogen.diagnostics import DiagnosticSink, Note, Span
from robogen.semantics.types import UNKNOWN, Type
from robogen.syntax import ast


@dataclass(eq=False)
class VarSym:
    name: str
    type: Type
    kind: str  # var, const, param, binder, let
    decl: ast.Node | None
    origin: str
    init: ast.Expr | None = None
    shared: bool = False  # declared by an interface (provided by a controller or platform)

    @property
    def assignable(self) -> bool:
        return self.kind == "var"

    @property
    def span(self) -> Span | None:
        return getattr(self.decl, "name_span", None)


@dataclass(eq=False)
class ClockSym:
    name: str
    decl: ast.Node
    origin: str

    @property
    def span(self) -> Span | None:
        return getattr(self.decl, "name_span", None)


@dataclass(eq=False)
class EventSym:
    name: str
    type: Type | None
    decl: ast.EventDecl
    origin: str
    input: bool = False  # RoboSim: named by the input context
    output: bool = False  # RoboSim: named by the output context
    broadcast: bool = False

    @property
    def span(self) -> Span | None:
        return self.decl.name_span


@dataclass(eq=False)
class OpSym:
    name: str
    params: tuple[tuple[str, Type], ...]
    decl: ast.Node  # OpSig or OperationDef
    origin: str
    platform: bool = False  # RoboSim: called with $op (an output-context operation)

    @property
    def span(self) -> Span | None:
        return getattr(self.decl, "name_span", None)


@dataclass(eq=False)
class FuncSym:
    name: str
    params: tuple[tuple[str, Type], ...]
    result: Type
    decl: ast.FunctionDef | None
    builtin: object | None = None  # types.Builtin for toolkit functions
    qname: str = ""


@dataclass(eq=False)
class EnumLitSym:
    enum: Type  # EnumT
    literal: str


Symbol = VarSym | ClockSym | EventSym | OpSym | FuncSym | EnumLitSym


@dataclass(eq=False)
class Region:
    """A container of nodes: a machine, an operation, or a composite state."""

    owner: ast.Node  # StateMachine, OperationDef or State
    parent: "Region | None"
    nodes: dict[str, ast.NodeDecl] = field(default_factory=dict)
    transitions: list[ast.Transition] = field(default_factory=list)
    children: dict[str, "Region"] = field(default_factory=dict)  # composite states by name

    @property
    def path(self) -> tuple[str, ...]:
        if self.parent is None:
            return ()
        return self.parent.path + (self.owner.name,)  # type: ignore[attr-defined]

    @property
    def description(self) -> str:
        """How messages name the container: state 'S', operation 'o' or state machine 'M'."""
        owner = self.owner
        if isinstance(owner, ast.State):
            return f"state '{owner.name}'"
        if isinstance(owner, ast.OperationDef):
            return f"operation '{owner.name}'"
        return f"state machine '{owner.name}'"  # type: ignore[attr-defined]

    def initials(self) -> list[ast.Initial]:
        return [n for n in self.nodes.values() if isinstance(n, ast.Initial)]

    def walk(self) -> Iterator["Region"]:
        yield self
        for child in self.children.values():
            yield from child.walk()


@dataclass(eq=False)
class MachineScope:
    node: ast.StateMachine | ast.OperationDef
    file: ast.File
    qname: str
    vars: dict[str, VarSym] = field(default_factory=dict)
    clocks: dict[str, ClockSym] = field(default_factory=dict)
    events: dict[str, EventSym] = field(default_factory=dict)
    ops: dict[str, OpSym] = field(default_factory=dict)
    region: Region | None = None
    cycle_defs: list[ast.CycleDef] = field(default_factory=list)
    interfaces: list[tuple[str, ast.InterfaceRef, ast.Interface | None]] = field(default_factory=list)

    @property
    def name(self) -> str:
        return self.node.name

    @property
    def language(self) -> str:
        return self.file.language

    @property
    def robosim(self) -> bool:
        return self.file.language == "robosim"

    @property
    def is_operation(self) -> bool:
        return isinstance(self.node, ast.OperationDef)

    @property
    def kind(self) -> str:
        return "operation" if self.is_operation else "state machine"

    def all_states(self) -> Iterator[tuple[tuple[str, ...], ast.NodeDecl]]:
        """Every node with its path from the machine: ('Outer', 'Inner')."""
        assert self.region is not None
        for region in self.region.walk():
            for name, node in region.nodes.items():
                yield region.path + (name,), node


class ScopeBuilder:
    """Builds a MachineScope. ``resolve_type`` and ``resolve_interface`` come from the checker."""

    def __init__(
        self,
        sink: DiagnosticSink,
        resolve_type: Callable[[ast.TypeExpr, ast.File], Type],
        resolve_interface: Callable[[ast.Name, ast.File], "tuple[ast.Interface, ast.File] | None"],
    ):
        self.sink = sink
        self.resolve_type = resolve_type
        self.resolve_interface = resolve_interface

    def build(self, node: ast.StateMachine | ast.OperationDef, file: ast.File, qname: str) -> MachineScope:
        scope = MachineScope(node, file, qname)
        own = f"{'operation' if isinstance(node, ast.OperationDef) else 'state machine'} '{node.name}'"
        if isinstance(node, ast.OperationDef):
            for p in node.params:
                self._add_var(scope, VarSym(p.name, self.resolve_type(p.type, file), "param", p, own))
        for m in node.members:
            if isinstance(m, ast.VarList):
                for v in m.vars:
                    kind = "const" if m.const else "var"
                    self._add_var(scope, VarSym(v.name, self.resolve_type(v.type, file), kind, v, own, v.init))
            elif isinstance(m, ast.ClockDecl):
                self._add_clock(scope, ClockSym(m.name, m, own))
            elif isinstance(m, ast.EventDecl):
                self._add_event(scope, m, own, file, both=True)
            elif isinstance(m, ast.InterfaceRef):
                self._add_interface(scope, m, file, context=None)
            elif isinstance(m, ast.Context):
                for c in m.members:
                    if isinstance(c, ast.InterfaceRef):
                        self._add_interface(scope, c, file, context=m.kind)
                    elif isinstance(c, ast.EventDecl):
                        self._add_event(scope, c, f"{m.kind} context of {own}", file, context=m.kind)
                    elif isinstance(c, ast.VarList):
                        for v in c.vars:
                            kind = "const" if c.const else "var"
                            self._add_var(scope, VarSym(v.name, self.resolve_type(v.type, file), kind, v, own, v.init, shared=True))
                    elif isinstance(c, ast.OpSig):
                        self._add_op(scope, c, f"{m.kind} context of {own}", file, platform=m.kind == "output")
            elif isinstance(m, ast.CycleDef):
                scope.cycle_defs.append(m)
        if not scope.robosim:
            # RoboChart events have no declared direction: both ways until connections say more.
            for e in scope.events.values():
                e.input = e.output = True
        scope.region = self._region(node, None)
        return scope

    # -- members

    def _add_var(self, scope: MachineScope, sym: VarSym) -> None:
        old = scope.vars.get(sym.name)
        if old is None:
            scope.vars[sym.name] = sym
            return
        if old.shared and sym.shared and old.type == sym.type:
            return  # the same shared variable, named by two interfaces
        self.sink.error(
            f"'{sym.name}' is declared twice in {scope.kind} '{scope.name}'",
            sym.span,
            Note(f"first declared in {old.origin}", old.span),
        )

    def _add_clock(self, scope: MachineScope, sym: ClockSym) -> None:
        old = scope.clocks.get(sym.name)
        if old is not None:
            if old.decl is sym.decl or old.origin != sym.origin:
                return  # the same clock brought in by an interface, or by two
            self.sink.error(f"clock '{sym.name}' is declared twice in {scope.kind} '{scope.name}'", sym.span, Note("first declared here", old.span))
            return
        scope.clocks[sym.name] = sym

    def _add_event(self, scope: MachineScope, e: ast.EventDecl, origin: str, file: ast.File, *, context: str | None = None, both: bool = False) -> None:
        t = self.resolve_type(e.type, file) if e.type is not None else None
        old = scope.events.get(e.name)
        if old is not None:
            if old.decl is e:
                pass
            elif old.origin == origin and not context:
                self.sink.error(f"event '{e.name}' is declared twice in {scope.kind} '{scope.name}'", e.name_span, Note("first declared here", old.span))
                return
            elif (old.type is None) != (t is None) or (t is not None and old.type is not None and str(old.type) != str(t) and not _same(old.type, t)):
                self.sink.error(
                    f"event '{e.name}' is declared with two types: {_show(old.type)} and {_show(t)}",
                    e.name_span,
                    Note(f"declared in {old.origin}", old.span),
                )
                return
            sym = old
        else:
            sym = EventSym(e.name, t, e, origin, broadcast=e.broadcast)
            scope.events[e.name] = sym
        if both or context == "input":
            sym.input = True
        if both or context == "output":
            sym.output = True

    def _add_op(self, scope: MachineScope, sig: ast.OpSig, origin: str, file: ast.File, platform: bool) -> None:
        params = tuple((p.name, self.resolve_type(p.type, file)) for p in sig.params)
        old = scope.ops.get(sig.name)
        if old is not None:
            if len(old.params) != len(params):
                self.sink.error(
                    f"operation '{sig.name}' is declared with {len(params)} parameters here and {len(old.params)} in {old.origin}",
                    sig.name_span,
                    Note("other declaration", old.span),
                )
            old.platform = old.platform or platform
            return
        scope.ops[sig.name] = OpSym(sig.name, params, sig, origin, platform)

    def _add_interface(self, scope: MachineScope, ref: ast.InterfaceRef, file: ast.File, context: str | None) -> None:
        found = self.resolve_interface(ref.name, file)
        iface, ifile = found if found is not None else (None, file)
        scope.interfaces.append((ref.kind if context is None else f"{context} context {ref.kind}", ref, iface))
        if iface is None:
            return
        origin = f"interface '{iface.name}'"
        for m in iface.members:
            if isinstance(m, ast.VarList):
                for v in m.vars:
                    kind = "const" if m.const else "var"
                    self._add_var(scope, VarSym(v.name, self.resolve_type(v.type, ifile), kind, v, origin, v.init, shared=True))
            elif isinstance(m, ast.ClockDecl):
                self._add_clock(scope, ClockSym(m.name, m, origin))
            elif isinstance(m, ast.EventDecl):
                if context is None and scope.robosim and ref.kind == "uses":
                    # RoboSim: a machine-level `uses` with events declares inputs (older style)
                    self._add_event(scope, m, origin, ifile, context="input")
                else:
                    self._add_event(scope, m, origin, ifile, context=context, both=context is None and not scope.robosim)
            elif isinstance(m, ast.OpSig):
                self._add_op(scope, m, origin, ifile, platform=context == "output")

    # -- nodes

    def _region(self, owner: ast.Node, parent: Region | None) -> Region:
        region = Region(owner, parent)
        members = owner.members  # type: ignore[attr-defined]
        for m in members:
            if isinstance(m, ast.NodeDecl):
                old = region.nodes.get(m.name)
                if old is not None:
                    self.sink.error(
                        f"node '{m.name}' is declared twice in {region.description}",
                        m.name_span,
                        Note("first declared here", old.name_span),
                    )
                    continue
                region.nodes[m.name] = m
                if isinstance(m, ast.State) and any(isinstance(x, ast.NodeDecl) for x in m.members):
                    region.children[m.name] = self._region(m, region)
            elif isinstance(m, ast.Transition):
                region.transitions.append(m)
        names: dict[str, ast.Transition] = {}
        for t in region.transitions:
            if t.name in names:
                self.sink.error(
                    f"transition '{t.name}' is declared twice in {region.description}",
                    t.name_span,
                    Note("first declared here", names[t.name].name_span),
                )
            else:
                names[t.name] = t
        return region


def _show(t: Type | None) -> str:
    return "none" if t is None else t.show()


def _same(a: Type, b: Type) -> bool:
    from robogen.semantics.types import same

    return same(a, b)


__all__ = [
    "VarSym",
    "ClockSym",
    "EventSym",
    "OpSym",
    "FuncSym",
    "EnumLitSym",
    "Symbol",
    "Region",
    "MachineScope",
    "ScopeBuilder",
    "UNKNOWN",
]
