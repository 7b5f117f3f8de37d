"""Connections and cycle periods (docs/robosim-robochart.md §3.1 and §5): the part of the
checker that needs every machine's scope, so :class:`~robogen.semantics.checker.Checker` runs
it after the machines. A mixin of the Checker: it uses its sink, tables and lookups."""

from __future__ import annotations

from fractions import Fraction
from typing import TYPE_CHECKING, Callable

from robogen.diagnostics import DiagnosticSink, Note, Span, did_you_mean
from robogen.semantics import types as T
from robogen.semantics.scope import EventSym, MachineScope
from robogen.syntax import ast

if TYPE_CHECKING:
    from robogen.semantics.checker import ControllerInfo, ModuleInfo


class ConnectionChecks:
    """Cycle definitions and periods, and the connections of modules and controllers."""

    # provided by the Checker
    sink: DiagnosticSink
    scopes: dict[int, MachineScope]
    controllers: dict[int, ControllerInfo]
    modules: dict[int, ModuleInfo]
    resolve_type: Callable[[ast.TypeExpr | None, ast.File], T.Type]
    resolve_interface: Callable[[ast.Name, ast.File], tuple[ast.Interface, ast.File] | None]

    def cycle_def(self, c: ast.CycleDef, previous: Fraction | None, owner: str) -> Fraction | None:
        """The period p of `cycleDef cycle == p` (a positive constant)."""
        e = c.expr
        if not (isinstance(e, ast.Binary) and e.op == "==" and isinstance(e.left, ast.Keyword) and e.left.word == "cycle"):
            self.sink.error("a cycle definition has the form 'cycleDef cycle == p' with p a positive number", e.span)
            return previous
        value = e.right
        if isinstance(value, ast.IntLit):
            period = Fraction(value.value)
        elif isinstance(value, ast.RealLit):
            period = Fraction(value.text)
        else:
            self.sink.error("the period in 'cycleDef cycle == p' must be a number literal", value.span)
            return previous
        if period <= 0:
            self.sink.error(f"the cycle period must be positive, not {value.text if isinstance(value, ast.RealLit) else value.value}", value.span)  # type: ignore[union-attr]
            return previous
        if previous is not None and previous != period:
            self.sink.error(f"{owner} declares two different cycle periods", c.span)
        return period

    def module_periods(self, info: ModuleInfo) -> None:
        """robogen: every machine, controller and module of one model has the same period."""
        periods: list[tuple[Fraction, str, Span | None]] = []
        if info.period is not None:
            periods.append((info.period, f"module '{info.node.name}'", info.node.name_span))
        for _, c, cf in info.controllers:
            ci = self.controllers.get(id(c))
            if ci is not None and ci.period is not None:
                periods.append((ci.period, f"controller '{c.name}'", c.name_span))
            if ci is None:
                continue
            for _, m, mf in ci.machines:
                scope = self.scopes.get(id(m))
                if scope is not None and scope.cycle_defs:
                    p = self._machine_period(scope)
                    if p is not None:
                        periods.append((p, f"state machine '{m.name}'", m.name_span))
        if periods:
            first = periods[0]
            for p, owner, span in periods[1:]:
                if p != first[0]:
                    self.sink.error(
                        f"{owner} has cycle period {frac(p)}, but {first[1]} has {frac(first[0])}",
                        span,
                        Note("robogen requires one period for every machine, controller and module of a model"),
                    )
            info.period = first[0]

    def _machine_period(self, scope: MachineScope) -> Fraction | None:
        period = None
        for c in scope.cycle_defs:
            period = self.cycle_def(c, period, f"state machine '{scope.name}'")
        return period

    # connections

    def _endpoint_events(self, node: ast.Node, f: ast.File) -> dict[str, EventSym]:
        if isinstance(node, (ast.StateMachine,)):
            scope = self.scopes.get(id(node))
            return dict(scope.events) if scope else {}
        events: dict[str, EventSym] = {}
        origin = f"{type(node).__name__.lower()} '{node.name}'"  # type: ignore[attr-defined]
        for m in node.members:  # type: ignore[attr-defined]
            if isinstance(m, ast.EventDecl):
                events[m.name] = EventSym(m.name, self.resolve_type(m.type, f) if m.type else None, m, origin, True, True, m.broadcast)
            elif isinstance(m, ast.InterfaceRef):
                found = self.resolve_interface(m.name, f)
                if found:
                    iface, ifile = found
                    for x in iface.members:
                        if isinstance(x, ast.EventDecl) and x.name not in events:
                            events[x.name] = EventSym(x.name, self.resolve_type(x.type, ifile) if x.type else None, x, f"interface '{iface.name}'", True, True, x.broadcast)
        return events

    def _connections(self, owner: str, members, ends: dict[str, tuple[ast.Node, ast.File, str]], f: ast.File, platform_name: str | None) -> None:
        used: dict[tuple[str, str, str], ast.Connection] = {}
        for conn in members:
            if not isinstance(conn, ast.Connection):
                continue
            spans = conn.spans or (conn.span,) * 4
            resolved = []
            for end, event, espan, vspan, role in (
                (conn.source, conn.source_event, spans[0], spans[1], "from"),
                (conn.target, conn.target_event, spans[2], spans[3], "to"),
            ):
                if end not in ends:
                    self.sink.error(
                        f"'{end}' is not a part of {owner}" + did_you_mean(end, ends),
                        espan,
                        Note(f"the ends of a connection in {owner} are " + ", ".join(sorted(ends))),
                    )
                    resolved.append(None)
                    continue
                node, nfile, kind = ends[end]
                events = self._endpoint_events(node, nfile)
                ev = events.get(event)
                if ev is None:
                    self.sink.error(f"{kind} '{end}' has no event '{event}'" + did_you_mean(event, events), vspan)
                    resolved.append(None)
                    continue
                key = (role, end, event)
                if key in used and not conn.mult:
                    self.sink.error(f"event '{event}' of '{end}' is connected twice", vspan, Note("first connection here", used[key].span))
                used[key] = conn
                resolved.append((end, node, ev, kind))
            if resolved[0] and resolved[1]:
                (_, _, a, ka), (_, _, b, kb) = resolved  # type: ignore[misc]
                if (a.type is None) != (b.type is None) or (a.type is not None and b.type is not None and not T.same(a.type, b.type)):
                    self.sink.error(
                        f"connected events have different types: '{a.name}' of '{conn.source}' carries {_show(a.type)}, "
                        f"'{b.name}' of '{conn.target}' carries {_show(b.type)}",
                        conn.span,
                        Note(f"'{a.name}' is declared in {a.origin}", a.span),
                        Note(f"'{b.name}' is declared in {b.origin}", b.span),
                    )
                if a.broadcast != b.broadcast:
                    self.sink.error("a broadcast event connects only to a broadcast event", conn.span)
                if platform_name is not None and platform_name in (conn.source, conn.target) and not conn.asynchronous:
                    self.sink.error(
                        "connections with the robotic platform must be asynchronous",
                        conn.span,
                        Note("append '( _async )' to the connection (rule Cn2)"),
                    )
                # RoboSim direction: a machine receives only on input events and sends only on output events.
                for (end, node, ev, kind), receiving in ((resolved[0], False), (resolved[1], True)):
                    if isinstance(node, ast.StateMachine):
                        scope = self.scopes.get(id(node))
                        if scope is not None and scope.robosim:
                            if receiving and not ev.input:
                                self.sink.error(f"'{ev.name}' is not an input of state machine '{end}'", conn.span, Note("declare it in the machine's input context"))
                            if not receiving and not ev.output:
                                self.sink.error(f"'{ev.name}' is not an output of state machine '{end}'", conn.span, Note("declare it in the machine's output context"))

    def controller_connections(self, c: ast.Controller, f: ast.File) -> None:
        info = self.controllers.get(id(c))
        if info is None:
            return
        ends: dict[str, tuple[ast.Node, ast.File, str]] = {c.name: (c, f, "controller")}
        for name, m, mf in info.machines:
            ends[name] = (m, mf, "state machine")
        self._connections(f"controller '{c.name}'", c.members, ends, f, None)

    def module_connections(self, mod: ast.Module, f: ast.File) -> None:
        info = self.modules.get(id(mod))
        if info is None:
            return
        ends: dict[str, tuple[ast.Node, ast.File, str]] = {}
        if info.platform is not None:
            ends[info.platform_name] = (info.platform, info.platform_file or f, "robotic platform")
        for name, c, cf in info.controllers:
            ends[name] = (c, cf, "controller")
        self._connections(f"module '{mod.name}'", mod.members, ends, f, info.platform_name or None)


def frac(f: Fraction) -> str:
    return str(f.numerator) if f.denominator == 1 else str(float(f))


def _show(t: T.Type | None) -> str:
    return "no value" if t is None else t.show()


__all__ = ["ConnectionChecks", "frac"]
