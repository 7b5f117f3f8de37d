"""Building scopes: what a state machine or software operation can name.

A :class:`~robogen.semantics.model.MachineScope` is built for every ``stm`` and every
``operation`` definition. It holds the variables, constants, clocks, events and operations
visible in its body, each as a symbol that remembers where it was declared, and the machine's
region tree. Later stages (checks, IR lowering) resolve names through these scopes, so there is
one lookup logic. The builder collects into a mutable draft and returns the frozen scope.

Visibility (as the RoboChart reference manual and RoboTool's scope provider define it):

- own declarations (``var``/``const`` lists, ``clock``, ``event``; operation parameters);
- members of interfaces the container ``uses``, ``requires`` or ``provides`` (variables,
  constants, clocks, operations, events);
- RoboSim: the events of ``input context`` are inputs, those of ``output context`` outputs;
  operations required by the output context are the platform operations called with ``$op``.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from fractions import Fraction
from types import MappingProxyType
from typing import Callable

from robogen.diagnostics import DiagnosticSink, Note
from robogen.semantics.model import ClockSym, EventSym, MachineScope, OpSym, Region, VarSym
from robogen.semantics.periods import declared_period
from robogen.semantics.types import Type, same
from robogen.syntax import ast


@dataclass
class _Draft:
    """A scope being built (the frozen MachineScope is made from it at the end)."""

    node: ast.StateMachine | ast.OperationDef
    file: ast.File
    vars: dict[str, VarSym] = field(default_factory=dict)
    clocks: dict[str, ClockSym] = field(default_factory=dict)
    events: dict[str, EventSym] = field(default_factory=dict)
    ops: dict[str, OpSym] = field(default_factory=dict)
    cycle_defs: list[ast.CycleDef] = field(default_factory=list)
    interfaces: list[tuple[str, ast.InterfaceRef, ast.Interface | None]] = field(default_factory=list)

    @property
    def robosim(self) -> bool:
        return self.file.language == "robosim"

    @property
    def kind(self) -> str:
        return "operation" if isinstance(self.node, ast.OperationDef) else "state machine"

    @property
    def name(self) -> str:
        return self.node.name


ResolveType = Callable[[ast.TypeExpr | None, ast.File], Type]
ResolveInterface = Callable[[ast.Name, ast.File], "tuple[ast.Interface, ast.File] | None"]
ResolveOperation = Callable[[str, ast.File], "ast.OperationDef | None"]


class ScopeBuilder:
    """Builds MachineScopes, and the event and operation tables of containers. The resolvers
    come from the checker: types, interfaces, and the software operation definition a name
    denotes where a file can see it."""

    def __init__(self, sink: DiagnosticSink, resolve_type: ResolveType, resolve_interface: ResolveInterface,
                 resolve_operation: ResolveOperation):
        self.sink = sink
        self.resolve_type = resolve_type
        self.resolve_interface = resolve_interface
        self.resolve_operation = resolve_operation

    def build(self, node: ast.StateMachine | ast.OperationDef, file: ast.File, qname: str) -> MachineScope:
        draft = _Draft(node, file)
        own = f"{draft.kind} '{node.name}'"
        if isinstance(node, ast.OperationDef):
            for p in node.params:
                self._add_var(draft, VarSym(p.name, self.resolve_type(p.type, file), "param", p, own))
        for m in node.members:
            self._member(draft, m, own)
        if not draft.robosim:
            # RoboChart events have no declared direction: both ways until connections say more.
            draft.events = {n: replace(e, input=True, output=True) for n, e in draft.events.items()}
        return MachineScope(
            node, file, qname,
            vars=MappingProxyType(draft.vars),
            clocks=MappingProxyType(draft.clocks),
            events=MappingProxyType(draft.events),
            ops=MappingProxyType(draft.ops),
            region=self._region(node, ()),
            cycle_defs=tuple(draft.cycle_defs),
            interfaces=tuple(draft.interfaces),
            period=self._period(draft),
            definitions=MappingProxyType(self._definitions(draft)),
        )

    def _member(self, draft: _Draft, m: ast.Node, own: str) -> None:
        file = draft.file
        if isinstance(m, ast.VarList):
            for v in m.vars:
                kind = "const" if m.const else "var"
                self._add_var(draft, VarSym(v.name, self.resolve_type(v.type, file), kind, v, own, v.init))
        elif isinstance(m, ast.ClockDecl):
            self._add_clock(draft, ClockSym(m.name, m, own))
        elif isinstance(m, ast.EventDecl):
            self._add_event(draft, m, own, file, both=True)
        elif isinstance(m, ast.InterfaceRef):
            self._add_interface(draft, m, file, context=None)
        elif isinstance(m, ast.Context):
            for c in m.members:
                self._context_member(draft, m.kind, c, own)
        elif isinstance(m, ast.CycleDef):
            draft.cycle_defs.append(m)

    def _context_member(self, draft: _Draft, context: str, c: ast.Node, own: str) -> None:
        file = draft.file
        if isinstance(c, ast.InterfaceRef):
            self._add_interface(draft, c, file, context=context)
        elif isinstance(c, ast.EventDecl):
            self._add_event(draft, c, f"{context} context of {own}", file, context=context)
        elif isinstance(c, ast.VarList):
            for v in c.vars:
                kind = "const" if c.const else "var"
                self._add_var(draft, VarSym(v.name, self.resolve_type(v.type, file), kind, v, own, v.init, shared=True))
        elif isinstance(c, ast.OpSig):
            self._add_op(draft, c, f"{context} context of {own}", file, platform=context == "output")

    def _period(self, draft: _Draft) -> Fraction | None:
        if not draft.cycle_defs:
            return None
        return declared_period(draft.cycle_defs, f"state machine '{draft.name}'", self.sink)

    def _definitions(self, draft: _Draft) -> dict[str, ast.OperationDef]:
        """The software operation definitions visible from the file for the operations the
        scope requires (the others belong to the robotic platform)."""
        found = {}
        for name in draft.ops:
            definition = self.resolve_operation(name, draft.file)
            if definition is not None:
                found[name] = definition
        return found

    # -- containers

    def container_events(self, node: ast.Platform | ast.Controller, file: ast.File) -> dict[str, EventSym]:
        """The events of a controller or robotic platform: its own, then those of the
        interfaces it names (the first declaration of a name wins)."""
        events: dict[str, EventSym] = {}
        origin = f"{type(node).__name__.lower()} '{node.name}'"
        for m in node.members:
            if isinstance(m, ast.EventDecl):
                events[m.name] = EventSym(m.name, self.resolve_type(m.type, file) if m.type else None, m, origin, True, True, m.broadcast)
            elif isinstance(m, ast.InterfaceRef):
                found = self.resolve_interface(m.name, file)
                if found:
                    iface, ifile = found
                    for x in iface.members:
                        if isinstance(x, ast.EventDecl) and x.name not in events:
                            events[x.name] = EventSym(x.name, self.resolve_type(x.type, ifile) if x.type else None, x,
                                                      f"interface '{iface.name}'", True, True, x.broadcast)
        return events

    def platform_operations(self, node: ast.Platform, file: ast.File) -> dict[str, OpSym]:
        """The operations a robotic platform declares or provides through its interfaces."""
        ops: dict[str, OpSym] = {}
        origin = f"robotic platform '{node.name}'"
        for m in node.members:
            if isinstance(m, ast.OpSig):
                ops.setdefault(m.name, OpSym(m.name, self._params(m, file), m, origin, platform=True))
            elif isinstance(m, ast.InterfaceRef) and m.kind == "provides":
                found = self.resolve_interface(m.name, file)
                if found:
                    iface, ifile = found
                    for x in iface.members:
                        if isinstance(x, ast.OpSig):
                            ops.setdefault(x.name, OpSym(x.name, self._params(x, ifile), x, f"interface '{iface.name}'", platform=True))
        return ops

    def _params(self, sig: ast.OpSig, file: ast.File) -> tuple[tuple[str, Type], ...]:
        return tuple((p.name, self.resolve_type(p.type, file)) for p in sig.params)

    # -- members

    def _add_var(self, draft: _Draft, sym: VarSym) -> None:
        old = draft.vars.get(sym.name)
        if old is None:
            draft.vars[sym.name] = sym
            return
        if old.shared and sym.shared and old.type == sym.type:
            return  # the same shared variable, named by two interfaces
        self.sink.error(
            f"'{sym.name}' is declared twice in {draft.kind} '{draft.name}'",
            sym.span,
            Note(f"first declared in {old.origin}", old.span),
        )

    def _add_clock(self, draft: _Draft, sym: ClockSym) -> None:
        old = draft.clocks.get(sym.name)
        if old is not None:
            if old.decl is sym.decl or old.origin != sym.origin:
                return  # the same clock brought in by an interface, or by two
            self.sink.error(f"clock '{sym.name}' is declared twice in {draft.kind} '{draft.name}'", sym.span, Note("first declared here", old.span))
            return
        draft.clocks[sym.name] = sym

    def _add_event(self, draft: _Draft, e: ast.EventDecl, origin: str, file: ast.File, *, context: str | None = None, both: bool = False) -> None:
        t = self.resolve_type(e.type, file) if e.type is not None else None
        old = draft.events.get(e.name)
        if old is not None:
            if old.decl is e:
                pass
            elif old.origin == origin and not context:
                self.sink.error(f"event '{e.name}' is declared twice in {draft.kind} '{draft.name}'", e.name_span, Note("first declared here", old.span))
                return
            elif (old.type is None) != (t is None) or (t is not None and old.type is not None and str(old.type) != str(t) and not same(old.type, t)):
                self.sink.error(
                    f"event '{e.name}' is declared with two types: {_show(old.type)} and {_show(t)}",
                    e.name_span,
                    Note(f"declared in {old.origin}", old.span),
                )
                return
            sym = old
        else:
            sym = EventSym(e.name, t, e, origin, broadcast=e.broadcast)
        draft.events[e.name] = replace(sym, input=sym.input or both or context == "input",
                                       output=sym.output or both or context == "output")

    def _add_op(self, draft: _Draft, sig: ast.OpSig, origin: str, file: ast.File, platform: bool) -> None:
        params = self._params(sig, file)
        old = draft.ops.get(sig.name)
        if old is not None:
            if len(old.params) != len(params):
                self.sink.error(
                    f"operation '{sig.name}' is declared with {len(params)} parameters here and {len(old.params)} in {old.origin}",
                    sig.name_span,
                    Note("other declaration", old.span),
                )
            if platform and not old.platform:
                draft.ops[sig.name] = replace(old, platform=True)
            return
        draft.ops[sig.name] = OpSym(sig.name, params, sig, origin, platform)

    def _add_interface(self, draft: _Draft, ref: ast.InterfaceRef, file: ast.File, context: str | None) -> None:
        found = self.resolve_interface(ref.name, file)
        iface, ifile = found if found is not None else (None, file)
        draft.interfaces.append((ref.kind if context is None else f"{context} context {ref.kind}", ref, iface))
        if iface is None:
            return
        origin = f"interface '{iface.name}'"
        for m in iface.members:
            if isinstance(m, ast.VarList):
                for v in m.vars:
                    kind = "const" if m.const else "var"
                    self._add_var(draft, VarSym(v.name, self.resolve_type(v.type, ifile), kind, v, origin, v.init, shared=True))
            elif isinstance(m, ast.ClockDecl):
                self._add_clock(draft, ClockSym(m.name, m, origin))
            elif isinstance(m, ast.EventDecl):
                if context is None and draft.robosim and ref.kind == "uses":
                    # RoboSim: a machine-level `uses` with events declares inputs (older style)
                    self._add_event(draft, m, origin, ifile, context="input")
                else:
                    self._add_event(draft, m, origin, ifile, context=context, both=context is None and not draft.robosim)
            elif isinstance(m, ast.OpSig):
                self._add_op(draft, m, origin, ifile, platform=context == "output")

    # -- nodes

    def _region(self, owner: ast.Node, path: tuple[str, ...]) -> Region:
        """The region of ``owner`` (its nodes, transitions and composite states), built bottom-up."""
        description = Region(owner, path).description
        nodes: dict[str, ast.NodeDecl] = {}
        children: dict[str, Region] = {}
        transitions: list[ast.Transition] = []
        for m in owner.members:  # type: ignore[attr-defined]
            if isinstance(m, ast.NodeDecl):
                old = nodes.get(m.name)
                if old is not None:
                    self.sink.error(f"node '{m.name}' is declared twice in {description}", m.name_span, Note("first declared here", old.name_span))
                    continue
                nodes[m.name] = m
                if isinstance(m, ast.State) and any(isinstance(x, ast.NodeDecl) for x in m.members):
                    children[m.name] = self._region(m, path + (m.name,))
            elif isinstance(m, ast.Transition):
                transitions.append(m)
        names: dict[str, ast.Transition] = {}
        for t in transitions:
            if t.name in names:
                self.sink.error(f"transition '{t.name}' is declared twice in {description}", t.name_span,
                                Note("first declared here", names[t.name].name_span))
            else:
                names[t.name] = t
        return Region(owner, path, MappingProxyType(nodes), tuple(transitions), MappingProxyType(children))


def _show(t: Type | None) -> str:
    return "none" if t is None else t.show()


__all__ = ["ScopeBuilder"]
