"""Lowering of statements (actions): each statement is appended to the open block; one that
waits (exec, wait, an input) or calls a software operation closes the block and control goes on
in a new one, which the step returns.

Software operations are inlined at each call site, with their own nodes, variables and clocks;
platform operations and output events become ``Emit`` statements routed by the FMU's ports.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from robogen.diagnostics import Span, working_on
from robogen.ir import model as ir
from robogen.ir.region_tree import Graph, place_of
from robogen.ir.supported import FunMapT, check_codegen_type, not_supported
from robogen.semantics import types as T
from robogen.semantics.model import MachineScope, OpSym
from robogen.syntax import ast

if TYPE_CHECKING:  # the attributes MachineLowering provides
    from robogen.ir.ports import Ports
    from robogen.semantics.model import Controller, SemanticModel


class StatementLowering:
    """The statement steps of :class:`~robogen.ir.machines.MachineLowering` (a mixin). It uses
    the expression steps and the machine lowering's blocks, clocks, node index and initial
    transitions (``block``, ``clock``, ``index_regions``, ``initial_transition``, ``evaluation``)."""

    model: SemanticModel
    machine: ir.Machine
    scope: MachineScope
    ctrl: Controller | None
    ports: Ports
    site: int  # the last call site or statement deadline numbered
    node_now: int  # the machine's state output where the statement being lowered runs
    inline_stack: list[str]

    def stmts(self, s: ast.Stmt, cur: ir.Block, graph: Graph) -> ir.Block:
        """Lower statement ``s`` at the end of block ``cur``; returns the block where control
        continues afterwards (a new one when ``s`` suspends or calls an operation)."""
        with working_on(s.span):
            step = getattr(self, "_s_" + type(s).__name__, None)
            if step is None:  # pragma: no cover - every statement form has a step
                raise not_supported(f"the statement '{type(s).__name__}'", s.span)
            return step(s, cur, graph)

    # -- sequencing and waiting

    def _s_Seq(self, s: ast.Seq, cur: ir.Block, graph: Graph) -> ir.Block:
        for x in s.stmts:
            cur = self.stmts(x, cur, graph)
        return cur

    def _s_Skip(self, s: ast.Skip, cur: ir.Block, graph: Graph) -> ir.Block:
        return cur

    def _s_Exec(self, s: ast.Exec, cur: ir.Block, graph: Graph) -> ir.Block:
        nxt = self.block("after exec", s.span)
        cur.term = ir.Suspend(nxt.id)
        return nxt

    def _s_Wait(self, s: ast.Wait, cur: ir.Block, graph: Graph) -> ir.Block:
        cur.stmts.append(ir.StartWait(s.span, self._duration(s.duration, cur, graph)))
        wait = self.block("wait", s.span)
        nxt = self.block("after wait", s.span)
        cur.term = ir.Goto(wait.id)
        done = ir.Bin(T.BOOLEAN, "le", ir.WaitLeft(T.INT), ir.Lit(T.INT, 0))
        wait.term = ir.Branch((ir.Case(done, nxt.id, "wait over", s.span),), ir.Suspend(wait.id))
        return nxt

    def _duration(self, d: ast.Expr, cur: ir.Block, graph: Graph) -> ir.Expr:
        """The time units of ``wait(d)``: ``d`` itself, or a number chosen by the FMU's seeded
        generator from a range (``[a, b]``, ``(a, b]``...) or a set literal of integers: RoboChart
        lets a nondeterministically chosen number pass, robogen draws it (robogen.ir.model.Draw)."""
        if isinstance(d, ast.Range):
            low, high = (self._integer(x, graph) for x in (d.low, d.high))
            if not d.low_closed:
                low = ir.Bin(T.INT, "add", low, ir.Lit(T.INT, 1))
            if not d.high_closed:
                high = ir.Bin(T.INT, "sub", high, ir.Lit(T.INT, 1))
            return ir.Draw(T.INT, self.random_state(), low, high)  # type: ignore[attr-defined]
        if isinstance(d, ast.SetLit) and d.items:
            items = [self._integer(x, graph) for x in d.items]
            k = ir.Draw(T.INT, self.random_state(), ir.Lit(T.INT, 1), ir.Lit(T.INT, len(items)))  # type: ignore[attr-defined]
            if len(items) == 1:
                return items[0]
            self.site += 1  # the k-th element, k drawn once
            chosen = ir.Var(f"choice#{self.site}", T.INT, "local", None, d.span, False, len(self.machine.vars))
            self.machine.vars.append(chosen)
            cur.stmts.append(ir.Assign(d.span, ir.Ref(T.INT, chosen), k))
            value: ir.Expr = items[-1]
            for i in range(len(items) - 2, -1, -1):
                value = ir.Cond(T.INT, ir.Bin(T.BOOLEAN, "eq", ir.Ref(T.INT, chosen), ir.Lit(T.INT, i + 1)), items[i], value)
            return value
        value = self.expr(d, graph)
        if value.type not in T.NUMERIC:
            raise not_supported(f"wait on a value of type {value.type.show()}", d.span)
        return self.conv(value, T.INT, d.span)

    def _integer(self, e: ast.Expr, graph: Graph) -> ir.Expr:
        value = self.expr(e, graph)
        if value.type not in (T.NAT, T.INT):
            raise not_supported(f"a wait of {value.type.show()} time units", e.span)
        return self.conv(value, T.INT, e.span)

    def _s_ClockReset(self, s: ast.ClockReset, cur: ir.Block, graph: Graph) -> ir.Block:
        cur.stmts.append(ir.ResetClock(s.span, graph.clocks[s.clock]))
        return cur

    def _s_IfStmt(self, s: ast.IfStmt, cur: ir.Block, graph: Graph) -> ir.Block:
        cond = self.expr(s.cond, graph)
        if not has_control(s.then) and not has_control(s.otherwise):
            then = self._straight(s.then, graph)
            otherwise = self._straight(s.otherwise, graph) if s.otherwise is not None else []
            cur.stmts.append(ir.If(s.span, cond, tuple(then), tuple(otherwise)))
            return cur
        then_b = self.block("then", s.then.span)
        join = self.block("end if", s.span)
        self.stmts(s.then, then_b, graph).term = ir.Goto(join.id)
        default: ir.Terminator = ir.Goto(join.id)
        if s.otherwise is not None:
            else_b = self.block("else", s.otherwise.span)
            self.stmts(s.otherwise, else_b, graph).term = ir.Goto(join.id)
            default = ir.Goto(else_b.id)
        cur.term = ir.Branch((ir.Case(cond, then_b.id, "if", s.span, self.model.text(s.cond)),), default)
        return join

    def _straight(self, s: ast.Stmt, graph: Graph) -> list[ir.Stmt]:
        """The statements of ``s``, which has no control flow of its own (no exec, wait, input or
        call: see has_control), lowered into a detached block that never joins the machine."""
        detached = ir.Block(-1, "detached", s.span)
        end = self.stmts(s, detached, graph)
        assert end is detached and detached.term is None, "a statement with control flow in an if without blocks"
        return detached.stmts

    def _s_StmtDeadline(self, s: ast.StmtDeadline, cur: ir.Block, graph: Graph) -> ir.Block:
        if not has_control(s.stmt):  # takes no time: cannot miss its deadline
            return self.stmts(s.stmt, cur, graph)
        self.site += 1
        start = ir.Var(f"deadline#{self.site}", T.NAT, "local", None, s.span, False, len(self.machine.vars))
        self.machine.vars.append(start)
        cur.stmts.append(ir.Assign(s.span, ir.Ref(T.NAT, start), ir.Now(T.NAT)))
        cur = self.stmts(s.stmt, cur, graph)
        elapsed = ir.Bin(T.NAT, "sub", ir.Now(T.NAT), ir.Ref(T.NAT, start))
        late = self.later(elapsed, self.expr(s.bound, graph), s.bound.span)
        text = ir.Text(("deadline missed: the statement at ", place_of(s), f" took longer than {self.model.text(s.bound)} time unit(s)"))
        cur.stmts.append(ir.If(s.span, late, (ir.DeadlineMiss(s.span, text),), ()))
        return cur

    # -- assignments

    def _s_Assign(self, s: ast.Assign, cur: ir.Block, graph: Graph) -> ir.Block:
        target = self.lvalue(s.target, graph)
        if isinstance(target.type, FunMapT):  # a function value (robogen.ir.functions)
            cur.stmts.append(ir.Assign(s.span, target, self.fvalue(s.value, target.type, graph)))  # type: ignore[attr-defined]
            return cur
        cur.stmts.append(ir.Assign(s.span, target, self.conv(self.expr(s.value, graph), target.type, s.value.span)))
        return cur

    def _s_DollarAssign(self, s: ast.DollarAssign, cur: ir.Block, graph: Graph) -> ir.Block:
        target = self.var_ref(graph, self.model.symbol(s), s.var_span)
        cur.stmts.append(ir.Assign(s.span, target, self.conv(self.expr(s.value, graph), target.type, s.value.span)))
        return cur

    # -- communication

    def _s_DollarOutput(self, s: ast.DollarOutput, cur: ir.Block, graph: Graph) -> ir.Block:
        return self._emit(s.event, s.value, s.span, cur, graph)

    def _s_Communicate(self, s: ast.Communicate, cur: ir.Block, graph: Graph) -> ir.Block:
        c = s.comm
        if c.kind == "?":
            return self._input(s, cur, graph)
        if c.filter is not None and (c.filter.bind is not None or c.filter.predicate is not None):
            raise not_supported("a filter on an output or synchronisation", c.filter.span)
        # e.v offers exactly v: towards the machines and the platform it is connected to, the same
        # communication as e!v (the receiver's e?x or trigger takes it)
        return self._emit(c.event, c.value, s.span, cur, graph)

    def _emit(self, event: str, value: ast.Expr | None, span: Span | None, cur: ir.Block, graph: Graph) -> ir.Block:
        args = () if value is None else (self._payload(event, value, graph),)
        cur.stmts.append(ir.Emit(span, event, args, self.ports.output_routes(self, event, "output-event", span)))  # type: ignore[arg-type]
        return cur

    def _payload(self, event: str, value: ast.Expr, graph: Graph) -> ir.Expr:
        t = self.event_type(event)
        e = self.expr(value, graph)
        return self.conv(e, t, value.span) if t is not None else e

    def _input(self, s: ast.Communicate, cur: ir.Block, graph: Graph) -> ir.Block:
        """An input ``e?x`` in an action waits for the event, then binds its value."""
        c = s.comm
        ev = self.machine.event(c.event)
        if ev is None:
            raise not_supported(f"an input of '{c.event}', which this boundary never receives", s.span)
        wait = self.block(f"wait for {c.event}", s.span)
        nxt = self.block(f"after {c.event}?{c.var}", s.span)
        cur.term = ir.Goto(wait.id)
        if ev.sender:  # bound when it comes, from the register, with the sender
            nxt.stmts += self.bindings(c, ev, graph)
        nxt.stmts.append(ir.Consume(s.span, ev.index))
        guard = self.receive(c, ev, graph, bind=not ev.sender)
        wait.term = ir.Branch((ir.Case(guard, nxt.id, f"{c.event}?{c.var}", s.span),), ir.Suspend(wait.id))
        return nxt

    def bindings(self, c: ast.Communication, ev: ir.Event, graph: Graph) -> list[ir.Stmt]:
        """The assignments of a communication that takes the occurrence of ``ev`` in the buffer:
        the sender to the variable of ``[| x = from |]``, then the value to ``x`` of ``e?x``."""
        out: list[ir.Stmt] = []
        sender = self.sender_binding(c, ev)  # type: ignore[attr-defined]
        if sender is not None:
            var, value = sender
            out.append(ir.Assign(c.span, self.var_ref(graph, var, c.filter.span), value))  # type: ignore[attr-defined, union-attr]
        if c.kind == "?":
            target = self.var_ref(graph, self.model.bound_var(c), c.var_span)  # type: ignore[attr-defined]
            out.append(ir.Assign(c.span, target, self.conv(self.event_value(ev), target.type, c.span)))  # type: ignore[attr-defined]
        return out

    def bind_in(self, ev: ir.Event, target: ir.Expr, span: Span | None) -> ir.BindIn:
        """``e?x`` in a guard: the value stored in x as its type holds it (RoboChart lets a real
        event be received into an int variable, and an int into a nat one)."""
        value = self.conv(ir.Payload(ev.type, ev.index), target.type, span)  # type: ignore[arg-type, attr-defined]
        return ir.BindIn(T.BOOLEAN, ev.index, target, None if isinstance(value, ir.Payload) else value)

    def receive(self, c: ast.Communication, ev: ir.Event, graph: Graph, bind: bool = True) -> ir.Expr:
        """The test that ``c`` (``e``, ``e?x``, with a filter or not) can take event ``ev`` now;
        ``e?x`` stores the value in ``x`` when it can, and only then (unless ``bind`` is false: a
        transition's trigger binds when the transition is taken, see MachineLowering._completion)."""
        offered: ir.Expr = ir.Occurred(T.BOOLEAN, ev.index)
        condition = self.filter_guard(c, ev, graph)  # type: ignore[attr-defined]
        if condition is not None:
            offered = ir.Bin(T.BOOLEAN, "and", offered, condition)
        if c.kind != "?" or not bind:
            return offered
        bind_in = self.bind_in(ev, self.var_ref(graph, self.model.bound_var(c), c.var_span), c.span)  # type: ignore[attr-defined]
        return bind_in if condition is None else ir.Bin(T.BOOLEAN, "and", offered, bind_in)

    # -- operation calls

    def _s_CallStmt(self, s: ast.CallStmt, cur: ir.Block, graph: Graph) -> ir.Block:
        return self._call(self.model.symbol(s.call.func), s.call.args, cur, graph, s.span)

    def _s_DollarCall(self, s: ast.DollarCall, cur: ir.Block, graph: Graph) -> ir.Block:
        return self._call(self.model.symbol(s), s.args, cur, graph, s.span)

    def _call(self, op: OpSym, args, cur: ir.Block, graph: Graph, span: Span | None) -> ir.Block:
        """A call of a platform operation, or of an abstract operation (a definition without
        nodes: the model leaves its behaviour to the environment), leaves the FMU through the
        operation's output clock; a software operation's body is inlined."""
        values = tuple(self.conv(self.expr(a, graph), self._norm(pt), a.span) for a, (_, pt) in zip(args, op.params))
        definition = self.software_operation(op.name, graph.scope) if not op.platform else None
        if definition is None or is_abstract(definition):
            params = tuple((p, self._norm(t)) for p, t in op.params)
            routes = self.ports.output_routes(self, op.name, "operation", span, params, abstract=definition is not None)  # type: ignore[arg-type]
            cur.stmts.append(ir.Emit(span, op.name, values, routes))
            return cur
        return self._inline(definition, values, cur, graph, span)

    def software_operation(self, name: str, caller: MachineScope | None = None) -> MachineScope | None:
        """The definition of a software operation the machine (or the operation ``caller``)
        calls, if it has one (otherwise the operation belongs to the robotic platform): the one
        its controller references (opref), else the one visible from the calling file (its
        package, its imports, files without a package), never an operation of the same name
        elsewhere in the workspace."""
        module = self.boundary.module
        if module is not None and module.platform is not None and name in module.platform.operations:
            return None
        if self.ctrl is not None:
            for used, scope in self.ctrl.operations:
                if scope.name == name or used == name:
                    return scope
        definition = (caller or self.scope).definitions.get(name)
        return self.model.scope_of(definition) if definition is not None else None

    def _inline(self, op: MachineScope, values, cur: ir.Block, graph: Graph, span: Span | None) -> ir.Block:
        """The body of software operation ``op`` at this call site, entered from ``cur``; returns
        the block where the caller goes on when the operation reaches its final node."""
        if op.name in self.inline_stack:
            raise not_supported(f"the recursive call of operation '{op.name}'", span)
        if op.region is None or not op.region.initials():  # nodes, but none to start from (RoboTool warns)
            raise not_supported(f"a call of operation '{op.name}', whose definition has nodes but no initial node", span)
        self.site += 1
        site = self.site
        after = self.block(f"after {op.name}()", span)
        sub = Graph(op, (f"{op.name}#{site}",), self._call_site_vars(op, site), {}, after.id)
        for name, clock in op.clocks.items():
            if clock.from_interface and name in graph.clocks:
                sub.clocks[name] = graph.clocks[name]  # a clock of the caller, required by the operation
            else:
                sub.clocks[name] = self.clock(f"{op.name}#{site}.{name}")
        self.index_regions(sub, op.region, None)
        for p, value in zip(op.node.params, values):  # type: ignore[attr-defined]
            var = sub.env[p.name]
            cur.stmts.append(ir.Assign(span, ir.Ref(var.type, var), self.conv(value, var.type, span)))
        for name, v in op.vars.items():
            if v.kind in ("var", "const") and not v.shared and v.init is not None:
                var = sub.env[name]
                value = self.fvalue(v.init, var.type, sub) if isinstance(var.type, FunMapT) \
                    else self.conv(self.expr(v.init, sub), var.type, v.init.span)  # type: ignore[attr-defined]
                cur.stmts.append(ir.Assign(v.span, ir.Ref(var.type, var), value))
        caller_node = self.node_now
        self.inline_stack.append(op.name)
        try:
            start = self.block(f"call {op.name}()", span)
            cur.term = ir.Goto(start.id)
            self.initial_transition(sub, op.region, start)
        finally:
            self.inline_stack.pop()
        # back in the caller: its node is the machine's state again (no new entry)
        after.stmts.insert(0, ir.Enter(span, caller_node, resume=True))
        self.node_now = caller_node
        return after

    def _call_site_vars(self, op: MachineScope, site: int) -> dict[str, ir.Var]:
        """The operation's parameters and own variables at one call site (initialised at each
        call, not at the start of the FMU)."""
        env: dict[str, ir.Var] = {}
        for name, v in op.vars.items():
            if v.shared:
                continue
            if v.kind == "const" and v.init is None:  # a parameter of the FMU, not of the call
                env[name] = self.operation_constant(op, v)
                continue
            t = self._norm(v.type)
            check_codegen_type(t, v.span, f"variable '{name}' of operation '{op.name}'")
            var = ir.Var(f"{op.name}#{site}.{name}", t, "local", None, v.span, False, len(self.machine.vars))
            self.machine.vars.append(var)
            env[name] = var
        return env


def is_abstract(op: MachineScope) -> bool:
    """An operation definition without nodes (only its signature, requirements or ``terminates``):
    abstract, valid in RoboTool, and an operation that terminates at once. Its call is an output
    of the FMU, as a platform operation's (README: The FMI mapping)."""
    return op.region is None or not op.region.nodes


def has_control(s: ast.Stmt | None) -> bool:
    """Does ``s`` need blocks of its own (exec, wait, operation calls, inputs)?"""
    if s is None:
        return False
    if isinstance(s, (ast.Exec, ast.Wait, ast.CallStmt, ast.DollarCall)):
        return True  # calls may be software operations; the platform ones are cheap either way
    if isinstance(s, ast.Communicate):
        return s.comm.kind == "?"
    if isinstance(s, ast.Seq):
        return any(has_control(x) for x in s.stmts)
    if isinstance(s, ast.IfStmt):
        return has_control(s.then) or has_control(s.otherwise)
    if isinstance(s, ast.StmtDeadline):
        return has_control(s.stmt)
    return False


__all__ = ["StatementLowering", "has_control", "is_abstract"]
