"""Lowering: a checked model and a boundary (a module, a controller or one state machine)
become one :class:`~robogen.ir.model.Fmu`.

The boundary decides the FMU's ports. For a module, events the robotic platform sends to a
controller are input clocks, events sent to the platform and calls of the platform's operations
are output clocks; connections between controllers and machines inside the module become
routes inside the FMU. For a single machine, its own events and platform operations are the ports.

Every machine becomes a control-flow graph (see :mod:`robogen.ir.model`). Constructs that have
no code-generation meaning yet (sets, sequences, quantifiers, strings, user functions without an
implementation, probabilistic junctions) are reported as located errors, never silently dropped.
"""

from __future__ import annotations

import hashlib
import re
from dataclasses import dataclass, field
from fractions import Fraction

from robogen.diagnostics import DiagnosticSink, Note, RobogenError, Span, did_you_mean, working_on
from robogen.ir import model as ir
from robogen.semantics import types as T
from robogen.semantics.model import (Controller, EnumLitSym, EventSym, FuncSym, MachineScope, Module, OpSym, Region,
                                     SemanticModel, VarSym)
from robogen.syntax import ast


@dataclass
class Options:
    semantics: str = "exhaustive"  # exhaustive | stepwise
    trigger: str = "cycle"  # cycle | on-input (RoboSim)
    time_unit: Fraction = Fraction(1)  # seconds per model time unit
    settings: dict[str, str] = field(default_factory=dict)  # constant name -> value text
    given: str = "int"  # the scalar type of given types
    max_steps: int = 1000
    functions: str | None = None  # a C file implementing the model's user functions


class Unsupported(Exception):
    pass


def not_supported(what: str, span: Span | None) -> RobogenError:
    return RobogenError.at(f"{what} is not supported for code generation", span)


# ---------------------------------------------------------------------------- boundary


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


def select_boundary(model: SemanticModel, module: str | None = None, machine: str | None = None) -> Boundary:
    """The module or machine to compile: named, or the only one in the model."""

    def named(candidates, name, what):
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

    modules = [Boundary("module", m.name, m.qname, module=m) for m in model.modules]
    machines = [Boundary("machine", s.name, s.qname, machine=s) for s in model.machines]
    if module is not None:
        return named(modules, module, "module")
    if machine is not None:
        return named(machines, machine, "state machine")
    if len(modules) == 1:
        return modules[0]
    if not modules and len(machines) == 1:
        return machines[0]
    if modules:
        raise RobogenError.at("the model has several modules; choose one with --module: " + ", ".join(sorted(m.qname for m in modules)), None)
    if not machines:
        raise RobogenError.at("the model has no module and no state machine to compile", None)
    raise RobogenError.at("the model has several state machines and no module; choose one with --machine: " + ", ".join(sorted(m.qname for m in machines)), None)


def model_identifier(name: str) -> str:
    ident = re.sub(r"[^A-Za-z0-9_]", "_", name)
    if not ident or ident[0].isdigit():
        ident = "m_" + ident
    return ident


# ---------------------------------------------------------------------------- FMU lowering


def lower(model: SemanticModel, boundary: Boundary, options: Options | None = None) -> ir.Fmu:
    if model.errors:
        raise RobogenError(model.errors)
    return _FmuLowering(model, boundary, options or Options()).run()


class _FmuLowering:
    def __init__(self, model: SemanticModel, boundary: Boundary, options: Options):
        self.model = model
        self.b = boundary
        self.o = options
        self.sink = DiagnosticSink()
        self.fmu: ir.Fmu | None = None
        self.machine_scopes: list[tuple[str, MachineScope, Controller | None]] = []
        self.lowerings: list[_MachineLowering] = []
        # variables a controller provides, shared by its machines: (controller, name) -> storage
        self.shared_vars: dict[tuple[int, str], ir.Var] = {}

    def run(self) -> ir.Fmu:
        b = self.b
        language = b.file.language
        period = self._period(language)
        fmu = ir.Fmu(
            name=b.name,
            model_identifier=model_identifier(b.name),
            language=language,
            semantics=self.o.semantics,
            trigger=self.o.trigger,
            period=period,
            time_unit=self.o.time_unit,
            sources=tuple(sorted({f.path for f in self.model.files})),
            span=getattr(b.node, "name_span", None),
            max_steps=self.o.max_steps,
            functions_file=self.o.functions,
        )
        self.fmu = fmu
        self._collect_machines()
        lowerings = self.lowerings
        for i, (used_name, scope, ctrl) in enumerate(self.machine_scopes):
            with working_on(scope.node.span):
                ml = _MachineLowering(self, scope, ctrl, i, used_name)
                fmu.machines.append(ml.machine)
                lowerings.append(ml)
        self._ports(lowerings)
        for ml in lowerings:
            with working_on(ml.scope.node.span):
                ml.build()
        self.sink.raise_if_errors()
        return fmu

    def _period(self, language: str) -> Fraction:
        if language == "robochart":
            return Fraction(1)
        b = self.b
        period = b.module.period if b.module is not None else b.machine.period  # type: ignore[union-attr]
        if period is None:
            raise RobogenError.at(
                f"RoboSim {b.kind} '{b.name}' has no cycle period",
                getattr(b.node, "name_span", None),
                Note("declare it with 'cycleDef cycle == p'"),
            )
        return period

    def _collect_machines(self) -> None:
        b = self.b
        if b.machine is not None:
            self.machine_scopes.append((b.name, b.machine, None))
            return
        assert b.module is not None
        for _, c in b.module.controllers:
            for used, m in c.machines:
                self.machine_scopes.append((used, m, c))

    # -- ports and routes

    def _ports(self, lowerings: list["_MachineLowering"]) -> None:
        """Create the FMU's clocks in a stable order: inputs, then outputs (events, then
        operations), each in declaration order."""
        fmu = self.fmu
        assert fmu is not None
        if self.b.kind == "machine":
            ml = lowerings[0]
            used_in, used_out = _event_uses(ml.scope)
            for ev in ml.machine.events:
                sym = ml.scope.events[ev.name]
                if ml.scope.robosim or ev.name in used_in:
                    self._input_port(ev.name, ev.type, sym.span).routes.append((0, ev.index))
            for name, sym in ml.scope.events.items():
                if sym.output and (ml.scope.robosim or name in used_out):
                    self._output_port(name, "output-event", ml.event_type(name), (), sym.span)
            for name, op in ml.scope.ops.items():
                if ml.is_platform_operation(op):
                    self._output_port(name, "operation", None, ml.op_params(name), op.span)
            return
        info = self.b.module
        assert info is not None
        platform = info.platform.name if info.platform is not None else ""
        for conn in info.connections:
            if conn.source == platform:
                port = self._input_port(conn.source_event, self._platform_event_type(info, conn.source_event), conn.span)
                for r in self._routes_into_controller(conn.target, conn.target_event, lowerings, info):
                    if r not in port.routes:
                        port.routes.append(r)
        for conn in info.connections:
            if conn.target == platform:
                self._output_port(conn.target_event, "output-event", self._platform_event_type(info, conn.target_event), (), conn.span)
        for ml in lowerings:
            for name, op in ml.scope.ops.items():
                if ml.is_platform_operation(op):
                    self._output_port(name, "operation", None, ml.op_params(name), op.span)

    def _platform_event_type(self, info: Module, name: str) -> T.Type | None:
        sym = info.platform.events.get(name) if info.platform is not None else None
        return None if sym is None or sym.type is None else self._norm(sym.type)

    def _routes_into_controller(self, ctrl_name: str, event: str, lowerings, info: Module) -> list[tuple[int, int]]:
        """Machine events that receive ``event`` when it reaches controller ``ctrl_name``."""
        routes = []
        for used, c in info.controllers:
            if used != ctrl_name:
                continue
            for conn in c.connections:
                if conn.source == c.name and conn.source_event == event:
                    for ml in lowerings:
                        if ml.ctrl is c and ml.used_name == conn.target:
                            ev = ml.machine.event(conn.target_event)
                            if ev is not None:
                                routes.append((ml.machine.index, ev.index))
        return routes

    def output_routes(self, ml: "_MachineLowering", name: str, kind: str, span: Span | None) -> tuple[tuple, ...]:
        """Where a machine's output event or platform operation call goes."""
        if kind == "operation" or self.b.kind == "machine":
            t = None if kind == "operation" else ml.event_type(name)
            return (("port", self._output_port(name, kind, t, ml.op_params(name), span).index),)
        info = self.b.module
        assert info is not None
        routes: list[tuple] = []
        ctrl = ml.ctrl
        if ctrl is None:
            return ()
        ctrl_used = next((u for u, c in info.controllers if c is ctrl), ctrl.name)
        platform = info.platform.name if info.platform is not None else ""
        for conn in ctrl.connections:
            if conn.source != ml.used_name or conn.source_event != name:
                continue
            if conn.target == ctrl.name:  # machine -> its controller -> the module's connections
                for mconn in info.connections:
                    if mconn.source == ctrl_used and mconn.source_event == conn.target_event:
                        if mconn.target == platform:
                            port = self._output_port(mconn.target_event, "output-event", ml.event_type(name), (), span)
                            routes.append(("port", port.index))
                        else:
                            routes += [("machine", mi, me) for mi, me in self._routes_into_controller(mconn.target, mconn.target_event, self.lowerings, info)]
            else:  # machine -> machine of the same controller
                for other in self.lowerings:
                    if other.ctrl is ctrl and other.used_name == conn.target:
                        ev = other.machine.event(conn.target_event)
                        if ev is not None:
                            routes.append(("machine", other.machine.index, ev.index))
        return tuple(routes)

    def _input_port(self, name: str, t: T.Type | None, span: Span | None) -> ir.Port:
        fmu = self.fmu
        assert fmu is not None
        for p in fmu.inputs:
            if p.name == name:
                return p
        fields = tuple(_flatten(name + ".value" if not isinstance(t, T.RecordT) else name, t, (), span)) if t is not None else ()
        port = ir.Port(name, "input-event", t, fields, span=span, index=len(fmu.inputs))
        fmu.inputs.append(port)
        return port

    def _output_port(self, name: str, kind: str, t: T.Type | None, params, span: Span | None) -> ir.Port:
        fmu = self.fmu
        assert fmu is not None
        for p in fmu.outputs:
            if p.name == name:
                if p.kind != kind:
                    raise RobogenError.at(
                        f"the FMU would have two output clocks named '{name}': an output event and a platform operation; "
                        "rename one of them in the model", span, Note(f"the other '{name}' is declared here", p.span))
                return p
        if kind == "operation":
            fields: list[ir.Field_] = []
            for pname, ptype in params:
                fields += _flatten(f"{name}.{pname}", ptype, (pname,), span)
            port = ir.Port(name, kind, None, tuple(fields), tuple(params), span=span, index=len(fmu.outputs))
        else:
            fields = _flatten(name + ".value" if not isinstance(t, T.RecordT) else name, t, (), span) if t is not None else []
            port = ir.Port(name, kind, t, tuple(fields), span=span, index=len(fmu.outputs))
        fmu.outputs.append(port)
        return port

    def _norm(self, t: T.Type) -> T.Type:
        return normalise(t, self.o.given)


def _event_uses(scope: MachineScope) -> tuple[set[str], set[str]]:
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


def normalise(t: T.Type, given: str = "int") -> T.Type:
    """Replace given types by their concrete scalar type, recursively."""
    if isinstance(t, T.Given):
        return T.PRIMITIVES[given]
    if isinstance(t, T.RecordT):
        return T.RecordT(t.qname, tuple((n, normalise(ft, given)) for n, ft in t.fields))
    if isinstance(t, T.VectorT):
        return T.VectorT(normalise(t.element, given), t.size)
    if isinstance(t, T.MatrixT):
        return T.MatrixT(normalise(t.element, given), t.rows, t.columns)
    return t


SCALARS = (T.NAT, T.INT, T.REAL, T.BOOLEAN)


def is_scalar(t: T.Type) -> bool:
    return t in SCALARS or isinstance(t, T.EnumT)


def check_codegen_type(t: T.Type, span: Span | None, what: str) -> None:
    if is_scalar(t):
        return
    if isinstance(t, T.RecordT):
        for n, ft in t.fields:
            check_codegen_type(ft, span, f"field '{n}' of {what}")
        return
    if isinstance(t, T.VectorT) and is_scalar(t.element):
        if t.size is None:
            raise not_supported(f"{what}: a vector whose size is not an integer literal", span)
        return
    if isinstance(t, T.MatrixT) and is_scalar(t.element):
        if t.rows is None or t.columns is None:
            raise not_supported(f"{what}: a matrix whose size is not given by integer literals", span)
        return
    raise not_supported(f"{what} of type {t.show()}", span)


def _flatten(prefix: str, t: T.Type | None, path: tuple[str, ...], span: Span | None) -> list[ir.Field_]:
    assert t is not None
    check_codegen_type(t, span, f"'{prefix}'")
    if isinstance(t, T.RecordT):
        out: list[ir.Field_] = []
        for n, ft in t.fields:
            out += _flatten(f"{prefix}.{n}", ft, path + (n,), span)
        return out
    if isinstance(t, T.MatrixT):
        raise not_supported(f"'{prefix}': a matrix as an FMU port", span)
    return [ir.Field_(prefix, t, path)]


# ---------------------------------------------------------------------------- machines


@dataclass
class _Graph:
    """One region tree being lowered: the machine body, or a software operation inlined at one
    call site. Names resolve first in ``env`` (the call site's parameters and locals)."""

    scope: MachineScope
    prefix: tuple[str, ...]  # node path prefix (empty for the machine)
    env: dict[str, ir.Var]
    clocks: dict[str, int]
    exit_block: int | None  # operations: where control goes when the final node is reached
    regions: dict[int, Region] = field(default_factory=dict)  # id(owner node) -> region
    node_ids: dict[int, int] = field(default_factory=dict)  # id(ast node) -> ir node id
    parent: dict[int, ast.Node] = field(default_factory=dict)  # id(ast node) -> enclosing state (or None)


class _MachineLowering:
    def __init__(self, fl: _FmuLowering, scope: MachineScope, ctrl: Controller | None, index: int, used_name: str):
        self.fl = fl
        self.scope = scope
        self.ctrl = ctrl
        self.used_name = used_name
        self.robosim = scope.robosim
        self.model = fl.model
        self.machine = ir.Machine(scope.name, scope.qname, scope.node.name_span, index=index)
        self.vars: dict[str, ir.Var] = {}
        self.evals: dict[tuple[int, int], int] = {}
        self.completions: dict[tuple[int, int], int] = {}
        self.inline_stack: list[str] = []
        self.site = 0
        self.node_now = 0  # the machine's state output where the statement being lowered runs
        self.deadline_flags: dict[tuple[int, int], ir.Var] = {}  # (graph, transition) -> missed flag
        # storage: machine variables and constants, events, clocks
        for name, v in scope.vars.items():
            self._declare_var(v, name, name)
        for name, e in scope.events.items():
            if e.input:
                t = self._norm(e.type) if e.type is not None else None
                if t is not None:
                    check_codegen_type(t, e.span, f"event '{name}'")
                self.machine.events.append(ir.Event(name, t, len(self.machine.events), e.span))

    # -- helpers

    def _norm(self, t: T.Type) -> T.Type:
        return normalise(t, self.fl.o.given)

    def _declare_var(self, v: VarSym, name: str, display: str) -> ir.Var:
        t = self._norm(v.type)
        check_codegen_type(t, v.span, f"variable '{display}'")
        key = (id(self.ctrl) if self.ctrl is not None else 0, name)
        if v.shared and v.kind == "var" and key in self.fl.shared_vars:
            var = self.fl.shared_vars[key]  # another machine of the controller holds it
            if var.type != t:
                raise not_supported(f"shared variable '{name}' with two types ({var.type.show()}, {t.show()})", v.span)
            self.vars[name] = var
            return var
        var = ir.Var(_cname(name), display, t, "const" if v.kind == "const" else ("param" if v.kind == "param" else "var"),
                     None, v.span, v.shared, len(self.machine.vars), owner=self.machine.index)
        self.machine.vars.append(var)
        self.vars[name] = var
        if v.shared and v.kind == "var":
            self.fl.shared_vars[key] = var
        if v.kind == "const":
            self._constant(var, v)
        return var

    def _constant(self, var: ir.Var, v: VarSym) -> None:
        fmu = self.fl.fmu
        assert fmu is not None
        fmi_name = f"{self.scope.name}.{v.name}"
        settings = self.fl.o.settings
        text = settings.get(fmi_name, settings.get(v.name))
        value: object = None
        if text is not None:
            value = _parse_setting(text, var.type, v.span, fmi_name)
        elif v.init is not None:
            value = _constant_value(v.init, var.type, self.model, {p.var.display: p.value for p in fmu.params if p.machine == self.machine.index})
            if value is None:
                self.fl.sink.error(f"the value of constant '{v.name}' must be computable from literals and other constants", v.init.span)
        else:
            self.fl.sink.error(
                f"constant '{v.name}' has no value: give one in the model or with --set {v.name}=VALUE",
                v.span,
                Note("RoboChart constants without a value are model parameters; an FMU parameter needs a start value"),
            )
        fmu.params.append(ir.Param(fmi_name, var, self.machine.index, value))

    def is_platform_operation(self, op: OpSym) -> bool:
        """RoboSim: an operation of the output context. RoboChart: a required operation that no
        software operation definition implements."""
        if self.robosim:
            return op.platform
        return self._software_operation(op.name) is None

    def event_type(self, name: str) -> T.Type | None:
        sym = self.scope.events.get(name)
        return self._norm(sym.type) if sym is not None and sym.type is not None else None

    def op_params(self, name: str) -> tuple[tuple[str, T.Type], ...]:
        sym = self.scope.ops.get(name)
        if sym is None:
            return ()
        return tuple((p, self._norm(t)) for p, t in sym.params)

    def block(self, label: str, span: Span | None) -> ir.Block:
        b = ir.Block(len(self.machine.blocks), label, span)
        self.machine.blocks.append(b)
        return b

    # -- structure

    def build(self) -> None:
        graph = _Graph(self.scope, (), {}, {}, None)
        for name in self.scope.clocks:
            graph.clocks[name] = self._clock(name)
        self._index_regions(graph, self.scope.region, None)
        for name, v in self.scope.vars.items():
            var = self.vars[name]
            if v.kind == "var" and v.init is not None:
                var.init = self._conv(self.expr(v.init, graph), var.type, v.init.span)
        root = self.scope.region
        assert root is not None
        start = self.block(f"start {self.scope.name}", self.scope.node.name_span)
        start.step = True  # the initial transition is the first transition segment
        self.machine.start = start.id
        initials = root.initials()
        if not initials:
            raise RobogenError.at(f"state machine '{self.scope.name}' has no initial node", self.scope.node.name_span)
        self.machine.initial_node = graph.node_ids[id(initials[0])]
        self.node_now = self.machine.initial_node
        self._initial(graph, root, start)

    def _clock(self, name: str) -> int:
        self.machine.clocks.append(name)
        return len(self.machine.clocks) - 1

    def _index_regions(self, graph: _Graph, region: Region | None, parent_state: ast.Node | None) -> None:
        assert region is not None
        graph.regions[id(region.owner)] = region
        for name, node in region.nodes.items():
            nid = len(self.machine.nodes)
            kind = {ast.State: "state", ast.Junction: "junction", ast.Final: "final", ast.Initial: "initial", ast.Probabilistic: "probabilistic"}[type(node)]
            if kind == "probabilistic":
                raise not_supported("a probabilistic junction", node.name_span)
            self.machine.nodes.append(ir.Node(nid, graph.prefix + region.path + (name,), kind, node.name_span))
            graph.node_ids[id(node)] = nid
            graph.parent[id(node)] = parent_state  # type: ignore[assignment]
            child = region.children.get(name)
            if child is not None:
                self._index_regions(graph, child, node)

    def _region_of(self, graph: _Graph, node: ast.Node) -> Region:
        parent = graph.parent[id(node)]
        owner = parent if parent is not None else graph.scope.node
        return graph.regions[id(owner)]

    def _initial(self, graph: _Graph, region: Region, cur: ir.Block) -> tuple[ir.Block, ast.Node]:
        """Take the transition of ``region``'s initial node from block ``cur``: returns the open
        block and the node where control arrives (a leaf)."""
        cur, leaf = self._initial_inner(graph, region, cur)
        if region.owner is graph.scope.node and cur.term is None:
            cur.term = ir.Goto(self._eval(graph, leaf))
        return cur, leaf

    def _enter(self, graph: _Graph, node: ast.NodeDecl, cur: ir.Block) -> tuple[ir.Block, ast.Node]:
        """Entry into ``node``: its entry action and, for a composite state, its initial
        transition, recursively. Returns the open block and the leaf node reached."""
        nid = graph.node_ids[id(node)]
        cur.stmts.append(ir.Enter(node.name_span, nid))
        self.node_now = nid
        for t in self._outgoing(graph, node):
            if t.deadline is not None:  # a new activation of the source: its deadline runs again
                flag = self._deadline_flag(graph, t)
                cur.stmts.append(ir.Assign(t.deadline.span, ir.Ref(T.BOOLEAN, flag), ir.Lit(T.BOOLEAN, False)))
        if isinstance(node, ast.State):
            entry = _action(node, "entry")
            if entry is not None:
                cur = self.stmts(entry, cur, graph)
            if not self.robosim:
                during = _action(node, "during")
                if during is not None:
                    cur = self.stmts(during, cur, graph)
            region = graph.regions.get(id(node))
            if region is not None and region.initials():
                return self._initial_inner(graph, region, cur)
        return cur, node

    def _initial_inner(self, graph: _Graph, region: Region, cur: ir.Block) -> tuple[ir.Block, ast.Node]:
        """The initial transition of ``region`` and entry into its target, down to a leaf."""
        init = region.initials()[0]
        ts = [t for t in region.transitions if t.source == init.name]
        if len(ts) != 1:
            raise RobogenError.at(f"initial node '{init.name}' must have exactly one transition", init.name_span)
        t = ts[0]
        cur.stmts.append(ir.Trace(t.span, f"{t.name}: {init.name} -> {t.target}"))
        if t.action is not None:
            cur = self.stmts(t.action, cur, graph)
        return self._enter(graph, region.nodes[t.target], cur)

    def _chain(self, graph: _Graph, node: ast.Node) -> list[ast.Node]:
        """The enclosing states of ``node``, outermost first, then the node itself."""
        chain = [node]
        p = graph.parent.get(id(node))
        while p is not None:
            chain.append(p)
            p = graph.parent.get(id(p))
        return list(reversed(chain))

    def _eval(self, graph: _Graph, leaf: ast.Node) -> int:
        key = (id(graph), graph.node_ids[id(leaf)])
        if key in self.evals:
            return self.evals[key]
        name = ".".join(self.machine.nodes[key[1]].path)
        b = self.block(f"EVAL {name}", getattr(leaf, "span", None))
        self.evals[key] = b.id
        self.node_now = key[1]
        cur = b
        cases: list[ir.Case] = []
        if isinstance(leaf, (ast.State, ast.Final)):
            chain = self._chain(graph, leaf)
            if self.robosim:
                for s in chain:
                    if isinstance(s, ast.State):
                        during = _action(s, "during")
                        if during is not None:
                            cur = self.stmts(during, cur, graph)
            sources = chain
        else:
            sources = [leaf]
        for src in sources:
            for t in self._outgoing(graph, src):
                if t.deadline is not None and not self.robosim:
                    cur.stmts.append(self._deadline_check(graph, t, src))
        for src in sources:
            # declaration order, except that 'condition else' is the default: tried last
            for t in sorted(self._outgoing(graph, src), key=lambda t: t.condition_else):
                cases.append(self._case(graph, t, src, leaf))
        is_top_final = isinstance(leaf, ast.Final) and graph.parent.get(id(leaf)) is None
        if is_top_final and graph.exit_block is not None:
            cur.term = ir.Goto(graph.exit_block)  # an operation ends at its final node
            return b.id
        if is_top_final:
            default: ir.Terminator = ir.Suspend(b.id)  # the machine has terminated
        elif self.robosim or isinstance(leaf, ast.Junction):
            where = f"{_at(leaf)}"
            kind = "junction" if isinstance(leaf, ast.Junction) else "state"
            default = ir.Fail(f"deadlock in {kind} '{name}' ({where}): no transition is enabled" + (" and no exec" if self.robosim else ""))
        else:
            default = ir.Suspend(b.id)  # RoboChart: wait for an event or for time to pass
        cur.term = ir.Branch(tuple(cases), default)
        return b.id

    def _case(self, graph: _Graph, t: ast.Transition, src: ast.Node, leaf: ast.Node) -> ir.Case:
        guard: ir.Expr | None = None
        event_index = None
        if t.trigger is not None:
            ev = self.machine.event(t.trigger.event)
            if ev is None:
                raise not_supported(f"a trigger on '{t.trigger.event}', which this boundary never receives", t.trigger.span)
            event_index = ev.index
            if t.trigger.kind == "?":
                var = self.model.bound_var(t.trigger)
                guard = ir.BindIn(T.BOOLEAN, ev.index, self._var_ref(graph, var, t.trigger.var_span))
            else:
                guard = ir.Occurred(T.BOOLEAN, ev.index)
        if t.condition is not None:
            cond = self.expr(t.condition, graph)
            guard = cond if guard is None else ir.Bin(T.BOOLEAN, "and", guard, cond)
        if guard is None:
            guard = ir.Lit(T.BOOLEAN, True)
        label = f"{t.name}: {src.name} -> {t.target}"  # type: ignore[attr-defined]
        if t.exec:
            # decide now, act next cycle: the completion is the first segment of the next cycle
            decide = self.block(f"{t.name}: exec decided", t.span)
            decide.stmts.append(ir.Trace(t.span, f"{t.name}: exec"))
            decide.term = ir.Suspend(self._completion(graph, t, src, leaf, None))
            return ir.Case(guard, decide.id, label + " (exec)", t.name_span)
        return ir.Case(guard, self._completion(graph, t, src, leaf, event_index), label, t.name_span)

    def _outgoing(self, graph: _Graph, src: ast.Node) -> list[ast.Transition]:
        """The transitions leaving ``src``, in declaration order."""
        if id(src) not in graph.parent:
            return []
        region = self._region_of(graph, src)
        return [t for t in region.transitions if t.source == src.name]  # type: ignore[attr-defined]

    # -- deadlines (RoboChart; RoboSim rejects them in the checker)

    def _deadline_flag(self, graph: _Graph, t: ast.Transition) -> ir.Var:
        """The flag that says the deadline of ``t`` was already reported for this activation of
        its source (one per transition and inlined operation)."""
        key = (id(graph), id(t))
        if key not in self.deadline_flags:
            name = "_".join(graph.prefix) + ("_" if graph.prefix else "") + f"{t.name}_deadline"
            var = ir.Var(_cname(name), f"{'.'.join(graph.prefix + (t.name,))}.deadline", T.BOOLEAN, "local", None,
                         t.deadline.span if t.deadline is not None else None, False, len(self.machine.vars))
            self.machine.vars.append(var)
            self.deadline_flags[key] = var
        return self.deadline_flags[key]

    def _deadline_check(self, graph: _Graph, t: ast.Transition, src: ast.Node) -> ir.Stmt:
        """In the source's evaluation: the trigger of ``t`` is late if the source has been active
        longer than the deadline; reported once per activation."""
        assert t.deadline is not None
        flag = self._deadline_flag(graph, t)
        elapsed = ir.SinceEntry(self._since_type(), graph.node_ids[id(src)])
        late = self._later(elapsed, self.expr(t.deadline, graph), t.deadline.span)
        guard = ir.Bin(T.BOOLEAN, "and", ir.Un(T.BOOLEAN, "not", ir.Ref(T.BOOLEAN, flag)), late)
        text = (f"{t.name}: deadline missed: trigger '{t.trigger.event if t.trigger else ''}' not within "
                f"{self.model.text(t.deadline)} time unit(s) of entering {src.name} ({_at(t)})")  # type: ignore[attr-defined]
        return ir.If(t.deadline.span, guard, (ir.Assign(t.deadline.span, ir.Ref(T.BOOLEAN, flag), ir.Lit(T.BOOLEAN, True)),
                                               ir.DeadlineMiss(t.deadline.span, text)), ())

    def _later(self, elapsed: ir.Expr, bound: ir.Expr, span: Span | None) -> ir.Expr:
        """elapsed > bound, compared as reals if the bound is real, else as integers."""
        t = T.REAL if bound.type == T.REAL else T.INT
        return ir.Bin(T.BOOLEAN, "gt", self._conv(elapsed, t, span), self._conv(bound, t, span))

    def _completion(self, graph: _Graph, t: ast.Transition, src: ast.Node, leaf: ast.Node, consume: int | None) -> int:
        key = (id(t), graph.node_ids[id(leaf)])
        if key in self.completions:
            return self.completions[key]
        b = self.block(f"{t.name}: {src.name} -> {t.target}", t.span)  # type: ignore[attr-defined]
        b.step = True
        self.completions[key] = b.id
        self.node_now = graph.node_ids[id(leaf)]
        cur = b
        if consume is not None:
            cur.stmts.append(ir.Consume(t.span, consume))
        cur.stmts.append(ir.Trace(t.span, f"{t.name}: {src.name} -> {t.target}"))  # type: ignore[attr-defined]
        # exit the active states from the leaf up to the source, innermost first
        for s in reversed(self._chain(graph, leaf)[self._chain(graph, leaf).index(src):]):
            if isinstance(s, ast.State):
                ex = _action(s, "exit")
                if ex is not None:
                    cur = self.stmts(ex, cur, graph)
        for r in t.resets:
            cur.stmts.append(ir.ResetClock(r.span, graph.clocks[r.clock]))
        if t.action is not None:
            cur = self.stmts(t.action, cur, graph)
        region = self._region_of(graph, src)
        target = region.nodes[t.target]
        cur, arrived = self._enter(graph, target, cur)
        if cur.term is None:
            cur.term = ir.Goto(self._eval(graph, arrived))
        return b.id

    # -- statements

    def stmts(self, s: ast.Stmt, cur: ir.Block, graph: _Graph) -> ir.Block:
        """Lower statement ``s`` at the end of block ``cur``; returns the block where control
        continues afterwards (a new one when ``s`` suspends or calls an operation)."""
        with working_on(s.span):
            return self._stmt(s, cur, graph)

    def _stmt(self, s: ast.Stmt, cur: ir.Block, graph: _Graph) -> ir.Block:
        if isinstance(s, ast.Seq):
            for x in s.stmts:
                cur = self.stmts(x, cur, graph)
            return cur
        if isinstance(s, ast.Skip):
            return cur
        if isinstance(s, ast.Exec):
            nxt = self.block("after exec", s.span)
            cur.term = ir.Suspend(nxt.id)
            return nxt
        if isinstance(s, ast.Wait):
            cur.stmts.append(ir.StartWait(s.span, self._conv(self.expr(s.duration, graph), T.INT, s.duration.span)))
            wait = self.block("wait", s.span)
            nxt = self.block("after wait", s.span)
            cur.term = ir.Goto(wait.id)
            done = ir.Bin(T.BOOLEAN, "le", ir.WaitLeft(T.INT), ir.Lit(T.INT, 0))
            wait.term = ir.Branch((ir.Case(done, nxt.id, "wait over", s.span),), ir.Suspend(wait.id))
            return nxt
        if isinstance(s, ast.ClockReset):
            cur.stmts.append(ir.ResetClock(s.span, graph.clocks[s.clock]))
            return cur
        if isinstance(s, ast.IfStmt):
            cond = self.expr(s.cond, graph)
            if not _has_control(s.then) and (s.otherwise is None or not _has_control(s.otherwise)):
                then = self._straight(s.then, graph)
                otherwise = self._straight(s.otherwise, graph) if s.otherwise is not None else []
                cur.stmts.append(ir.If(s.span, cond, tuple(then), tuple(otherwise)))
                return cur
            then_b = self.block("then", s.then.span)
            join = self.block("end if", s.span)
            end_then = self.stmts(s.then, then_b, graph)
            end_then.term = ir.Goto(join.id)
            if s.otherwise is not None:
                else_b = self.block("else", s.otherwise.span)
                end_else = self.stmts(s.otherwise, else_b, graph)
                end_else.term = ir.Goto(join.id)
                default: ir.Terminator = ir.Goto(else_b.id)
            else:
                default = ir.Goto(join.id)
            cur.term = ir.Branch((ir.Case(cond, then_b.id, "if", s.span),), default)
            return join
        if isinstance(s, ast.Assign):
            target = self.lvalue(s.target, graph)
            cur.stmts.append(ir.Assign(s.span, target, self._conv(self.expr(s.value, graph), target.type, s.value.span)))
            return cur
        if isinstance(s, ast.DollarAssign):
            var = self.model.symbol(s)
            target = self._var_ref(graph, var, s.var_span)
            cur.stmts.append(ir.Assign(s.span, target, self._conv(self.expr(s.value, graph), target.type, s.value.span)))
            return cur
        if isinstance(s, ast.CallStmt):
            op: OpSym = self.model.symbol(s.call.func)
            return self._call(op, s.call.args, cur, graph, s.span)
        if isinstance(s, ast.DollarCall):
            op = self.model.symbol(s)
            return self._call(op, s.args, cur, graph, s.span)
        if isinstance(s, ast.DollarOutput):
            args = () if s.value is None else (self._payload(s.event, s.value, graph),)
            if s.kind == ".":
                raise not_supported("a synchronisation output $e.v (use $e!v)", s.span)
            cur.stmts.append(ir.Emit(s.span, s.event, args, self.fl.output_routes(self, s.event, "output-event", s.span)))
            return cur
        if isinstance(s, ast.Communicate):
            c = s.comm
            if c.kind in ("", "!"):
                args = () if c.value is None else (self._payload(c.event, c.value, graph),)
                cur.stmts.append(ir.Emit(s.span, c.event, args, self.fl.output_routes(self, c.event, "output-event", s.span)))
                return cur
            if c.kind == "?":
                # an input in an action waits for the event, then binds its value
                ev = self.machine.event(c.event)
                if ev is None:
                    raise not_supported(f"an input of '{c.event}', which this boundary never receives", s.span)
                var = self.model.bound_var(c)
                wait = self.block(f"wait for {c.event}", s.span)
                nxt = self.block(f"after {c.event}?{c.var}", s.span)
                cur.term = ir.Goto(wait.id)
                nxt.stmts.append(ir.Consume(s.span, ev.index))
                guard = ir.BindIn(T.BOOLEAN, ev.index, self._var_ref(graph, var, c.var_span))
                wait.term = ir.Branch((ir.Case(guard, nxt.id, f"{c.event}?{c.var}", s.span),), ir.Suspend(wait.id))
                return nxt
            raise not_supported("a synchronisation communication e.v in an action", s.span)
        if isinstance(s, ast.StmtDeadline):
            if not _has_control(s.stmt):  # takes no time: cannot miss its deadline
                return self.stmts(s.stmt, cur, graph)
            self.site += 1
            start = ir.Var(f"deadline_{self.site}", f"deadline#{self.site}.start", T.NAT, "local", None, s.span, False,
                           len(self.machine.vars))
            self.machine.vars.append(start)
            cur.stmts.append(ir.Assign(s.span, ir.Ref(T.NAT, start), ir.Now(T.NAT)))
            cur = self.stmts(s.stmt, cur, graph)
            elapsed = ir.Bin(T.NAT, "sub", ir.Now(T.NAT), ir.Ref(T.NAT, start))
            late = self._later(elapsed, self.expr(s.bound, graph), s.bound.span)
            text = f"deadline missed: the statement at {_at(s)} took longer than {self.model.text(s.bound)} time unit(s)"
            cur.stmts.append(ir.If(s.span, late, (ir.DeadlineMiss(s.span, text),), ()))
            return cur
        raise not_supported(f"the statement '{type(s).__name__}'", s.span)  # pragma: no cover

    def _straight(self, s: ast.Stmt, graph: _Graph) -> list[ir.Stmt]:
        """The statements of ``s``, which has no control flow of its own (no exec, wait, input or
        call: see _has_control), lowered into a detached block that never joins the machine."""
        detached = ir.Block(-1, "detached", s.span)
        end = self.stmts(s, detached, graph)
        assert end is detached and detached.term is None, "a statement with control flow in an if without blocks"
        return detached.stmts

    def _payload(self, event: str, value: ast.Expr, graph: _Graph) -> ir.Expr:
        t = self.event_type(event)
        e = self.expr(value, graph)
        return self._conv(e, t, value.span) if t is not None else e

    def _call(self, op: OpSym, args, cur: ir.Block, graph: _Graph, span: Span | None) -> ir.Block:
        values = tuple(self._conv(self.expr(a, graph), self._norm(pt), a.span) for a, (_, pt) in zip(args, op.params))
        definition = self._software_operation(op.name, graph.scope) if not op.platform else None
        if definition is None:
            cur.stmts.append(ir.Emit(span, op.name, values, self.fl.output_routes(self, op.name, "operation", span)))
            return cur
        return self._inline(definition, values, cur, graph, span)

    def _software_operation(self, name: str, caller: MachineScope | None = None) -> MachineScope | None:
        """The definition of a software operation the machine (or the operation ``caller``)
        calls, if it has one (otherwise the operation belongs to the robotic platform): the one
        its controller references (opref), else the one visible from the calling file (its
        package, its imports, files without a package), never an operation of the same name
        elsewhere in the workspace."""
        module = self.fl.b.module
        if module is not None and module.platform is not None and name in module.platform.operations:
            return None
        if self.ctrl is not None:
            for used, scope in self.ctrl.operations:
                if scope.name == name or used == name:
                    return scope
        definition = (caller or self.scope).definitions.get(name)
        return self.model.scope_of(definition) if definition is not None else None

    def _inline(self, op: MachineScope, values, cur: ir.Block, graph: _Graph, span: Span | None) -> ir.Block:
        if op.name in self.inline_stack:
            raise not_supported(f"the recursive call of operation '{op.name}'", span)
        self.site += 1
        site = self.site
        env: dict[str, ir.Var] = {}
        # parameters and the operation's own variables: one set per call site
        for name, v in op.vars.items():
            if v.shared:
                continue
            t = self._norm(v.type)
            check_codegen_type(t, v.span, f"variable '{name}' of operation '{op.name}'")
            var = ir.Var(_cname(f"{op.name}_{site}_{name}"), f"{op.name}#{site}.{name}", t, "local", None, v.span, False, len(self.machine.vars))
            self.machine.vars.append(var)
            env[name] = var
            if v.kind in ("var", "const") and v.init is not None:
                var.init = None  # initialised at each call below
        after = self.block(f"after {op.name}()", span)
        sub = _Graph(op, (f"{op.name}#{site}",), env, {}, after.id)
        for name, clock in op.clocks.items():
            if clock.from_interface and name in graph.clocks:
                sub.clocks[name] = graph.clocks[name]  # a clock of the caller, required by the operation
            else:
                sub.clocks[name] = self._clock(f"{op.name}#{site}.{name}")
        self._index_regions(sub, op.region, None)
        for (pname, _), value in zip([(p.name, p) for p in op.node.params], values):  # type: ignore[attr-defined]
            var = env[pname]
            cur.stmts.append(ir.Assign(span, ir.Ref(var.type, var), self._conv(value, var.type, span)))
        for name, v in op.vars.items():
            if v.kind in ("var", "const") and not v.shared and v.init is not None:
                var = env[name]
                cur.stmts.append(ir.Assign(v.span, ir.Ref(var.type, var), self._conv(self.expr(v.init, sub), var.type, v.init.span)))
        caller_node = self.node_now
        self.inline_stack.append(op.name)
        try:
            start = self.block(f"call {op.name}()", span)
            cur.term = ir.Goto(start.id)
            end, leaf = self._initial_op(sub, start)
        finally:
            self.inline_stack.pop()
        # back in the caller: its node is the machine's state again (no new entry)
        after.stmts.insert(0, ir.Enter(span, caller_node, resume=True))
        self.node_now = caller_node
        return after

    def _initial_op(self, graph: _Graph, start: ir.Block) -> tuple[ir.Block, ast.Node]:
        region = graph.scope.region
        assert region is not None
        cur, leaf = self._initial_inner(graph, region, start)
        if cur.term is None:
            cur.term = ir.Goto(self._eval(graph, leaf))
        return cur, leaf

    # -- expressions

    def _var_ref(self, graph: _Graph, sym, span: Span | None) -> ir.Expr:
        if not isinstance(sym, VarSym):
            raise not_supported("this variable reference", span)
        var = graph.env.get(sym.name) or self.vars.get(sym.name)
        if var is None and sym.shared and sym.kind == "var":
            # a variable the controller provides, used by an operation the machine calls
            var = self._declare_var(sym, sym.name, sym.name)
        if var is None:
            raise not_supported(f"variable '{sym.name}' here", span)
        return ir.Ref(var.type, var)

    def lvalue(self, e: ast.Expr, graph: _Graph) -> ir.Expr:
        if isinstance(e, ast.Name):
            return self._var_ref(graph, self.model.symbol(e), e.span)
        if isinstance(e, ast.Field):
            base = self.lvalue(e.obj, graph)
            assert isinstance(base.type, T.RecordT)
            return ir.FieldOf(self._norm(base.type.field(e.field)), base, e.field)  # type: ignore[arg-type]
        if isinstance(e, ast.Index):
            base = self.lvalue(e.obj, graph)
            return self._index(base, e, graph)
        raise not_supported("this assignment target", e.span)

    def _index(self, base: ir.Expr, e: ast.Index, graph: _Graph) -> ir.Expr:
        if isinstance(base.type, T.VectorT) and len(e.indices) == 1:
            return ir.IndexOf(base.type.element, base, (self._conv(self.expr(e.indices[0], graph), T.INT, e.indices[0].span),))
        if isinstance(base.type, T.MatrixT) and len(e.indices) == 2:
            return ir.IndexOf(base.type.element, base, tuple(self._conv(self.expr(i, graph), T.INT, i.span) for i in e.indices))
        raise not_supported(f"indexing a value of type {base.type.show()}", e.span)

    def _conv(self, e: ir.Expr, t: T.Type | None, span: Span | None) -> ir.Expr:
        if t is None or e.type == t:
            return e
        if e.type in T.NUMERIC and t in T.NUMERIC:
            if isinstance(e, ir.Lit) and not isinstance(e.value, bool):
                value = e.value
                if t == T.REAL:
                    return ir.Lit(T.REAL, Fraction(value))  # type: ignore[arg-type]
                if isinstance(value, int) or (isinstance(value, Fraction) and value.denominator == 1):
                    return ir.Lit(t, int(value))  # type: ignore[arg-type]
            return ir.Conv(t, e)
        if isinstance(t, T.VectorT) and isinstance(e, ir.VectorLit):
            return ir.VectorLit(t, tuple(self._conv(x, t.element, span) for x in e.items))
        if isinstance(t, T.MatrixT) and isinstance(e, ir.VectorLit):
            return ir.VectorLit(t, tuple(self._conv(x, t.element, span) for x in e.items))
        if isinstance(t, T.RecordT) and isinstance(e, ir.RecordLit):
            return ir.RecordLit(t, tuple((n, self._conv(v, t.field(n), span)) for n, v in e.values))
        return e

    def expr(self, e: ast.Expr, graph: _Graph) -> ir.Expr:
        with working_on(e.span):
            return self._expr(e, graph)

    def _type(self, e: ast.Expr) -> T.Type:
        return self._norm(self.model.type_of(e))

    def _expr(self, e: ast.Expr, graph: _Graph) -> ir.Expr:
        if isinstance(e, ast.IntLit):
            return ir.Lit(T.NAT, e.value)
        if isinstance(e, ast.RealLit):
            return ir.Lit(T.REAL, Fraction(e.text))
        if isinstance(e, ast.BoolLit):
            return ir.Lit(T.BOOLEAN, e.value)
        if isinstance(e, ast.Name):
            sym = self.model.symbol(e)
            if isinstance(sym, EnumLitSym):
                enum = self._norm(sym.enum)
                assert isinstance(enum, T.EnumT)
                return ir.Lit(enum, enum.literals.index(sym.literal))
            return self._var_ref(graph, sym, e.span)
        if isinstance(e, ast.Keyword):
            if e.word == "cycle":
                return ir.Lit(T.REAL, self.fl.fmu.period)  # type: ignore[union-attr]
            raise not_supported(f"'{e.word}'", e.span)
        if isinstance(e, ast.Unary):
            operand = self.expr(e.operand, graph)
            if e.op == "not":
                return ir.Un(T.BOOLEAN, "not", operand)
            t = self._type(e)
            return ir.Un(t, "neg", self._conv(operand, t, e.span))
        if isinstance(e, ast.Binary):
            return self._binary(e, graph)
        if isinstance(e, ast.Field):
            base = self.expr(e.obj, graph)
            if not isinstance(base.type, T.RecordT):
                raise not_supported(f"field selection on {base.type.show()}", e.span)
            return ir.FieldOf(self._norm(base.type.field(e.field)), base, e.field)  # type: ignore[arg-type]
        if isinstance(e, ast.Index):
            base = self.expr(e.obj, graph)
            return self._index(base, e, graph)
        if isinstance(e, ast.IfExpr):
            t = self._type(e)
            return ir.Cond(t, self.expr(e.cond, graph), self._conv(self.expr(e.then, graph), t, e.then.span), self._conv(self.expr(e.otherwise, graph), t, e.otherwise.span))
        if isinstance(e, ast.Call):
            sym = self.model.symbol(e.func)
            if isinstance(sym, EnumLitSym):
                raise not_supported("an enumeration literal with arguments", e.span)
            if isinstance(sym, FuncSym) and sym.builtin is not None and sym.name in ("min", "max", "abs"):
                t = self._type(e)
                if t not in T.NUMERIC or any(self._type(a) not in T.NUMERIC for a in e.args):
                    raise not_supported(f"'{sym.name}' of a set or sequence", e.span)
                return ir.CallB(t, sym.name, tuple(self._conv(self.expr(a, graph), t, a.span) for a in e.args))
            if isinstance(sym, FuncSym) and sym.builtin is None and sym.decl is not None:
                return self._user_call(sym, e, graph)
            name = sym.name if isinstance(sym, FuncSym) else "?"
            raise not_supported(f"a call of function '{name}' (robogen has no implementation of it)", e.span)
        if isinstance(e, ast.Cast):
            t = self._norm(self.model.type_of(e.type))
            inner = self.expr(e.expr, graph)
            if e.op == "as" and t in T.NUMERIC and inner.type in T.NUMERIC:
                return ir.Conv(t, inner)
            raise not_supported(f"'{e.op}' here", e.span)
        if isinstance(e, ast.RecordLit):
            t = self._type(e)
            assert isinstance(t, T.RecordT)
            given = {fv.name: fv.value for fv in e.fields}
            return ir.RecordLit(t, tuple((n, self._conv(self.expr(given[n], graph), ft, given[n].span)) for n, ft in t.fields))
        if isinstance(e, ast.VectorLit):
            t = self._type(e)
            items = tuple(self.expr(x, graph) for row in e.rows for x in row)
            elem = t.element if isinstance(t, (T.VectorT, T.MatrixT)) else T.UNKNOWN
            check_codegen_type(t, e.span, "a vector literal")
            return ir.VectorLit(t, tuple(self._conv(x, elem, e.span) for x in items))
        if isinstance(e, ast.Since):
            clock = graph.clocks.get(e.clock)
            if clock is None:
                raise not_supported(f"clock '{e.clock}' here", e.span)
            return ir.Since(self._since_type(), clock)
        if isinstance(e, ast.SinceEntry):
            found = self.model.symbol(e)
            if found is None:
                raise not_supported("sinceEntry here", e.span)
            path, node = found
            nid = graph.node_ids.get(id(node))
            if nid is None:
                raise not_supported("sinceEntry of a state outside this machine", e.span)
            return ir.SinceEntry(self._since_type(), nid)
        if isinstance(e, ast.Dollar):
            sym = self.model.symbol(e)
            if isinstance(sym, EventSym):
                ev = self.machine.event(e.name)
                if ev is None:
                    raise not_supported(f"'${e.name}'", e.span)
                return ir.Occurred(T.BOOLEAN, ev.index)
            return self._var_ref(graph, sym, e.span)
        if isinstance(e, ast.DollarInput):
            ev = self.machine.event(e.event)
            if ev is None:
                raise not_supported(f"'${e.event}?{e.var}'", e.span)
            var = self.model.bound_var(e)
            guard: ir.Expr = ir.BindIn(T.BOOLEAN, ev.index, self._var_ref(graph, var, e.var_span))
            if e.predicate is not None:
                guard = ir.Bin(T.BOOLEAN, "and", guard, self.expr(e.predicate, graph))
            return guard
        if isinstance(e, ast.DollarValue):
            ev = self.machine.event(e.event)
            if ev is None or ev.type is None:
                raise not_supported(f"'${e.event}.v'", e.span)
            value = self.expr(e.value, graph)
            return ir.Bin(T.BOOLEAN, "and", ir.Occurred(T.BOOLEAN, ev.index), self._equal(ir.Payload(ev.type, ev.index), value))
        what = {
            ast.StringLit: "a string",
            ast.Binder: "a quantifier, lambda or definite description",
            ast.Let: "'let'",
            ast.TupleLit: "a tuple",
            ast.SeqLit: "a sequence",
            ast.SetLit: "a set",
            ast.SetRange: "a set",
            ast.SetComprehension: "a set comprehension",
            ast.Range: "a range",
            ast.MatrixOp: "inverse/transpose",
        }.get(type(e), type(e).__name__)
        raise not_supported(what, e.span)

    def _user_call(self, sym: FuncSym, e: ast.Call, graph: _Graph) -> ir.Expr:
        """A call of a function the model declares by its contract: implemented in C by the
        file given with --functions (the reference interpreter takes Python implementations)."""
        fmu = self.fl.fmu
        assert fmu is not None
        params = tuple((n, self._norm(t)) for n, t in sym.params)
        result = self._norm(sym.result)
        for n, t in params + (("result", result),):
            if not is_scalar(t):
                raise not_supported(f"function '{sym.name}': {n} of type {t.show()}", e.span)
        signature = f"static {_c_signature(sym.name, params, result)}"
        if self.fl.o.functions is None:
            raise RobogenError.at(
                f"function '{sym.name}' has no implementation: give robogen a C file with --functions",
                e.span,
                Note(f"the file must define: {signature} {{ ... }}"),
            )
        known = next((u for u in fmu.user_functions if u.name == sym.name), None)
        if known is None:
            fmu.user_functions.append(ir.UserFunction(sym.name, params, result, sym.decl.name_span if sym.decl else e.span))
        args = tuple(self._conv(self.expr(a, graph), pt, a.span) for a, (_, pt) in zip(e.args, params))
        return ir.CallU(result, sym.name, args)

    def _since_type(self) -> T.Type:
        p = self.fl.fmu.period  # type: ignore[union-attr]
        return T.NAT if p.denominator == 1 else T.REAL

    def _equal(self, a: ir.Expr, b: ir.Expr) -> ir.Expr:
        if a.type in T.NUMERIC and b.type in T.NUMERIC:
            t = T.REAL if T.REAL in (a.type, b.type) else T.INT
            return ir.Bin(T.BOOLEAN, "eq", self._conv(a, t, None), self._conv(b, t, None))
        return ir.Bin(T.BOOLEAN, "eq", a, b)

    def _binary(self, e: ast.Binary, graph: _Graph) -> ir.Expr:
        op = {
            "iff": "iff", "=>": "implies", "\\/": "or", "/\\": "and",
            "==": "eq", "!=": "ne", "<": "lt", "<=": "le", ">": "gt", ">=": "ge",
            "+": "add", "-": "sub", "*": "mul", "/": "div", "%": "mod",
        }.get(e.op)
        if op is None:
            raise not_supported(f"the operator '{e.op}'", e.span)
        a, b = self.expr(e.left, graph), self.expr(e.right, graph)
        if op in ("iff", "implies", "or", "and"):
            return ir.Bin(T.BOOLEAN, op, a, b)
        if op in ("eq", "ne", "lt", "le", "gt", "ge"):
            if a.type in T.NUMERIC and b.type in T.NUMERIC:
                t = T.REAL if T.REAL in (a.type, b.type) else (T.NAT if a.type == b.type == T.NAT else T.INT)
                return ir.Bin(T.BOOLEAN, op, self._conv(a, t, e.left.span), self._conv(b, t, e.right.span))
            if op not in ("eq", "ne"):
                raise not_supported(f"'{e.op}' on {a.type.show()}", e.span)
            if not (is_scalar(a.type) or isinstance(a.type, (T.RecordT, T.VectorT, T.MatrixT))):
                raise not_supported(f"comparing values of type {a.type.show()}", e.span)
            if a.type != b.type:  # a literal takes the type of the other side: [| 0, 0 |] is vector(nat, 2)
                if self._conv(b, a.type, e.right.span).type == a.type:
                    b = self._conv(b, a.type, e.right.span)
                elif self._conv(a, b.type, e.left.span).type == b.type:
                    a = self._conv(a, b.type, e.left.span)
                else:
                    raise not_supported(f"comparing a {a.type.show()} with a {b.type.show()}", e.span)
            return ir.Bin(T.BOOLEAN, op, a, b)
        t = self._type(e)
        if t not in T.NUMERIC:
            raise not_supported(f"'{e.op}' on {t.show()}", e.span)
        return ir.Bin(t, op, self._conv(a, t, e.left.span), self._conv(b, t, e.right.span))


def _c_signature(name: str, params, result: T.Type) -> str:
    """The C prototype a --functions file must define (for the error note; scalars only)."""

    def c(t: T.Type) -> str:
        return {T.NAT: "uint64_t", T.REAL: "double", T.BOOLEAN: "bool"}.get(t, "int64_t")

    args = ", ".join(f"{c(t)} {n}" for n, t in params) or "void"
    return f"{c(result)} rg_user_{name}({args})"


def _action(state: ast.Node, kind: str) -> ast.Stmt | None:
    for m in getattr(state, "members", ()):
        if isinstance(m, ast.StateAction) and m.kind == kind:
            return m.stmt
    return None


def _has_control(s: ast.Stmt | None) -> bool:
    """Does ``s`` need blocks of its own (exec, wait, operation calls, inputs)?"""
    if s is None:
        return False
    if isinstance(s, (ast.Exec, ast.Wait, ast.CallStmt, ast.DollarCall)):
        return True  # calls may be software operations; the platform ones are cheap either way
    if isinstance(s, ast.Communicate):
        return s.comm.kind == "?"
    if isinstance(s, ast.Seq):
        return any(_has_control(x) for x in s.stmts)
    if isinstance(s, ast.IfStmt):
        return _has_control(s.then) or _has_control(s.otherwise)
    if isinstance(s, ast.StmtDeadline):
        return _has_control(s.stmt)
    return False


def _at(node: ast.Node) -> str:
    span = getattr(node, "name_span", None) or node.span
    return f"{span.path}:{span.line}" if span else "?"


def _cname(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_]", "_", name)


def _parse_setting(text: str, t: T.Type, span: Span | None, name: str) -> object:
    text = text.strip()
    try:
        if t == T.BOOLEAN:
            if text not in ("true", "false"):
                raise ValueError
            return text == "true"
        if t == T.REAL:
            return Fraction(text)
        if t in (T.INT, T.NAT):
            v = int(text)
            if t == T.NAT and v < 0:
                raise ValueError
            return v
        if isinstance(t, T.EnumT):
            lit = text.rsplit("::", 1)[-1]
            return t.literals.index(lit)
    except (ValueError, ArithmeticError):
        pass
    raise RobogenError.at(f"--set {name}={text}: not a value of type {t.show()}", span)


def _constant_value(e: ast.Expr, t: T.Type, model, known: dict[str, object]) -> object:
    """Evaluate a constant's initialiser at generation time (literals, enum literals, constants)."""
    try:
        v = _eval_const(e, model, known)
    except (KeyError, ZeroDivisionError, TypeError):
        return None
    if t == T.REAL and isinstance(v, (int, Fraction)) and not isinstance(v, bool):
        return Fraction(v)
    return v


def _eval_const(e: ast.Expr, model, known: dict[str, object]):
    if isinstance(e, ast.IntLit):
        return e.value
    if isinstance(e, ast.RealLit):
        return Fraction(e.text)
    if isinstance(e, ast.BoolLit):
        return e.value
    if isinstance(e, ast.Name):
        sym = model.symbol(e)
        if isinstance(sym, EnumLitSym):
            return sym.enum.literals.index(sym.literal)  # type: ignore[attr-defined]
        if isinstance(sym, VarSym) and sym.kind == "const":
            return known[sym.name]
        raise KeyError(e.text)
    if isinstance(e, ast.Unary):
        v = _eval_const(e.operand, model, known)
        return (not v) if e.op == "not" else -v
    if isinstance(e, ast.Binary) and e.op in ("+", "-", "*", "/"):
        a, b = _eval_const(e.left, model, known), _eval_const(e.right, model, known)
        if e.op == "/" and isinstance(a, int) and isinstance(b, int):
            q = abs(a) // abs(b)
            return q if (a >= 0) == (b >= 0) else -q
        return {"+": a + b, "-": a - b, "*": a * b, "/": Fraction(a) / Fraction(b) if not (isinstance(a, int) and isinstance(b, int)) else None}[e.op]
    raise KeyError(type(e).__name__)


def instantiation_token(fmu: ir.Fmu, text: str) -> str:
    """A GUID-shaped token derived from the generated description (deterministic)."""
    h = hashlib.sha256(text.encode("utf-8")).hexdigest()
    return "{" + f"{h[0:8]}-{h[8:12]}-{h[12:16]}-{h[16:20]}-{h[20:32]}" + "}"


__all__ = ["Options", "Boundary", "select_boundary", "lower", "model_identifier", "normalise", "instantiation_token"]
