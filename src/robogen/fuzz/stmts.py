"""Random statements of RoboChart and RoboSim actions, over a :class:`Place`: what an action may
use where it is written (the variables it may assign, the events it may send or wait for, the
operations it may call, the clocks it may reset, whether it may wait or end the cycle)."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

from robogen.fuzz.exprs import Exprs, Scope, Sym, chained, fits, fits_bind
from robogen.fuzz.typegen import NUMBERS
from robogen.semantics import types as T
from robogen.syntax import ast


@dataclass(frozen=True)
class OpInfo:
    """An operation an action may call: a platform operation (an output clock) or a software one."""

    name: str
    params: tuple[tuple[str, T.Type], ...]
    platform: bool


@dataclass(frozen=True)
class Place:
    scope: Scope
    outputs: tuple[tuple[str, T.Type | None], ...] = ()  # events this action may send
    inputs: tuple[tuple[str, T.Type | None], ...] = ()  # RoboChart: events an action may wait for (e?x)
    ops: tuple[OpInfo, ...] = ()
    clocks: tuple[str, ...] = ()  # clocks it may reset
    timed: bool = False  # RoboChart: wait and statement deadlines allowed
    exec_ok: bool = False  # RoboSim: an exec statement allowed here
    dollar_writes: tuple[Sym, ...] = ()  # RoboSim: variables written with $x = e


@dataclass
class Stmts:
    x: Exprs
    sent: set[str] = field(default_factory=set)  # output events and operations some action uses
    called: set[str] = field(default_factory=set)

    @property
    def rng(self):
        return self.x.rng

    def action(self, p: Place, size: int = 2) -> ast.Stmt:
        """A statement of about ``size`` basic statements."""
        n = max(1, self.rng.randint(1, size))
        stmts = [self.basic(p, 2) for _ in range(n)]
        return stmts[0] if n == 1 else ast.Seq(tuple(_flat(stmts)))

    def basic(self, p: Place, depth: int) -> ast.Stmt:
        rng = self.rng
        sc = p.scope
        forms: list = []
        targets = [s for s in sc.syms if s.assignable]
        if targets:
            forms.append((6, self._assign))
        if p.outputs:
            forms.append((4, self._send))
        if p.ops:
            forms.append((3, self._call))
        if depth > 0:
            forms.append((2, self._if))
        if p.clocks:
            forms.append((1, lambda p, d: ast.ClockReset(rng.choice(p.clocks))))
        if p.timed:
            forms.append((1, self._wait))
        if p.inputs and not sc.robosim:
            forms.append((1, self._receive))
        if p.exec_ok:
            forms.append((1, lambda p, d: ast.Exec()))
        if p.dollar_writes:
            forms.append((2, self._dollar_assign))
        forms.append((1, lambda p, d: ast.Skip()))
        make = rng.choices([m for _, m in forms], [w for w, _ in forms])[0]
        s = make(p, depth - 1)
        if p.timed and not isinstance(s, (ast.Seq, ast.StmtDeadline)) and rng.random() < 0.08:
            s = ast.StmtDeadline(s, ast.IntLit(rng.randint(1, 3)))
        return s

    def _assign(self, p: Place, d: int) -> ast.Stmt:
        rng = self.rng
        sc = p.scope
        s = rng.choice([s for s in sc.syms if s.assignable])
        target: ast.Expr = ast.Name((s.name,))
        t = s.type
        r = rng.random()
        if isinstance(t, T.RecordT) and r < 0.4:
            f, t = rng.choice(t.fields)
            target = ast.Field(target, f)
        elif isinstance(t, T.VectorT) and r < 0.4:
            target = ast.Index(target, (ast.IntLit(rng.randint(1, t.size)),))  # type: ignore[arg-type]
            t = t.element
        elif isinstance(t, T.MatrixT) and r < 0.4:
            target = ast.Index(target, (ast.IntLit(rng.randint(1, t.rows)), ast.IntLit(rng.randint(1, t.columns))))  # type: ignore[arg-type]
            t = t.element
        elif isinstance(t, T.FunctionT) and "function_updates" in self.x.on and r < 0.5:
            return ast.Assign(target, self._updated(target, t, sc))
        value, _ = self.x.expr(t, sc, 2)
        return ast.Assign(target, value)

    def _updated(self, f: ast.Expr, t: T.FunctionT, sc: Scope) -> ast.Expr:
        """``override(f, {(| k, v |), ...})``: function variable ``f`` updated at one or two
        arguments by the relation toolkit (the later pair of one argument wins)."""
        self.x.toolkits.add("relation_toolkit")
        pairs = []
        for _ in range(self.rng.choice((1, 2))):
            (k, kt), (v, vt) = self.x.expr(t.domain, sc, 1), self.x.expr(t.range, sc, 1)
            pairs.append((ast.TupleLit((k, v)), T.ProductT((kt, vt))))
        return ast.Call(ast.Name(("override",)), (f, ast.SetLit(chained(pairs)[0])))  # (model 2.107)

    def _dollar_assign(self, p: Place, d: int) -> ast.Stmt:
        s = self.rng.choice(p.dollar_writes)
        return ast.DollarAssign(s.name, self.x.expr(s.type, p.scope, 2)[0])

    def _send(self, p: Place, d: int) -> ast.Stmt:
        rng = self.rng
        event, t = rng.choice(p.outputs)
        self.sent.add(event)
        if p.scope.robosim:
            if t is None:
                return ast.DollarOutput(event, "", None)
            return ast.DollarOutput(event, rng.choice(("!", "!", ".")), self.x.expr(t, p.scope, 2)[0])
        if t is None:
            return ast.Communicate(ast.Communication(event), rng.random() < 0.5)
        kind = rng.choice(("!", "!", "."))
        return ast.Communicate(ast.Communication(event, kind, value=self.x.expr(t, p.scope, 2)[0]), rng.random() < 0.6)

    def _receive(self, p: Place, d: int) -> ast.Stmt:
        """RoboChart ``e?x`` in an action: waits for the event."""
        rng = self.rng
        event, t = rng.choice(p.inputs)
        binders = [s for s in p.scope.syms if s.assignable and t is not None and fits_bind(t, s.type)]
        if binders:  # (a plain `e` in an action is an output: only `e?x` waits for an input)
            return ast.Communicate(ast.Communication(event, "?", var=rng.choice(binders).name), rng.random() < 0.5)
        return ast.Skip()

    def _call(self, p: Place, d: int) -> ast.Stmt:
        op = self.rng.choice(p.ops)
        self.called.add(op.name)
        args = tuple(self.x.expr(t, p.scope, 2)[0] for _, t in op.params)
        if p.scope.robosim and op.platform:
            return ast.DollarCall(op.name, args)
        return ast.CallStmt(ast.Call(ast.Name((op.name,)), args))

    def _if(self, p: Place, d: int) -> ast.Stmt:
        cond = self.x.boolean(replace(p.scope, guard=False), 2)
        then = self.basic(p, d)
        other = self.basic(p, d) if self.rng.random() < 0.5 else None
        return ast.IfStmt(cond, then, other)

    def _wait(self, p: Place, d: int) -> ast.Stmt:
        rng = self.rng
        if rng.random() < 0.25:
            low = rng.randint(0, 2)
            return ast.Wait(ast.Range(ast.IntLit(low), ast.IntLit(low + rng.randint(0, 2)), True, True))
        return ast.Wait(ast.IntLit(rng.randint(0, 2)))


def _flat(stmts: list[ast.Stmt]) -> list[ast.Stmt]:
    """A sequence is a flat list (the parser builds ``a ; b ; c`` as one Seq)."""
    out: list[ast.Stmt] = []
    for s in stmts:
        out.extend(s.stmts if isinstance(s, ast.Seq) else (s,))
    return out


__all__ = ["Stmts", "Place", "OpInfo", "fits", "NUMBERS"]
