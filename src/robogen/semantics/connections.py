"""Connections of modules and controllers (RoboChart reference manual, connections): both ends exist and
have the event, each end of an event is connected once, connected events carry the same type,
connections with the robotic platform are asynchronous, a RoboSim machine receives only on its
inputs and sends only on its outputs, and RoboChart's direction rules hold
(:mod:`robogen.semantics.directions`).

The checks read the assembled containers of :mod:`robogen.semantics.model`, so they run after
every machine's scope exists.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

from robogen.diagnostics import DiagnosticSink, Note, did_you_mean, working_on
from robogen.semantics import directions
from robogen.semantics import types as T
from robogen.semantics.model import Controller, EventSym, MachineScope, Module, SemanticModel
from robogen.syntax import ast


@dataclass(frozen=True)
class _End:
    """A part a connection can name: its kind for messages, its events, its scope if a machine."""

    kind: str
    events: Mapping[str, EventSym]
    machine: MachineScope | None = None


def check_controller(c: Controller, model: SemanticModel, sink: DiagnosticSink) -> None:
    """The connections of controller ``c`` of ``model`` (the machines' calls are followed into
    the operations they run)."""
    ends = {c.name: _End("controller", c.events)}
    for name, m in c.machines:
        ends[name] = _End("state machine", m.events, m)
    with working_on(c.node.span):
        _check(f"controller '{c.name}'", c.connections, ends, sink, None)
        directions.check_controller(c, model, sink)


def check_module(mod: Module, sink: DiagnosticSink) -> None:
    ends: dict[str, _End] = {}
    if mod.platform is not None:
        ends[mod.platform.name] = _End("robotic platform", mod.platform.events)
    for name, c in mod.controllers:
        ends[name] = _End("controller", c.events)
    with working_on(mod.node.span):
        _check(f"module '{mod.name}'", mod.connections, ends, sink, mod.platform.name if mod.platform else None)
        directions.check_module(mod, sink)


_Resolved = tuple[str, _End, EventSym]  # (name of the end, the end, its event)


def _check(owner: str, conns: tuple[ast.Connection, ...], ends: dict[str, _End], sink: DiagnosticSink,
           platform_name: str | None) -> None:
    used: dict[tuple[str, str, str], ast.Connection] = {}
    for conn in conns:
        source = _end(conn, "from", owner, ends, used, sink)
        target = _end(conn, "to", owner, ends, used, sink)
        if source is not None and target is not None:
            _compatible(conn, source[2], target[2], sink)
            if platform_name is not None and platform_name in (conn.source, conn.target) and not conn.asynchronous:
                sink.error("connections with the robotic platform must be asynchronous", conn.span,
                           Note("append '( _async )' to the connection (rule Cn2)"))
            _robosim_contexts(conn, source, target, sink)


def _end(conn: ast.Connection, role: str, owner: str, ends: dict[str, _End], used: dict, sink: DiagnosticSink) -> _Resolved | None:
    """One end of ``conn`` ("from" or "to") resolved to its part and event, or None (reported).
    A second connection of the same end is an error even when bidirectional: ``[ mult ]`` makes a
    connection carry events both ways, not connect an event twice."""
    name, event, name_span, event_span = directions.connection_end(conn, role)
    end = ends.get(name)
    if end is None:
        sink.error(f"'{name}' is not a part of {owner}" + did_you_mean(name, ends), name_span,
                   Note(f"the ends of a connection in {owner} are " + ", ".join(sorted(ends))))
        return None
    ev = end.events.get(event)
    if ev is None:
        sink.error(f"{end.kind} '{name}' has no event '{event}'" + did_you_mean(event, end.events), event_span)
        return None
    key = (role, name, event)
    if key in used:
        sink.error(f"event '{event}' of '{name}' is connected twice", event_span, Note("first connection here", used[key].span))
    used[key] = conn
    return name, end, ev


def _compatible(conn: ast.Connection, a: EventSym, b: EventSym, sink: DiagnosticSink) -> None:
    """Connected events carry the same type (or none), or the source's number widens to the
    target's (RoboChartValidator, RPConnectionIncompatibleType: ``typeCompatible(efrom.type,
    eto.type)``: nat to int, nat or int to real), and are both broadcast or neither."""
    if (a.type is None) != (b.type is None) or (a.type is not None and b.type is not None and not T.same(a.type, b.type)
                                                 and not T.widens(a.type, b.type)):
        sink.error(
            f"connected events have different types: '{a.name}' of '{conn.source}' carries {_show(a.type)}, "
            f"'{b.name}' of '{conn.target}' carries {_show(b.type)}",
            conn.span,
            Note(f"'{a.name}' is declared in {a.origin}", a.span),
            Note(f"'{b.name}' is declared in {b.origin}", b.span),
        )
    if a.broadcast != b.broadcast:
        sink.error("a broadcast event connects only to a broadcast event", conn.span)


def _robosim_contexts(conn: ast.Connection, source: _Resolved, target: _Resolved, sink: DiagnosticSink) -> None:
    """RoboSim: a machine receives only on input events and sends only on output events."""
    for (name, end, ev), receiving in ((source, False), (target, True)):
        if end.machine is None or not end.machine.robosim:
            continue
        if receiving and not ev.input:
            sink.error(f"'{ev.name}' is not an input of state machine '{name}'", conn.span, Note("declare it in the machine's input context"))
        if not receiving and not ev.output:
            sink.error(f"'{ev.name}' is not an output of state machine '{name}'", conn.span, Note("declare it in the machine's output context"))


def _show(t: T.Type | None) -> str:
    return "no value" if t is None else t.show()


__all__ = ["check_controller", "check_module"]
