"""Lowering of one state machine into its control-flow graph (see :mod:`robogen.ir.model`).

The machine's storage (variables, constants as FMU parameters, input events, clocks), then its
structure: every node gets an id; a leaf node gets an evaluation block that runs its ``during``
actions (RoboSim), checks its deadlines (RoboChart) and tries its transitions in priority order;
every transition gets a completion block (the exits from the leaf up to its source, its action,
the entry into its target down to a leaf). Statements and expressions are lowered by the
mixins of :mod:`robogen.ir.statements` and :mod:`robogen.ir.expressions`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any, Generator

from robogen.diagnostics import DiagnosticSink, Note, RobogenError, Span, did_you_mean
from robogen.ir import model as ir
from robogen.ir.binders import BinderLowering
from robogen.ir.bindings import BindingLowering, sender_events, sender_type
from robogen.ir.boundary import Boundary
from robogen.ir.derived import DerivedLowering
from robogen.ir.constants import constant_value, default_value, parse_setting, shown
from robogen.ir.expressions import ExpressionLowering
from robogen.ir.region_tree import Graph, place_of, state_action
from robogen.ir.ports import Ports
from robogen.ir.statements import StatementLowering, is_abstract
from robogen.ir.declared import DeclaredFunctions
from robogen.ir.functions import FunctionValues
from robogen.ir.supported import FunMapT, Shapes, check_codegen_type, is_scalar, normalise, not_supported
from robogen.semantics import types as T
from robogen.semantics.model import Controller, FuncSym, MachineScope, OpSym, Region, SemanticModel, VarSym
from robogen.syntax import ast


@dataclass
class FmuContext:
    """What the machines of one FMU share while they are lowered."""

    model: SemanticModel
    boundary: Boundary
    fmu: ir.Fmu
    given: str  # the concrete type of given types
    settings: dict[str, str]  # --set NAME=VALUE
    ports: Ports
    shapes: Shapes = field(default_factory=Shapes)  # the declared types, to unroll recursive ones
    fn_atoms: list | None = None  # the static function values, numbered (robogen.ir.functions)
    sink: DiagnosticSink = field(default_factory=DiagnosticSink)
    # variables a controller provides, shared by its machines: (id(controller), name) -> storage
    shared_vars: dict[tuple[int, str], ir.Var] = field(default_factory=dict)
    random: ir.Var | None = None  # the seeded generator's state, once a machine draws
    # every constant lowered, by FMI name and by its own name -> whether --set may give its value
    constants: dict[str, bool] = field(default_factory=dict)

    def check_settings(self) -> None:
        """Each --set must name a constant of the FMU that takes a value from the command line."""
        for name in self.settings:
            if name not in self.constants:
                scalar = [n for n, settable in self.constants.items() if settable]
                self.sink.error(f"--set {name}: the FMU has no constant named '{name}'{did_you_mean(name, scalar)}", None,
                                *([Note("its constants: " + ", ".join(sorted(scalar)))] if scalar else
                                  [Note("it has no constant a --set could give a value")]))
            elif not self.constants[name]:
                self.sink.error(f"--set {name}: only constants of scalar types and strings take a value from --set; "
                                "give this one its value in the model", None)


def _parameter_record(t: T.Type) -> bool:
    """Can a constant of record type ``t`` without a value be FMU parameters, one per field (an
    enumeration whose literals carry arguments is such a record: its tag and arguments)? Its
    fields are scalars, strings or such records, and start at their type's default."""
    return isinstance(t, T.RecordT) and all(
        is_scalar(ft) or ft == T.STRING or _parameter_record(ft) for _, ft in t.fields)


_NODE_KINDS = {ast.State: "state", ast.Junction: "junction", ast.Final: "final", ast.Initial: "initial",
               ast.Probabilistic: "probabilistic"}


Steps = Generator[Any, Any, Any]  # a lowering step that yields the steps it needs done first (see drive)


def drive(steps: Steps):
    """Run a lowering step and the steps it yields, depth first, with a stack of generators
    instead of Python's: a step yields another step and receives its result. The evaluation of a
    leaf needs the completion of each of its transitions, which needs the evaluation of the leaf
    it arrives at: a chain of 10,000 states is 10,000 steps deep, in the same order recursion
    would take them (the blocks are numbered the same)."""
    stack = [steps]
    value = None
    while stack:
        try:
            nxt = stack[-1].send(value)
        except StopIteration as done:
            stack.pop()
            value = done.value
            continue
        stack.append(nxt)
        value = None
    return value


class MachineLowering(StatementLowering, BindingLowering, BinderLowering, DerivedLowering, ExpressionLowering, FunctionValues,
                      DeclaredFunctions):
    def __init__(self, ctx: FmuContext, scope: MachineScope, ctrl: Controller | None, index: int, used_name: str,
                 name: str | None = None):
        """``name``: the machine's name in the FMU (its own, or its instance path where two
        machines of the FMU have one name: :attr:`Boundary.machine_names`)."""
        self.ctx = ctx
        self.model = ctx.model
        self.boundary = ctx.boundary
        self.ports = ctx.ports
        self.period: Fraction = ctx.fmu.period
        self.scope = scope
        self.ctrl = ctrl
        self.used_name = used_name
        self.robosim = scope.robosim
        self.machine = ir.Machine(name or scope.name, scope.qname, scope.node.name_span, index=index)  # type: ignore[attr-defined]
        self.vars: dict[str, ir.Var] = {}
        self.evals: dict[tuple[int, int], int] = {}  # (graph, leaf node) -> evaluation block
        self.completions: dict[tuple[int, int], int] = {}  # (transition, leaf node) -> completion block
        self.inline_stack: list[str] = []
        self.site = 0
        self.node_now = 0
        self.deadline_flags: dict[tuple[int, int], ir.Var] = {}  # (graph, transition) -> missed flag
        # id(declaration of a let name or lambda parameter) -> what it stands for (robogen.ir.bindings,
        # robogen.ir.functions)
        self.bound: dict = {}
        self.tvars: dict[str, T.Type] = {}  # the type variables of the generic function being inlined (robogen.ir.declared)
        self.inlining: list[tuple[ast.FunctionDef, str]] = []  # the defined functions being inlined, outermost first
        for name, v in scope.vars.items():
            self._declare_var(v, name)
        senders = sender_events(ctx.model, scope)
        for name, e in scope.events.items():
            if e.input:
                t = self._norm(e.type) if e.type is not None else None
                if t is not None:
                    check_codegen_type(t, e.span, f"event '{name}'")
                if name in senders:  # its register keeps the sender too
                    t = sender_type(t)
                self.machine.events.append(ir.Event(name, t, len(self.machine.events), e.span, sender=name in senders))

    # -- storage

    def _norm(self, t: T.Type) -> T.Type:
        return normalise(T.instantiate(t, self.tvars) if self.tvars else t, self.ctx.given, self.ctx.shapes)

    def _declare_var(self, v: VarSym, name: str) -> ir.Var:
        t = self._norm(v.type)
        check_codegen_type(t, v.span, f"variable '{name}'")
        key = (id(self.ctrl) if self.ctrl is not None else 0, name)
        shared = self.ctx.shared_vars
        if v.shared and v.kind == "var" and key in shared:
            var = shared[key]  # another machine of the controller holds it
            if var.type != t:
                raise not_supported(f"shared variable '{name}' with two types ({var.type.show()}, {t.show()})", v.span)
            self.vars[name] = var
            return var
        kind = v.kind if v.kind in ("const", "param") else "var"
        var = ir.Var(name, t, kind, None, v.span, v.shared, len(self.machine.vars), owner=self.machine.index)
        self.machine.vars.append(var)
        self.vars[name] = var
        if v.shared and v.kind == "var":
            shared[key] = var
        if v.kind == "const":
            self._constant(var, v, f"{self.machine.name}.{name}")
        return var

    def operation_constant(self, op: MachineScope, v: VarSym) -> ir.Var:
        """A constant an operation declares without a value: one FMU parameter of the machine,
        ``<machine>.<operation>.<name>``, whichever call site reads it."""
        name = f"{op.name}.{v.name}"
        return self.vars.get(name) or self._declare_var(v, name)

    def _constant(self, var: ir.Var, v: VarSym, fmi_name: str) -> None:
        """A constant is an FMU parameter; its start value comes from --set, its initialiser, or
        (a constant the model leaves without a value) the default value of its type, with a
        warning: the importer sets it in Initialization Mode. A constant whose initialiser is not
        computable here, or of a collection type, is no parameter: the FMU computes it when
        Initialization Mode ends (build(), in robogen.ir.walk.initial_order's order)."""
        fmu = self.ctx.fmu
        settable = is_scalar(var.type) or var.type == T.STRING
        for name in (fmi_name, v.name):
            self.ctx.constants[name] = self.ctx.constants.get(name, False) or settable
        whole_record = v.init is None and _parameter_record(var.type)  # one FMU parameter per field
        if not (settable or whole_record or isinstance(var.type, (T.VectorT, T.MatrixT))):
            # a set, sequence, tuple or record: its initialiser, computed once
            if v.init is None:
                self.ctx.sink.error(f"constant '{v.name}' of type {var.type.show()} has no value: give one in the model",
                                    v.span, Note("constants of scalar types, strings, vectors, matrices and records of these are FMU parameters"))
            return
        settings = self.ctx.settings
        text = settings.get(fmi_name, settings.get(v.name))
        value: object = None
        if text is not None:
            value = parse_setting(text, var.type, v.span, fmi_name)
        elif v.init is not None:
            mine = [p for p in fmu.params if p.machine == self.machine.index]
            value = constant_value(v.init, var.type, self.model, {p.var.name: p.value for p in mine if not p.free})
            if value is None:
                # Not computable here (a conditional, a collection, a function, a constant the
                # importer sets): the FMU computes it when Initialization Mode ends, from the
                # parameters' values then, as a constant of a collection type (build()).
                return
        else:
            value = default_value(var.type)
            if not any(w.span == v.span for w in self.ctx.sink.warnings):  # one per constant, however many machines use it
                how = (f"set its fields in the importer ('{fmi_name}.<field>')" if whole_record else
                       f"set it with --set {v.name}=... or in the importer")
                self.ctx.sink.warning(f"constant '{v.name}' has no value: it becomes FMU parameter '{fmi_name}' with start "
                                      f"{shown(value, var.type)}; {how}", v.span)
        fmu.params.append(ir.Param(fmi_name, var, self.machine.index, value, free=text is None and v.init is None))

    def random_state(self) -> ir.Var:
        """The state of the FMU's seeded generator (robogen.ir.model.RANDOM_SEED), made at its
        first use: it lives in the first machine that draws, starts at the FMU parameter
        random_seed when Initialization Mode ends, and every machine draws from it in turn."""
        ctx = self.ctx
        if ctx.random is None:
            holder = self.machine
            seed = ir.Var(ir.RANDOM_SEED_NAME, T.NAT, "const", None, None, False, len(holder.vars), owner=holder.index)
            holder.vars.append(seed)
            ctx.fmu.params.append(ir.Param(ir.RANDOM_SEED_NAME, seed, holder.index, ir.RANDOM_SEED))
            ctx.random = ir.Var(ir.RANDOM_STATE_NAME, T.NAT, "local", ir.Ref(T.NAT, seed), None, False, len(holder.vars),
                                owner=holder.index)
            holder.vars.append(ctx.random)
        return ctx.random

    def clock(self, name: str) -> int:
        self.machine.clocks.append(name)
        return len(self.machine.clocks) - 1

    def user_function(self, sym: FuncSym, call: ast.Expr, params, result, instance: str = "", shown: str = "") -> None:
        """Record the first use of a user function, or of one instantiation of a generic one
        (``instance``: its C name part; ``shown``: its type variables), whose body the code
        generator asks for. Two functions the user writes have two C names."""
        fmu = self.ctx.fmu
        cname = instance or sym.name
        span = sym.decl.name_span if sym.decl is not None else call.span
        for u in fmu.user_functions:
            if u.cname == cname:
                if u.span != span:
                    raise not_supported(f"function '{sym.name}' here: its C name rg_user_{cname} is also that of "
                                        f"function '{u.name}'", call.span)
                return
        fmu.user_functions.append(ir.UserFunction(sym.name, params, result, span, call.span, instance, shown))

    # -- what the ports ask

    def is_platform_operation(self, op: OpSym) -> bool:
        """RoboSim: an operation of the output context. RoboChart: a required operation that no
        software operation definition implements."""
        if self.robosim:
            return op.platform
        return self.software_operation(op.name) is None

    def is_abstract_operation(self, op: OpSym) -> bool:
        """A software operation the machine requires whose definition has no nodes (see
        robogen.ir.statements.is_abstract)."""
        if self.robosim and op.platform:
            return False
        definition = self.software_operation(op.name)
        return definition is not None and is_abstract(definition)

    def event_type(self, name: str) -> T.Type | None:
        sym = self.scope.events.get(name)
        return self._norm(sym.type) if sym is not None and sym.type is not None else None

    def op_params(self, name: str) -> tuple[tuple[str, T.Type], ...]:
        sym = self.scope.ops.get(name)
        if sym is None:
            return ()
        return tuple((p, self._norm(t)) for p, t in sym.params)

    # -- structure

    def block(self, label: str, span: Span | None) -> ir.Block:
        b = ir.Block(len(self.machine.blocks), label, span)
        self.machine.blocks.append(b)
        return b

    def build(self) -> None:
        """The machine's blocks, from the initial transition of its top region."""
        graph = Graph(self.scope, (), {}, {}, None)
        for name in self.scope.clocks:
            graph.clocks[name] = self.clock(name)
        root = self.scope.region
        assert root is not None
        self.index_regions(graph, root, None)
        parameters = {id(p.var) for p in self.ctx.fmu.params}  # their start values are the FMU's
        for name, v in self.scope.vars.items():
            var = self.vars[name]
            if (v.kind == "var" or (v.kind == "const" and id(var) not in parameters)) and v.init is not None:
                if isinstance(var.type, FunMapT):  # a function value (robogen.ir.functions)
                    var.init = self.fvalue(v.init, var.type, graph)
                else:
                    var.init = self.conv(self.expr(v.init, graph), var.type, v.init.span)
        start = self.block(f"start {self.scope.name}", self.scope.node.name_span)  # type: ignore[attr-defined]
        start.step = True  # the initial transition is the first transition segment
        self.machine.start = start.id
        initials = root.initials()
        if not initials:
            raise RobogenError.at(f"state machine '{self.scope.name}' has no initial node", self.scope.node.name_span)  # type: ignore[attr-defined]
        self.machine.initial_node = graph.node_ids[id(initials[0])]
        self.node_now = self.machine.initial_node
        self.initial_transition(graph, root, start)

    def index_regions(self, graph: Graph, region: Region | None, parent_state: ast.Node | None) -> None:
        """Give every node of ``region`` (and of its composite states) an IR node id."""
        assert region is not None
        graph.regions[id(region.owner)] = region
        for name, node in region.nodes.items():
            nid = len(self.machine.nodes)
            kind = _NODE_KINDS[type(node)]
            self.machine.nodes.append(ir.Node(nid, graph.prefix + region.path + (name,), kind, node.name_span))
            graph.node_ids[id(node)] = nid
            graph.parent[id(node)] = parent_state
            child = region.children.get(name)
            if child is not None:
                self.index_regions(graph, child, node)

    def _region_of(self, graph: Graph, node: ast.Node) -> Region:
        parent = graph.parent[id(node)]
        owner = parent if parent is not None else graph.scope.node
        return graph.regions[id(owner)]

    def initial_transition(self, graph: Graph, region: Region | None, cur: ir.Block) -> None:
        """Take the initial transition of the top ``region`` of a machine or an operation from
        block ``cur``, then evaluate the leaf it reaches."""
        assert region is not None
        cur, leaf = self._initial_inner(graph, region, cur)
        if cur.term is None:
            cur.term = ir.Goto(self._evaluation(graph, leaf))

    def _initial_inner(self, graph: Graph, region: Region, cur: ir.Block) -> tuple[ir.Block, ast.Node]:
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

    def _enter(self, graph: Graph, node: ast.NodeDecl, cur: ir.Block) -> tuple[ir.Block, ast.Node]:
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
            for kind in ("entry",) if self.robosim else ("entry", "during"):
                action = state_action(node, kind)
                if action is not None:
                    cur = self.stmts(action, cur, graph)
            region = graph.regions.get(id(node))
            if region is not None and region.initials():
                return self._initial_inner(graph, region, cur)
        return cur, node

    def _chain(self, graph: Graph, node: ast.Node) -> list[ast.Node]:
        """The enclosing states of ``node``, outermost first, then the node itself."""
        chain = [node]
        p = graph.parent.get(id(node))
        while p is not None:
            chain.append(p)
            p = graph.parent.get(id(p))
        return list(reversed(chain))

    def _outgoing(self, graph: Graph, src: ast.Node) -> list[ast.Transition]:
        """The transitions leaving ``src``, in declaration order."""
        if id(src) not in graph.parent:
            return []
        region = self._region_of(graph, src)
        return [t for t in region.transitions if t.source == src.name]  # type: ignore[attr-defined]

    # -- evaluation of a leaf, and transitions

    def _evaluation(self, graph: Graph, leaf: ast.Node) -> int:
        return drive(self._evaluation_steps(graph, leaf))

    def _evaluation_steps(self, graph: Graph, leaf: ast.Node) -> Steps:
        """The block that evaluates ``leaf``: its transitions (and those of the states around
        it) in priority order, or suspend / terminate / deadlock when none is enabled."""
        key = (id(graph), graph.node_ids[id(leaf)])
        if key in self.evals:
            return self.evals[key]
        name = ".".join(self.machine.nodes[key[1]].path)
        b = self.block(f"EVAL {name}", getattr(leaf, "span", None))
        self.evals[key] = b.id
        self.node_now = key[1]
        cur = b
        sources = self._chain(graph, leaf) if isinstance(leaf, (ast.State, ast.Final)) else [leaf]
        if self.robosim:
            for s in sources:
                during = state_action(s, "during") if isinstance(s, ast.State) else None
                if during is not None:
                    cur = self.stmts(during, cur, graph)
        else:
            for src in sources:
                for t in self._outgoing(graph, src):
                    if t.deadline is not None:
                        cur.stmts.append(self._deadline_check(graph, t, src))
        if isinstance(leaf, ast.Probabilistic):
            cur.term = yield self._probabilistic(graph, leaf, cur, name)
            return b.id
        cases: list[ir.Case] = []
        for src in sources:
            # declaration order, except that 'condition else' is the default: tried last
            for t in sorted(self._outgoing(graph, src), key=lambda t: t.condition_else):
                cases.append((yield self._case(graph, t, src, leaf)))
        default = self._no_transition(graph, leaf, b.id, name)
        cur.term = default if isinstance(default, ir.Goto) else ir.Branch(tuple(cases), default)
        return b.id

    def _probabilistic(self, graph: Graph, leaf: ast.Node, cur: ir.Block, name: str) -> Steps:
        """A probabilistic junction: one draw u in [0, 1) from the seeded generator, then the
        first transition (in declaration order) whose running sum of probabilities exceeds u; the
        last one takes what remains, so rounding never leaves the junction stuck."""
        ts = self._outgoing(graph, leaf)
        if not ts:
            return ir.Fail(ir.Text((f"deadlock in probabilistic junction '{name}' (", place_of(leaf), "): no transition")))
        draw = ir.Var(f"{name}.draw", T.REAL, "local", None, leaf.name_span, False, len(self.machine.vars))  # type: ignore[attr-defined]
        self.machine.vars.append(draw)
        cur.stmts.append(ir.Assign(leaf.name_span, ir.Ref(T.REAL, draw), ir.Draw(T.REAL, self.random_state())))  # type: ignore[attr-defined]
        cases = []
        total: ir.Expr | None = None
        for k, t in enumerate(ts):
            if t.probability is None:
                raise not_supported(f"transition '{t.name}' from a probabilistic junction without a probability", t.span)
            p = self.conv(self.expr(t.probability, graph), T.REAL, t.probability.span)
            total = p if total is None else ir.Bin(T.REAL, "add", total, p)
            last = k == len(ts) - 1
            guard = ir.Lit(T.BOOLEAN, True) if last else ir.Bin(T.BOOLEAN, "lt", ir.Ref(T.REAL, draw), total)
            target = yield self._completion(graph, t, leaf, leaf, None)
            cases.append(ir.Case(guard, target, f"{t.name}: {name} -> {t.target}",
                                 t.name_span, f"probability {self.model.text(t.probability)}"))
        return ir.Branch(tuple(cases), ir.Fail(ir.Text(("no transition taken at ", place_of(leaf)))))

    def _no_transition(self, graph: Graph, leaf: ast.Node, block: int, name: str) -> ir.Terminator:
        """What happens at ``leaf`` when no transition is enabled: an operation's final node
        returns to the caller (a Goto, no branch), the machine's final node terminates, a
        RoboChart state waits, a junction (or a RoboSim state without exec) deadlocks."""
        is_top_final = isinstance(leaf, ast.Final) and graph.parent.get(id(leaf)) is None
        if is_top_final and graph.exit_block is not None:
            return ir.Goto(graph.exit_block)
        if is_top_final:
            return ir.Suspend(block)
        if self.robosim or isinstance(leaf, ast.Junction):
            kind = "junction" if isinstance(leaf, ast.Junction) else "state"
            why = "no transition is enabled" + (" and no exec" if self.robosim else "")
            return ir.Fail(ir.Text((f"deadlock in {kind} '{name}' (", place_of(leaf), f"): {why}")))
        return ir.Suspend(block)  # RoboChart: wait for an event or for time to pass

    def _case(self, graph: Graph, t: ast.Transition, src: ast.Node, leaf: ast.Node) -> Steps:
        guard, event_index = self._guard(graph, t)
        label = f"{t.name}: {src.name} -> {t.target}"  # type: ignore[attr-defined]
        text = self._guard_text(t)
        if t.exec:
            # decide now, act next cycle: the completion is the first segment of the next cycle
            decide = self.block(f"{t.name}: exec decided", t.span)
            decide.stmts.append(ir.Trace(t.span, f"{t.name}: exec"))
            decide.term = ir.Suspend((yield self._completion(graph, t, src, leaf, None)))
            return ir.Case(guard, decide.id, label + " (exec)", t.name_span, text)
        target = yield self._completion(graph, t, src, leaf, event_index)
        return ir.Case(guard, target, label, t.name_span, text)

    def _guard_text(self, t: ast.Transition) -> str:
        """The trigger and condition of ``t`` as model text, in the diagrams' ``trigger [condition]``
        form ('' for a transition that has neither)."""
        parts = [self.model.text(t.trigger)] if t.trigger is not None else []
        if t.condition_else:
            parts.append("[else]")
        elif t.condition is not None:
            parts.append(f"[{self.model.text(t.condition)}]")
        return " ".join(parts)

    def _guard(self, graph: Graph, t: ast.Transition) -> tuple[ir.Expr, int | None]:
        """The guard of ``t`` (trigger and condition) and the event its trigger consumes."""
        guard: ir.Expr | None = None
        event_index = None
        if t.trigger is not None:
            ev = self.machine.event(t.trigger.event)
            if ev is None:
                raise not_supported(f"a trigger on '{t.trigger.event}', which this boundary never receives", t.trigger.span)
            event_index = ev.index
            # e?x binds x when the transition is taken (see _completion), never while guards are
            # only evaluated: the condition reads x as it was before the communication.
            guard = self.receive(t.trigger, ev, graph, bind=False)
        if t.condition is not None:
            cond = self.expr(t.condition, graph)
            guard = cond if guard is None else ir.Bin(T.BOOLEAN, "and", guard, cond)
        return (guard if guard is not None else ir.Lit(T.BOOLEAN, True)), event_index

    def _completion(self, graph: Graph, t: ast.Transition, src: ast.Node, leaf: ast.Node, consume: int | None) -> Steps:
        """The block that takes ``t`` from ``leaf`` (inside ``src``): exits, action, entry."""
        key = (id(t), graph.node_ids[id(leaf)])
        if key in self.completions:
            return self.completions[key]
        b = self.block(f"{t.name}: {src.name} -> {t.target}", t.span)  # type: ignore[attr-defined]
        b.step = True
        self.completions[key] = b.id
        self.node_now = graph.node_ids[id(leaf)]
        cur = b
        if consume is not None:
            if t.trigger is not None:  # bound as the transition is taken
                cur.stmts += self.bindings(t.trigger, self.machine.events[consume], graph)
            cur.stmts.append(ir.Consume(t.span, consume))
        cur.stmts.append(ir.Trace(t.span, f"{t.name}: {src.name} -> {t.target}"))  # type: ignore[attr-defined]
        chain = self._chain(graph, leaf)
        for s in reversed(chain[chain.index(src):]):  # exit from the leaf up to the source, innermost first
            exit_action = state_action(s, "exit") if isinstance(s, ast.State) else None
            if exit_action is not None:
                cur = self.stmts(exit_action, cur, graph)
        for r in t.resets:
            cur.stmts.append(ir.ResetClock(r.span, graph.clocks[r.clock]))
        if t.action is not None:
            cur = self.stmts(t.action, cur, graph)
        cur, arrived = self._enter(graph, self._region_of(graph, src).nodes[t.target], cur)
        if cur.term is None:
            cur.term = ir.Goto((yield self._evaluation_steps(graph, arrived)))
        return b.id

    # -- deadlines (RoboChart; RoboSim rejects them in the checker)

    def _deadline_flag(self, graph: Graph, t: ast.Transition) -> ir.Var:
        """The flag that says the deadline of ``t`` was already reported for this activation of
        its source (one per transition and inlined operation)."""
        key = (id(graph), id(t))
        if key not in self.deadline_flags:
            name = ".".join(graph.prefix + (t.name,)) + ".deadline"
            var = ir.Var(name, T.BOOLEAN, "local", None, t.deadline.span if t.deadline is not None else None, False,
                         len(self.machine.vars))
            self.machine.vars.append(var)
            self.deadline_flags[key] = var
        return self.deadline_flags[key]

    def _deadline_check(self, graph: Graph, t: ast.Transition, src: ast.Node) -> ir.Stmt:
        """In the source's evaluation: the trigger of ``t`` is late if the source has been active
        longer than the deadline; reported once per activation."""
        assert t.deadline is not None
        flag = self._deadline_flag(graph, t)
        elapsed = ir.SinceEntry(self.since_type(), graph.node_ids[id(src)])
        late = self.later(elapsed, self.expr(t.deadline, graph), t.deadline.span)
        guard = ir.Bin(T.BOOLEAN, "and", ir.Un(T.BOOLEAN, "not", ir.Ref(T.BOOLEAN, flag)), late)
        text = ir.Text((f"{t.name}: deadline missed: trigger '{t.trigger.event if t.trigger else ''}' not within "
                        f"{self.model.text(t.deadline)} time unit(s) of entering {src.name} (", place_of(t), ")"))  # type: ignore[attr-defined]
        return ir.If(t.deadline.span, guard, (ir.Assign(t.deadline.span, ir.Ref(T.BOOLEAN, flag), ir.Lit(T.BOOLEAN, True)),
                                               ir.DeadlineMiss(t.deadline.span, text)), ())


__all__ = ["MachineLowering", "FmuContext"]
