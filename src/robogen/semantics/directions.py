"""Which way events go through connections: RoboChart's rules Cn5 to Cn9.

A RoboChart event has no declared direction; a connection gives it one. A unidirectional
connection ``A on e to B on f`` carries e out of A and f into B, so a state machine at its start
must not take e as input (Cn9) and a machine at its end must not output on f (Cn8). What a machine
does counts as it runs: its own triggers and actions, and those of the software operations it
calls, however deep. A bidirectional connection (``[ mult ]``) restricts neither end. In a module,
a connection that reaches a controller must agree with the controller's own connection on that
event: both bidirectional (Cn5), or, for a unidirectional one, the controller's connection carries
the event on in the same direction (Cn6 at the connection's end, Cn7 at its start).

RoboChart's reference tool, RoboTool (``checkControllerConnections``, ``checkModuleConnections``
in its ``RoboChartValidator``), decides these rules; robogen reports them with RoboTool's
messages, and differs where RoboTool's behaviour is an accident:

- RoboTool stops checking a controller at its first bidirectional connection, so connections
  declared after one go unchecked; robogen skips only the bidirectional connection itself.
- RoboTool counts the operations a machine *requires* (whether it calls them or not) and names an
  operation only if it communicates itself: an input or output two calls deep makes it report
  nothing at all. robogen counts the operations a machine *calls*, resolved as code generation
  resolves them (the controller's operation, else the definition visible from the calling file),
  each once; it names the operation the machine calls and notes where the communication is.
- Cn5 at the start of a module connection: RoboTool's message names the event where the controller
  belongs and says "end"; robogen names the controller and says "start".
- A part used by reference is named as the connection names it, followed by its definition's name:
  ``stm_ref0 (OperationInputSTM)``.

RoboSim machines are left to their input and output contexts (:mod:`robogen.semantics.connections`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Iterator

from robogen.diagnostics import DiagnosticSink, Note, Span
from robogen.semantics import types as T
from robogen.semantics.model import IN, OUT, Controller, EventSym, MachineScope, Module, SemanticModel, communication_of
from robogen.syntax import ast

# ---------------------------------------------------------------------------- what a machine does


@dataclass(frozen=True)
class Use:
    """One input or output a machine makes as it runs."""

    event: EventSym  # as the communicating machine or operation declares it
    kind: str  # IN or OUT
    node: ast.Node  # the trigger or statement
    via: tuple[str, ...]  # the operations called, from the machine's call down to the one communicating


# The software operation a call statement of a body runs (None: the robotic platform's).
Resolve = Callable[[ast.CallStmt | ast.DollarCall, MachineScope], "MachineScope | None"]


def uses(machine: MachineScope, resolve: Resolve) -> list[Use]:
    """Every input and output of ``machine``: its own, then those of each operation it calls
    (``resolve`` gives the definition a call runs, or None for a platform operation), recursively.
    Below each operation the machine calls, every operation is followed once."""
    return list(_uses(machine, resolve, (), set()))


def _uses(scope: MachineScope, resolve: Resolve, via: tuple[str, ...], seen: set[int]) -> Iterator[Use]:
    for x in scope.body():
        if isinstance(x, (ast.CallStmt, ast.DollarCall)):
            op = resolve(x, scope)
            if op is None or id(op.node) in seen:
                continue
            seen.add(id(op.node))
            # each operation the machine calls is followed on its own, so that it is named with
            # everything it does even when another call reached the same operations first
            yield from _uses(op, resolve, via + (op.name,), seen if via else {id(scope.node), id(op.node)})
            continue
        use = communication_of(x)
        event = scope.events.get(use.event) if use is not None else None
        if event is not None:
            yield Use(event, use.direction, use.node, via)  # type: ignore[union-attr]


# ---------------------------------------------------------------------------- Cn8 and Cn9


def check_controller(ctrl: Controller, model: SemanticModel, sink: DiagnosticSink) -> None:
    """Cn8 and Cn9 on the controller's unidirectional connections; calls run the operations
    ``model`` resolves them to inside ``ctrl`` (as code generation runs them)."""
    machines = {name: m for name, m in ctrl.machines if name != ctrl.name and not m.robosim}

    def resolve(call: ast.CallStmt | ast.DollarCall, caller: MachineScope) -> MachineScope | None:
        return model.operation_called(call, caller, ctrl)
    done: dict[int, list[Use]] = {}
    for conn in ctrl.connections:
        if conn.bidirectional:
            continue
        for role in ("from", "to"):
            name, event, span, _ = connection_end(conn, role)
            machine = machines.get(name)
            if machine is None or event not in machine.events:
                continue
            found = done.setdefault(id(machine.node), uses(machine, resolve))
            _check_end(role, _part(name, machine.name), machine.events[event], found, span, sink)


def _check_end(role: str, part: str, event: EventSym, found: list[Use], span: Span | None, sink: DiagnosticSink) -> None:
    """One machine end: at the start it must not receive ``event``, at the end not send it."""
    kind, verb, rule = (IN, "receives input on", "Cn9") if role == "from" else (OUT, "outputs on", "Cn8")
    hits = [u for u in found if u.kind == kind and u.event.name == event.name and _same_event(u.event, event)]
    head = (f"{event.name} on {part} is used as the {'start' if role == 'from' else 'end'} of a unidirectional "
            f"connection, but {part} {verb} {event.name}")
    own = [u for u in hits if not u.via]
    if own:
        sink.error(f"{head} (rule {rule})", span, Note(f"{part} {verb} {event.name} here", _earliest(own).node.span))
        return
    for op in dict.fromkeys(u.via[0] for u in hits):
        first = _earliest([u for u in hits if u.via[0] == op])
        sink.error(f"{head} via the operation {op} (rule {rule})", span,
                   Note(f"{_chain(first.via)} {verb} {event.name} here", first.node.span))


def _same_event(a: EventSym, b: EventSym) -> bool:
    """An operation's event stands for the machine's event of the same name and type."""
    if a.type is None or b.type is None:
        return a.type is None and b.type is None
    return T.assignable(a.type, b.type) or T.assignable(b.type, a.type)


def _chain(via: tuple[str, ...]) -> str:
    """How a note names the operation that communicates: 'operation Op', or 'operation Op calls
    Inner, which' when the machine's call reaches it through others."""
    return f"operation {via[0]}" + "".join(f" calls {callee}, which" for callee in via[1:])


def _earliest(found: list[Use]) -> Use:
    """The use that comes first in the source (notes point at it)."""

    def position(u: Use) -> tuple:
        s = u.node.span
        return (0, "", 0, 0) if s is None else (1, s.path, s.line, s.column)

    return min(found, key=position)


# ---------------------------------------------------------------------------- Cn5 to Cn7


def check_module(mod: Module, sink: DiagnosticSink) -> None:
    """Cn5 to Cn7: each module connection that reaches a controller agrees with the controller's
    own connections on that event (the first that disagrees is reported)."""
    controllers = dict(mod.controllers)
    for conn in mod.connections:
        for role in ("to", "from"):
            name, event, span, _ = connection_end(conn, role)
            ctrl = controllers.get(name)
            if ctrl is None:
                continue
            for inner in ctrl.connections:
                problem = _disagreement(conn, role, ctrl, inner, event)
                if problem is not None:
                    tail, note = problem
                    part = _part(name, ctrl.name)
                    end = "start" if role == "from" else "end"
                    kind = "bidirectional" if conn.bidirectional else "unidirectional"
                    sink.error(f"{event} on {part} is used as the {end} of a {kind} connection, but {part} {tail}", span,
                               Note(note, inner.span))
                    break


def _disagreement(conn: ast.Connection, role: str, ctrl: Controller, inner: ast.Connection, event: str) -> tuple[str, str] | None:
    """How ``inner``, a connection of ``ctrl``, disagrees with the module connection ``conn`` that
    reaches ``ctrl`` on ``event`` at its ``role`` end: (the end of the message, a note on
    ``inner``), or None if it agrees or is on another event."""
    into = inner.source == ctrl.name and inner.source_event == event  # takes the event on into the controller
    out_of = inner.target == ctrl.name and inner.target_event == event  # brings the event out of the controller
    if not (into or out_of):
        return None
    c = ctrl.name
    if conn.bidirectional:
        if inner.bidirectional:
            return None
        return f"does not contain a bidirectional connection to {event} (rule Cn5)", f"{c}'s connection on {event} is unidirectional"
    rule = "Cn7" if role == "from" else "Cn6"
    if inner.bidirectional:
        return f"contains a bidirectional connection to {event} (rule {rule})", f"{c}'s connection on {event} is bidirectional"
    if role == "to" and not into:
        return f"contains a connection to {event} (rule Cn6)", f"inside {c}, this connection sends {event} out of {c}"
    if role == "from" and not out_of:
        return f"contains a connection from {event} (rule Cn7)", f"inside {c}, this connection takes {event} into {c}"
    return None


# ---------------------------------------------------------------------------- helpers


def connection_end(conn: ast.Connection, role: str) -> tuple[str, str, Span | None, Span | None]:
    """One end of ``conn`` (``"from"`` or ``"to"``): the part, its event, and where each is written."""
    spans = conn.spans or (conn.span,) * 4
    if role == "from":
        return conn.source, conn.source_event, spans[0], spans[1]
    return conn.target, conn.target_event, spans[2], spans[3]


def _part(used: str, defined: str) -> str:
    """How messages name a part: as the connection names it, with its definition's name if that
    differs (``stm_ref0 (OperationInputSTM)``)."""
    return used if used == defined else f"{used} ({defined})"


__all__ = ["Use", "uses", "connection_end", "check_controller", "check_module"]
