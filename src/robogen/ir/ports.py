"""The FMU's ports and the routes of events inside it.

For a module, events the robotic platform sends to a controller are input clocks, events sent to
the platform and calls of the platform's operations are output clocks; connections between
controllers and machines inside the module become routes inside the FMU. For a single machine,
its own events and platform operations are the ports. A bidirectional connection (``[ mult ]``)
carries events both ways: routes follow it in each direction, and a platform event it carries
both ways is two clocks, the input ``e`` and the output ``e_event`` (see ``_clock_name``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

from robogen.diagnostics import Span, warning
from robogen.ir import model as ir
from robogen.ir.boundary import Boundary
from robogen.ir.layout import leaves
from robogen.ir.supported import FunMapT, check_codegen_type, not_supported
from robogen.semantics import types as T
from robogen.semantics.model import Controller, MachineScope, Module, OpSym
from robogen.syntax import ast

class MachinePorts(Protocol):
    """What the ports need to know of a machine being lowered."""

    scope: MachineScope
    machine: ir.Machine
    ctrl: Controller | None
    used_name: str

    def event_type(self, name: str) -> T.Type | None: ...
    def op_params(self, name: str) -> tuple[tuple[str, T.Type], ...]: ...
    def is_platform_operation(self, op: OpSym) -> bool: ...
    def is_abstract_operation(self, op: OpSym) -> bool: ...


class Ports:
    """Creates the FMU's clocks (each once, by name) and computes where events go."""

    def __init__(self, fmu: ir.Fmu, boundary: Boundary, lowerings: list[MachinePorts], normalise):
        self.fmu = fmu
        self.b = boundary
        self.lowerings = lowerings
        self.normalise = normalise  # model type -> concrete type

    def create(self) -> None:
        """Create the FMU's clocks in a stable order: inputs, then outputs (events, then
        operations), each in declaration order."""
        if self.b.module is None:
            self._machine_ports(self.lowerings[0])
            return
        info = self.b.module
        platform = info.platform.name if info.platform is not None else ""
        for conn in directed(info.connections):
            if conn.source == platform:
                port = self.input_port(conn.source_event, self._platform_event_type(info, conn.source_event), conn.span)
                for r in self._routes_into_controller(conn.target, conn.target_event, info):
                    self._deliverable(port.type, r, conn.span)
                    if r not in port.routes:
                        port.routes.append(r)
        for conn in directed(info.connections):
            if conn.target == platform:
                self.output_port(conn.target_event, "output-event", self._platform_event_type(info, conn.target_event), (), conn.span)
        for ml in self.lowerings:
            self._operation_ports(ml)

    def _machine_ports(self, ml: MachinePorts) -> None:
        """A single machine's ports: the events it receives and sends, its platform operations."""
        used_in, used_out = event_uses(ml.scope)
        for ev in ml.machine.events:
            sym = ml.scope.events[ev.name]
            if ml.scope.robosim or ev.name in used_in:
                self.input_port(ev.name, ev.value_type, sym.span).routes.append((0, ev.index))
        for name, sym in ml.scope.events.items():
            if sym.output and (ml.scope.robosim or name in used_out):
                self.output_port(name, "output-event", ml.event_type(name), (), sym.span)
        self._operation_ports(ml)

    def _operation_ports(self, ml: MachinePorts) -> None:
        """The output clocks of the operations a machine calls that leave the FMU: those of the
        platform and the abstract ones (definitions without nodes)."""
        for name, op in ml.scope.ops.items():
            if ml.is_platform_operation(op):
                self.output_port(name, "operation", None, ml.op_params(name), op.span)
            elif ml.is_abstract_operation(op):
                self.output_port(name, "operation", None, ml.op_params(name), op.span, abstract=True)

    def _platform_event_type(self, info: Module, name: str) -> T.Type | None:
        sym = info.platform.events.get(name) if info.platform is not None else None
        return None if sym is None or sym.type is None else self.normalise(sym.type)

    def _routes_into_controller(self, ctrl_name: str, event: str, info: Module) -> list[tuple[int, int]]:
        """Machine events that receive ``event`` when it reaches controller ``ctrl_name``."""
        routes = []
        for used, c in info.controllers:
            if used != ctrl_name:
                continue
            for conn in directed(c.connections):
                if conn.source == c.name and conn.source_event == event:
                    routes += self._machine_event(c, conn.target, conn.target_event)
        return routes

    def _machine_event(self, ctrl: Controller, machine: str, event: str) -> list[tuple[int, int]]:
        """(machine index, event index) of ``event`` of the machines used as ``machine`` in ``ctrl``."""
        routes = []
        for ml in self.lowerings:
            if ml.ctrl is ctrl and ml.used_name == machine:
                ev = ml.machine.event(event)
                if ev is not None:
                    routes.append((ml.machine.index, ev.index))
        return routes

    def output_routes(self, ml: MachinePorts, name: str, kind: str, span: Span | None,
                      params: tuple[tuple[str, T.Type], ...] | None = None, abstract: bool = False) -> tuple[tuple, ...]:
        """Where a machine's output event or operation call (of a platform or an ``abstract``
        operation) goes: ("port", index) or ("machine", machine index, event index). ``params``:
        the parameters of the operation called (a call inside a software operation names an
        operation the machine itself may not declare)."""
        if kind == "operation" or self.b.module is None:
            t = None if kind == "operation" else ml.event_type(name)
            params = ml.op_params(name) if params is None else params
            return (("port", self.output_port(name, kind, t, params, span, abstract).index),)
        info = self.b.module
        ctrl = ml.ctrl
        if ctrl is None:
            return ()
        routes: list[tuple] = []
        for conn in directed(ctrl.connections):
            if conn.source != ml.used_name or conn.source_event != name:
                continue
            if conn.target == ctrl.name:  # machine -> its controller -> the module's connections
                routes += self._from_controller(ml, info, ctrl, conn.target_event, name, span)
            else:  # machine -> machine of the same controller
                routes += [("machine", mi, me) for mi, me in self._machine_event(ctrl, conn.target, conn.target_event)]
        for route in routes:
            if route[0] == "machine":
                self._deliverable(ml.event_type(name), route[1:], span)
        return tuple(routes)

    def _deliverable(self, source: T.Type | None, route: tuple[int, int], span: Span | None) -> None:
        """A value of type ``source`` can reach the machine event of ``route``: the same type, or
        a number the delivery converts without a run-time error (connections may widen a number,
        RoboChart's nat to int or real; a bidirectional one carries it back too, narrowed)."""
        event = self.fmu.machines[route[0]].events[route[1]]
        target = event.value_type
        if source is None or target is None or source == target or (T.same(source, target) and source not in T.NUMERIC):
            return  # the same values (two declarations of one record or enumeration: the same layout)
        if not (source in T.NUMERIC and target in T.NUMERIC) or source == T.REAL:
            raise not_supported(f"a connection that delivers {source.show()} values to event '{event.name}' of "
                                f"{self.fmu.machines[route[0]].name}, which carries {target.show()}", span)

    def _from_controller(self, ml: MachinePorts, info: Module, ctrl: Controller, event: str, name: str,
                         span: Span | None) -> list[tuple]:
        """Where ``event`` of controller ``ctrl`` goes by the module's connections: to the platform
        (an output port) or into other controllers' machines."""
        ctrl_used = next((u for u, c in info.controllers if c is ctrl), ctrl.name)
        platform = info.platform.name if info.platform is not None else ""
        routes: list[tuple] = []
        for mconn in directed(info.connections):
            if mconn.source == ctrl_used and mconn.source_event == event:
                if mconn.target == platform:
                    port = self.output_port(mconn.target_event, "output-event", ml.event_type(name), (), span)
                    if port.type != ml.event_type(name) and port.type in T.NUMERIC:  # the first sender's number type is the port's
                        raise not_supported(f"sending {_shown(ml.event_type(name))} values on '{port.source}', whose "
                                            f"FMI variables another machine sends {_shown(port.type)} values on", span)
                    routes.append(("port", port.index))
                else:
                    routes += [("machine", mi, me) for mi, me in self._routes_into_controller(mconn.target, mconn.target_event, info)]
        return routes

    def input_port(self, name: str, t: T.Type | None, span: Span | None) -> ir.Port:
        fmu = self.fmu
        for p in fmu.inputs:
            if p.source == name:
                return p
        clock = self._clock_name(name, "input-event", span)
        fields = tuple(_flatten(clock + ".value" if not isinstance(t, T.RecordT) else clock, t, (), span, fmu.capacity_of)) \
            if t is not None else ()
        port = ir.Port(clock, "input-event", t, fields, span=span, index=len(fmu.inputs), model_name=_renamed(name, clock))
        fmu.inputs.append(port)
        return port

    def output_port(self, name: str, kind: str, t: T.Type | None, params, span: Span | None,
                    abstract: bool = False) -> ir.Port:
        fmu = self.fmu
        for p in fmu.outputs:
            if p.source == name and p.kind == kind:
                return p
        clock = self._clock_name(name, "abstract operation" if abstract else kind, span)
        if kind == "operation":
            fields: list[ir.Field_] = []
            for pname, ptype in params:
                fields += _flatten(f"{clock}.{pname}", ptype, (pname,), span, fmu.capacity_of)
            port = ir.Port(clock, kind, None, tuple(fields), tuple(params), span=span, index=len(fmu.outputs),
                           model_name=_renamed(name, clock), abstract=abstract)
        else:
            fields = _flatten(clock + ".value" if not isinstance(t, T.RecordT) else clock, t, (), span, fmu.capacity_of) if t is not None else []
            port = ir.Port(clock, kind, t, tuple(fields), span=span, index=len(fmu.outputs), model_name=_renamed(name, clock))
        fmu.outputs.append(port)
        return port

    def _clock_name(self, name: str, kind: str, span: Span | None) -> str:
        """The FMI name of the clock of event or operation ``name``: its own, unless FMI or
        robogen already names a variable so (``time``, the periodic clock, the counters) or
        another port has it (an input event and an output event of one name, an event and a
        platform operation); then ``<name>_event`` or ``<name>_call`` (numbered if that is taken
        too), with a warning. Ports are made in a fixed order (inputs, output events, operation
        calls), so the renaming is the same every time."""
        fmu = self.fmu
        taken = {"time", fmu.clock_name, *RESERVED} | {p.name for p in fmu.inputs + fmu.outputs}
        if name not in taken:
            return name
        base = f"{name}_call" if kind.endswith("operation") else f"{name}_event"
        clock, n = base, 2
        while clock in taken:
            clock, n = f"{base}{n}", n + 1
        what = {"operation": "platform operation", "abstract operation": "abstract operation", "input-event": "input event",
                "output-event": "output event"}[kind]
        why = "FMI's independent variable" if name == "time" else (
            "one of robogen's own FMI variables" if name in RESERVED or name == fmu.clock_name else "the clock of another port")
        fmu.warnings.append(warning(f"{what} '{name}' becomes the FMI clock '{clock}': '{name}' is {why}", span))
        return clock


#: FMI variables robogen adds to every FMU (besides ``time`` and the periodic clock)
RESERVED = ("cycles", "dropped_events", "deadline_misses")


def _shown(t: T.Type | None) -> str:
    return t.show() if t is not None else "no"


def _renamed(name: str, clock: str) -> str:
    return name if clock != name else ""


@dataclass(frozen=True)
class Way:
    """One direction of a connection: events go from ``source`` to ``target``."""

    source: str
    source_event: str
    target: str
    target_event: str
    span: Span | None


def directed(connections) -> list[Way]:
    """The directions events take over ``connections``: each connection's own, and for a
    bidirectional one (RoboChart's ``[ mult ]``) the reverse too, right after it."""
    ways = []
    for c in connections:
        ways.append(Way(c.source, c.source_event, c.target, c.target_event, c.span))
        if c.bidirectional:
            ways.append(Way(c.target, c.target_event, c.source, c.source_event, c.span))
    return ways


def event_uses(scope: MachineScope) -> tuple[set[str], set[str]]:
    """RoboChart events have no direction: those a machine receives (triggers, e?x) and those
    it sends (e!v, plain sends), from its transitions and actions."""
    ins: set[str] = set()
    outs: set[str] = set()

    def stmt(s):
        if s is None:
            return
        if isinstance(s, ast.Seq):
            for x in s.stmts:
                stmt(x)
        elif isinstance(s, ast.IfStmt):
            stmt(s.then)
            stmt(s.otherwise)
        elif isinstance(s, ast.StmtDeadline):
            stmt(s.stmt)
        elif isinstance(s, ast.Communicate):
            (ins if s.comm.kind == "?" else outs).add(s.comm.event)

    assert scope.region is not None
    for region in scope.region.walk():
        for t in region.transitions:
            if t.trigger is not None:
                ins.add(t.trigger.event)
            stmt(t.action)
        for node in region.nodes.values():
            for m in getattr(node, "members", ()):
                if isinstance(m, ast.StateAction):
                    stmt(m.stmt)
    return ins, outs


def _flatten(prefix: str, t: T.Type | None, path: tuple[str, ...], span: Span | None, capacity_of) -> list[ir.Field_]:
    """The FMI variables of a payload of type ``t`` named ``prefix``: its leaves
    (robogen.ir.layout), each a scalar or an array."""
    assert t is not None
    check_codegen_type(t, span, f"'{prefix}'")
    function = _function_part(t, prefix)
    if function is not None:
        raise not_supported(f"'{function}': a function value as an FMU port (its default is a lambda of the model, which "
                            "an FMI variable cannot carry)", span)
    return [ir.Field_(".".join((prefix,) + leaf.name), leaf.type, path + leaf.path) for leaf in leaves(t, capacity_of)]


def _function_part(t: T.Type, name: str) -> str | None:
    """The name of the first part of a value of ``t`` (named ``name``) that is a function value."""
    if isinstance(t, FunMapT):
        return name
    if isinstance(t, T.RecordT):
        return next((p for n, ft in t.fields if (p := _function_part(ft, f"{name}.{n}")) is not None), None)
    if isinstance(t, (T.SetT, T.SeqT)):
        return _function_part(t.element, f"{name}.elements")
    return None


__all__ = ["Ports", "MachinePorts", "Way", "directed", "event_uses"]
