"""Random state machines and operation bodies, well formed by construction.

A region (the machine's top level, or a composite state) is an ordered list of nodes: its
initial node, then states, junctions, probabilistic junctions and at most one final node. Every
node after the first state has a *parent* earlier in the list with a transition to it, so every
state is reachable. What keeps a run finite:

- a transition that can run without waiting (RoboSim: not ``exec``; RoboChart: no trigger)
  only goes forward in the list, so such transitions form no cycle (a composite state's inner
  nodes come between it and its next sibling);
- RoboSim: every state has a last transition, ``exec``, enabled when none of the others is, so
  every cycle ends; a junction's last branch is ``condition else``;
- RoboChart: a junction's last branch is ``condition else``; a state may wait for an event.

The guards of one source (RoboChart: of one trigger) exclude each other: the k-th is
``not g1 /\\ ... /\\ not g(k-1) /\\ gk``, so the checker finds no two transitions enabled
together.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

from robogen.fuzz.exprs import Exprs, Scope, Sym
from robogen.fuzz.stmts import OpInfo, Place, Stmts
from robogen.fuzz.typegen import SCALARS, is_struct, parts, type_ast
from robogen.semantics import types as T
from robogen.syntax import ast


@dataclass
class MachineSpec:
    """What the model decided for one machine (or operation) before its body is drawn."""

    name: str
    robosim: bool
    inputs: list[tuple[str, T.Type | None]] = field(default_factory=list)
    outputs: list[tuple[str, T.Type | None]] = field(default_factory=list)
    ops: list[OpInfo] = field(default_factory=list)
    shared: list[Sym] = field(default_factory=list)  # variables it requires (read and written by name)
    dollar_reads: list[Sym] = field(default_factory=list)  # RoboSim platform variables read as $x
    dollar_writes: list[Sym] = field(default_factory=list)  # RoboSim platform variables written ($x = e)
    params: list[Sym] = field(default_factory=list)  # an operation's parameters
    operation: bool = False
    broadcast: set[str] = field(default_factory=set)  # events declared _broadcast
    sw_ifaces: list[str] = field(default_factory=list)  # interfaces of the software operations it calls
    read_ifaces: list[str] = field(default_factory=list)  # RoboSim: interfaces of the variables it reads with $
    write_ifaces: list[str] = field(default_factory=list)  # RoboSim: interfaces of the variables it writes with $


@dataclass
class _Region:
    prefix: str
    nodes: list[ast.NodeDecl] = field(default_factory=list)
    transitions: list[ast.Transition] = field(default_factory=list)


class Machines:
    """Draws the body of a state machine or operation (its variables, clocks, nodes and
    transitions) for a :class:`MachineSpec`."""

    def __init__(self, x: Exprs, s: Stmts, functions: tuple = ()):
        self.x, self.s, self.functions = x, s, functions
        self.rng = x.rng
        self.on = x.on

    # ---------------------------------------------------------------- the body

    def body(self, spec: MachineSpec) -> list[ast.Node]:
        """The members of the machine: variable lists, clocks, nodes and transitions."""
        self.spec = spec
        self.tcount = 0
        self.x.written = set()
        members: list[ast.Node] = []
        consts, vars_ = self._variables(spec, members)
        self.clocks = [f"C{i + 1}" for i in range(self.rng.choice((0, 0, 1, 2)))] if self._timed_ok() else []
        members += [ast.ClockDecl(c) for c in self.clocks]
        syms = tuple(consts + vars_ + spec.shared + spec.params)
        self.base = Scope(syms=syms, robosim=spec.robosim, functions=self.functions,
                          dollar_vars=tuple(spec.dollar_reads))
        self.state_names: list[str] = []
        top = _Region("")
        self._region(top, depth=2 if "composite_states" in self.on else 0)
        keep = self._kept_types(spec, syms)
        return keep + members + top.nodes + top.transitions

    def _kept_types(self, spec: MachineSpec, syms: tuple[Sym, ...]) -> list[ast.Node]:
        """Without the switch ``literal_types``: a variable of each record, tuple and enumeration
        with arguments that the machine writes in an expression, or sends, or passes to an
        operation, but stores in no variable (code generation on main declares the C type of
        such a type only where a variable has it: issue 23's `rg_rec_Twist`)."""
        if "literal_types" in self.on:
            return []
        stored = {p for s in syms for p in parts(s.type)}
        used = set(self.x.written)
        used.update(t for _, t in spec.inputs + spec.outputs if t is not None)
        used.update(t for op in spec.ops for _, t in op.params)
        needed = sorted({p for t in used for p in parts(t) if is_struct(p)} - stored, key=lambda t: t.show())
        return [ast.VarList(False, tuple(ast.VarDecl(self.x.fresh("keep"), type_ast(t)) for t in needed))] if needed else []

    def _timed_ok(self) -> bool:
        return "time" in self.on

    def _variables(self, spec: MachineSpec, members: list[ast.Node]) -> tuple[list[Sym], list[Sym]]:
        rng, x = self.rng, self.x
        consts: list[Sym] = []
        for _ in range(rng.choice((0, 0, 1, 2))):
            t = x.env.draw("var", 1)
            c = Sym(x.fresh("k"), t, "const")
            scope = Scope(syms=tuple(consts), robosim=spec.robosim, lambdas=False)
            if "constant_expressions" not in self.on and (t in SCALARS or t == T.STRING
                                                          or isinstance(t, (T.EnumT, T.VectorT, T.MatrixT))):
                value = x.foldable(t, scope)
            else:
                value = x.expr(t, scope, 1)[0]
            members.append(ast.VarList(True, (ast.VarDecl(c.name, type_ast(t), value),)))
            consts.append(c)
        vars_: list[Sym] = []
        decls = []
        for _ in range(rng.randint(1, 4)):
            t = x.env.draw("var", 2)
            v = Sym(x.fresh("v"), t, "var")
            init = None
            if rng.random() < 0.6:
                init = x.expr(t, Scope(syms=tuple(consts), robosim=spec.robosim, lambdas=False), 1)[0]
            decls.append(ast.VarDecl(v.name, type_ast(t), init))
            vars_.append(v)
        while decls:
            k = rng.randint(1, len(decls))
            members.append(ast.VarList(False, tuple(decls[:k])))
            decls = decls[k:]
        return consts, vars_

    # ---------------------------------------------------------------- regions

    def _region(self, region: _Region, depth: int) -> None:
        rng = self.rng
        kinds = self._node_kinds(depth)
        names: list[str] = []
        initial = ast.Initial(f"i{region.prefix}")
        region.nodes.append(initial)
        for kind in kinds:
            names.append(self._node(region, kind, depth))
        kinds_by_name = dict(zip(names, kinds))
        parent = {n: rng.choice([m for m in names[:i] if kinds_by_name[m] != "final"]) for i, n in enumerate(names) if i}
        children: dict[str, list[str]] = {}
        for child, p in parent.items():
            children.setdefault(p, []).append(child)
        first = names[0]
        action = self.s.action(self._place("initial"), 1) if rng.random() < 0.3 else None
        region.transitions.append(self._t(initial.name, first, action=action))
        for i, n in enumerate(names):
            kind = kinds_by_name[n]
            later = names[i + 1:]
            if kind == "state" or kind == "composite":
                self._state_transitions(region, n, names, later, children.get(n, []), kind == "composite")
            elif kind == "junction":
                self._junction_transitions(region, n, later, children.get(n, []))
            elif kind == "probabilistic":
                self._probabilistic_transitions(region, n, later, children.get(n, []))

    def _node_kinds(self, depth: int) -> list[str]:
        """The kinds of a region's nodes after its initial node: a state first; a junction is
        never last (it needs a node after it); at most one final node."""
        rng, on = self.rng, self.on
        n = rng.randint(1, 4 if depth == 2 else 2)
        kinds = ["state"]
        for _ in range(n - 1):
            options = ["state", "state"]
            if "junctions" in on:
                options.append("junction")
            if "probabilistic" in on and not self.spec.robosim and not self.spec.operation:
                options.append("probabilistic")
            if depth > 0 and "composite_states" in on:
                options.append("composite")
            kinds.append(rng.choice(options))
        if "finals" in on and (self.spec.operation or rng.random() < 0.15):
            kinds.append("final")
        elif kinds[-1] in ("junction", "probabilistic"):
            kinds.append("state")
        if depth > 0 and "composite_states" in on and rng.random() < 0.2:
            kinds[0] = "composite"
        return kinds

    def _node(self, region: _Region, kind: str, depth: int) -> str:
        x = self.x
        if kind == "junction":
            node: ast.NodeDecl = ast.Junction(x.fresh("J"))
        elif kind == "probabilistic":
            node = ast.Probabilistic(x.fresh("P"))
        elif kind == "final":
            node = ast.Final(x.fresh("F"))
        else:
            name = x.fresh("S")
            self.state_names.append(name)
            members: list[ast.Node] = self._state_actions()
            if kind == "composite":
                inner = _Region(f"_{name}")
                self._region(inner, depth - 1)
                members += inner.nodes + inner.transitions
            node = ast.State(name, tuple(members))
        region.nodes.append(node)
        return node.name

    def _state_actions(self) -> list[ast.Node]:
        rng = self.rng
        out: list[ast.Node] = []
        for kind, p in (("entry", 0.5), ("during", 0.1), ("exit", 0.25)):
            if rng.random() < p:
                out.append(ast.StateAction(kind, self.s.action(self._place(kind), 2)))
        return out

    # ---------------------------------------------------------------- places and transitions

    def _place(self, where: str) -> Place:
        """What an action may do: ``where`` is entry, during, exit, initial, transition or
        junction (an action on a junction's branch)."""
        spec = self.spec
        robochart = not spec.robosim
        return Place(
            scope=self.base,
            outputs=tuple(spec.outputs),
            inputs=tuple(spec.inputs) if robochart and where in ("entry", "transition") else (),
            ops=tuple(spec.ops),
            clocks=tuple(self.clocks),
            timed=robochart and self._timed_ok() and where != "initial",
            exec_ok=spec.robosim and where in ("entry", "transition") and self.rng.random() < 0.3,
            dollar_writes=tuple(spec.dollar_writes),
        )

    def _t(self, source: str, target: str, **kw) -> ast.Transition:
        self.tcount += 1
        return ast.Transition(self.x.fresh("t"), source, target, **kw)

    def _guard(self, scope: Scope, used: set[str]) -> ast.Expr:
        return self.x.condition(replace(scope, guard=True, inputs=tuple(self._guard_inputs()),
                                        clocks=tuple(self.clocks), states=tuple(self.state_names)), used)

    def _guard_inputs(self) -> list[tuple[str, T.Type | None]]:
        return self.spec.inputs if self.spec.robosim else []

    def _exclusive(self, guards: list[ast.Expr | None]) -> list[ast.Expr | None]:
        """Conditions that exclude each other: the k-th holds only when no earlier one does;
        a None guard (the last: the fallback) holds when none of the others does."""
        out: list[ast.Expr | None] = []
        for k, g in enumerate(guards):
            negated = [ast.Unary("not", h) for h in guards[:k] if h is not None]
            parts = negated + ([g] if g is not None else [])
            cond = None
            for p in parts:
                cond = p if cond is None else ast.Binary("/\\", cond, p)
            out.append(cond)
        return out

    def _state_transitions(self, region: _Region, n: str, names: list[str], later: list[str],
                           children: list[str], composite: bool) -> None:
        if self.spec.robosim:
            self._robosim_state(region, n, names, later, children, composite)
        else:
            self._robochart_state(region, n, names, later, children, composite)

    def _robosim_state(self, region: _Region, n: str, names: list[str], later: list[str],
                       children: list[str], composite: bool) -> None:
        """Moves (to children and a few more), each exec or not; then, unless the state is
        composite, the fallback: exec, when no move is enabled."""
        rng = self.rng
        targets = list(children) + [rng.choice(names) for _ in range(rng.choice((0, 0, 1)))]
        moves = []
        used: set[str] = set()
        for target in targets:
            forward = target in later
            is_exec = not forward or rng.random() < 0.4
            moves.append((target, is_exec, self._guard(self.base, used)))
        if not composite or not moves:
            moves.append((rng.choice(names), True, None))
        conds = self._exclusive([g for _, _, g in moves])
        for (target, is_exec, _), cond in zip(moves, conds):
            action = self.s.action(self._place("transition"), 2) if rng.random() < 0.4 else None
            region.transitions.append(self._t(n, target, exec=is_exec, condition=cond, action=action))

    def _robochart_state(self, region: _Region, n: str, names: list[str], later: list[str],
                         children: list[str], composite: bool) -> None:
        """Each move is triggered by an input event (any target) or eventless (forward only);
        the guards of the moves with one trigger exclude each other."""
        rng = self.rng
        inputs = self.spec.inputs
        targets = list(children) + [rng.choice(names) for _ in range(rng.choice((0, 1, 1, 2)))]
        by_trigger: dict[str | None, list[tuple[str, ast.Communication | None, ast.Expr | None]]] = {}
        used: dict[str | None, set[str]] = {}
        for target in targets:
            forward = target in later
            if inputs and (not forward or rng.random() < 0.6):
                trigger = self._trigger()
            elif forward:
                trigger = None
            else:
                continue
            key = trigger.event if trigger else None
            guard = self._guard(self.base, used.setdefault(key, set())) if rng.random() < 0.6 else None
            by_trigger.setdefault(key, []).append((target, trigger, guard))
        eventless = by_trigger.pop(None, [])
        ordered = [m for ms in by_trigger.values() for m in ms] + eventless  # an unguarded eventless move shadows later ones
        groups: dict[str | None, list[int]] = {}
        for i, (_, trig, _) in enumerate(ordered):
            groups.setdefault(trig.event if trig else None, []).append(i)
        conds: list[ast.Expr | None] = [None] * len(ordered)
        for key, idx in groups.items():
            guards = [ordered[i][2] for i in idx]
            for k in range(len(guards) - 1):  # only the last of a group may be unguarded
                if guards[k] is None:
                    guards[k] = self._guard(self.base, used.setdefault(key, set()))
            for i, c in zip(idx, self._exclusive([g for g in guards[:-1]] + [guards[-1]])):
                conds[i] = c
        for (target, trigger, _), cond in zip(ordered, conds):
            self._robochart_transition(region, n, target, trigger, cond)

    def _robochart_transition(self, region: _Region, n: str, target: str, trigger: ast.Communication | None,
                              cond: ast.Expr | None) -> None:
        rng = self.rng
        resets = tuple(ast.ClockReset(c) for c in self.clocks if rng.random() < 0.2)
        deadline = ast.IntLit(rng.randint(1, 3)) if trigger is not None and self.clocks and rng.random() < 0.15 else None
        action = self.s.action(self._place("transition"), 2) if rng.random() < 0.5 else None
        region.transitions.append(self._t(n, target, trigger=trigger, resets=resets, deadline=deadline,
                                          condition=cond, action=action))

    def _trigger(self) -> ast.Communication:
        """``e``, ``e?x`` or ``e[| p |]?x`` on an input event."""
        rng = self.rng
        event, t = rng.choice(self.spec.inputs)
        if t is None:
            return ast.Communication(event)
        binders = [s for s in self.base.syms if s.assignable and s.type == t]
        if not binders:
            return ast.Communication(event)
        var = rng.choice(binders)
        filt = None
        if rng.random() < 0.15:
            filt = ast.Filter(None, None, self.x.boolean(self.base, 1))
        # the sender is a number or a name: robogen binds it to a nat, int or string (README, Known limits)
        senders = [s for s in self.base.syms if s.assignable and s.name != var.name and s.type in (T.NAT, T.INT, T.STRING)]
        if "filter_from" in self.on and senders and rng.random() < 0.3:  # [| x = from |]: bind the sender
            pred = self.x.boolean(self.base, 0) if rng.random() < 0.5 else None
            filt = ast.Filter(rng.choice(senders).name, ast.Keyword("from"), pred)
        return ast.Communication(event, "?", var=var.name, filter=filt)

    def _junction_transitions(self, region: _Region, n: str, later: list[str], children: list[str]) -> None:
        rng = self.rng
        targets = list(children) + [rng.choice(later) for _ in range(rng.choice((0, 1)))]
        if not targets:
            targets = [rng.choice(later)]
        used: set[str] = set()
        guards = [self._guard(self.base, used) for _ in targets[:-1]]
        conds = self._exclusive(guards + [None])
        for i, (target, cond) in enumerate(zip(targets, conds)):
            action = self.s.action(self._place("junction"), 1) if rng.random() < 0.3 else None
            last = i == len(targets) - 1
            region.transitions.append(self._t(n, target, condition=None if last else guards[i] if i == 0 else cond,
                                              condition_else=last and len(targets) > 1, action=action))

    def _probabilistic_transitions(self, region: _Region, n: str, later: list[str], children: list[str]) -> None:
        rng = self.rng
        targets = list(children) or [rng.choice(later)]
        if len(targets) == 1:
            targets.append(rng.choice(later))
        shares = {2: ("0.25", "0.75"), 3: ("0.5", "0.25", "0.25"), 4: ("0.25", "0.25", "0.25", "0.25")}
        probs = shares.get(len(targets), ("1.0",))
        if len(targets) > 4:
            targets = targets[:4]
            probs = shares[4]
        for target, p in zip(targets, probs):
            action = self.s.action(self._place("junction"), 1) if rng.random() < 0.3 else None
            region.transitions.append(self._t(n, target, probability=ast.RealLit(p), action=action))


__all__ = ["Machines", "MachineSpec"]
