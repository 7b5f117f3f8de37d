"""Static analyses of one state machine that produce warnings (never errors):

- states no path from the initial node reaches;
- transitions that can never fire (a guard that no assignment satisfies, or an earlier
  transition of the same source that is always enabled and has priority);
- non-determinism: two transitions of one source (same trigger) whose guards can hold together,
  reported only with a concrete witness, so the warning is never speculative;
- RoboSim: states from which no path reaches ``exec``, and cycles of transitions without ``exec``.

Guards are evaluated over small domains: each input event ``$e`` and boolean leaf is true or
false, an enumeration-valued leaf ranges over its literals, a numeric leaf over the literals of
the guards and their neighbours. "Never fires" uses an abstraction in which every comparison is
an independent proposition (an over-approximation: if even that is unsatisfiable, the guard is).
"""

from __future__ import annotations

import itertools
from fractions import Fraction
from typing import Iterable, Iterator

from robogen.diagnostics import DiagnosticSink, Note
from robogen.semantics import types as T
from robogen.semantics.exprs import Tables
from robogen.semantics.scope import EnumLitSym, MachineScope, Region, VarSym
from robogen.syntax import ast

_MAX_ASSIGNMENTS = 4096


def analyse_machine(scope: MachineScope, tables: Tables, sink: DiagnosticSink) -> None:
    """Run the analyses, unless the machine has errors: warnings built on a name that did not
    resolve would only repeat, less clearly, what the errors already say."""
    assert scope.region is not None
    if sink.errors and any(_in_machine(d.span, scope) for d in sink.errors):
        return
    never = _never_firing(scope, tables, sink)
    _unreachable(scope, never, sink)
    _nondeterminism(scope, tables, never, sink)
    if scope.robosim:
        _exec_reachability(scope, never, sink)
        _exec_free_cycles(scope, never, sink)


# ---------------------------------------------------------------------------- structure helpers


def _in_machine(span, scope: MachineScope) -> bool:
    own = scope.node.span
    if span is None or own is None or span.path != own.path:
        return False
    return (own.line, own.column) <= (span.line, span.column) <= (own.end_line, own.end_column)


def _regions(scope: MachineScope) -> Iterator[Region]:
    assert scope.region is not None
    yield from scope.region.walk()


def _by_source(region: Region) -> dict[str, list[ast.Transition]]:
    out: dict[str, list[ast.Transition]] = {}
    for t in region.transitions:
        out.setdefault(t.source, []).append(t)
    return out


def _stmts(s: ast.Stmt | None) -> Iterator[ast.Stmt]:
    if s is None:
        return
    yield s
    if isinstance(s, ast.Seq):
        for x in s.stmts:
            yield from _stmts(x)
    elif isinstance(s, ast.IfStmt):
        yield from _stmts(s.then)
        yield from _stmts(s.otherwise)
    elif isinstance(s, ast.StmtDeadline):
        yield from _stmts(s.stmt)


def has_exec(s: ast.Stmt | None) -> bool:
    return any(isinstance(x, ast.Exec) for x in _stmts(s))


def _action(state: ast.NodeDecl, kind: str) -> ast.Stmt | None:
    if isinstance(state, ast.State):
        for m in state.members:
            if isinstance(m, ast.StateAction) and m.kind == kind:
                return m.stmt
    return None


def _always_enabled(t: ast.Transition) -> bool:
    return t.trigger is None and t.probability is None and not t.condition_else and (
        t.condition is None or (isinstance(t.condition, ast.BoolLit) and t.condition.value)
    )


# ---------------------------------------------------------------------------- never firing


def _never_firing(scope: MachineScope, tables: Tables, sink: DiagnosticSink) -> set[int]:
    never: set[int] = set()
    for region in _regions(scope):
        for source, ts in _by_source(region).items():
            shadow: ast.Transition | None = None
            for t in ts:
                if shadow is not None:
                    sink.warning(
                        f"transition '{t.name}' can never fire: '{shadow.name}' leaves '{source}' first and is always enabled",
                        t.name_span,
                        Note(f"'{shadow.name}' is declared here; transitions of one source are tried in declaration order", shadow.name_span),
                    )
                    never.add(id(t))
                    continue
                if t.condition is not None and (not _abstract_satisfiable(t.condition) or _exactly_unsatisfiable(t.condition, tables)):
                    sink.warning(f"transition '{t.name}' can never fire: its condition is always false", t.condition.span)
                    never.add(id(t))
                    continue
                if _always_enabled(t):
                    shadow = t
    return never


# ---------------------------------------------------------------------------- reachability


def _unreachable(scope: MachineScope, never: set[int], sink: DiagnosticSink) -> None:
    assert scope.region is not None
    reached: set[int] = set()
    todo: list[tuple[Region, str]] = []

    def enter(region: Region, name: str) -> None:
        node = region.nodes.get(name)
        if node is None or id(node) in reached:
            return
        reached.add(id(node))
        todo.append((region, name))
        child = region.children.get(name)
        if child is not None:
            for i in child.initials():
                enter(child, i.name)

    for i in scope.region.initials():
        enter(scope.region, i.name)
    while todo:
        region, name = todo.pop()
        for t in region.transitions:
            if t.source == name and id(t) not in never:
                enter(region, t.target)
    for region in _regions(scope):
        if region.parent is not None and id(region.owner) not in reached:
            continue  # inside an unreachable composite state: reported once, for the composite
        for name, node in region.nodes.items():
            if isinstance(node, ast.State) and id(node) not in reached:
                sink.warning(f"state '{name}' is unreachable: no path from the initial node enters it", node.name_span)


# ---------------------------------------------------------------------------- guards


class _Leaf:
    """A sub-expression the evaluator treats as a variable, with its candidate values."""

    def __init__(self, key: object, domain: list):
        self.key = key
        self.domain = domain


def _guard_leaves(exprs: Iterable[ast.Expr], tables: Tables) -> dict[object, _Leaf]:
    literals: set[Fraction] = {Fraction(0), Fraction(1), Fraction(2)}
    leaves: dict[object, _Leaf] = {}
    numeric: list[tuple[object, T.Type]] = []

    def visit(e: ast.Expr) -> None:
        if isinstance(e, ast.IntLit):
            literals.add(Fraction(e.value))
            return
        if isinstance(e, ast.RealLit):
            literals.add(Fraction(e.text))
            return
        if isinstance(e, (ast.BoolLit, ast.StringLit)):
            return
        if isinstance(e, ast.Unary) and e.op in ("not", "-"):
            visit(e.operand)
            return
        if isinstance(e, ast.Binary) and e.op in ("/\\", "\\/", "=>", "iff", "==", "!=", "<", "<=", ">", ">=", "+", "-", "*"):
            visit(e.left)
            visit(e.right)
            return
        if isinstance(e, ast.DollarInput):
            leaves.setdefault(("ev", e.event), _Leaf(("ev", e.event), [False, True]))
            if e.predicate is not None:
                leaves.setdefault(("opaque", e.predicate), _Leaf(("opaque", e.predicate), [False, True]))
            return
        if isinstance(e, ast.Name) and isinstance(tables.ref(e), EnumLitSym):
            return
        if isinstance(e, ast.Name):
            value = _const_value(e, tables)
            if value is not None:
                if isinstance(value, Fraction):
                    literals.add(value)
                return
        if isinstance(e, ast.Dollar) and type(tables.ref(e)).__name__ == "EventSym":
            leaves.setdefault(("ev", e.name), _Leaf(("ev", e.name), [False, True]))
            return
        t = tables.type_of(e)
        key = ("leaf", e)
        if key in leaves:
            return
        if t == T.BOOLEAN:
            leaves[key] = _Leaf(key, [False, True])
        elif isinstance(t, T.EnumT):
            leaves[key] = _Leaf(key, list(t.literals))
        elif isinstance(t, T.Given):
            leaves[key] = _Leaf(key, [f"{t.simple}#1", f"{t.simple}#2", f"{t.simple}#3"])
        elif t in T.NUMERIC:
            leaves[key] = _Leaf(key, [])
            numeric.append((key, t))
        else:
            leaves[key] = _Leaf(key, [False, True])  # opaque

    for e in exprs:
        visit(e)
    if not numeric:
        return leaves
    points = sorted(literals)
    candidates = sorted({p + d for p in points for d in (Fraction(-1), Fraction(0), Fraction(1))})
    mids = [(a + b) / 2 for a, b in zip(candidates, candidates[1:])]
    for key, t in numeric:
        if t == T.REAL:
            domain = set(candidates + mids)
        else:
            domain = {c for c in candidates if c.denominator == 1 and (t == T.INT or c >= 0)}
        leaves[key].domain = sorted(domain)
    return leaves


class _Unknown(Exception):
    pass


def _const_value(e: ast.Name, tables: Tables):
    """The value of a constant declared with a literal value (a number, boolean or enumeration
    literal), or None: such a constant is not an unknown of the guard."""
    ref = tables.ref(e)
    if not isinstance(ref, VarSym) or ref.kind != "const" or ref.init is None:
        return None
    init = ref.init
    negate = isinstance(init, ast.Unary) and init.op == "-"
    if negate:
        init = init.operand  # type: ignore[union-attr]
    if isinstance(init, ast.IntLit):
        value = Fraction(init.value)
    elif isinstance(init, ast.RealLit):
        value = Fraction(init.text)
    elif isinstance(init, ast.BoolLit) and not negate:
        return init.value
    elif isinstance(init, ast.Name) and isinstance(tables.ref(init), EnumLitSym) and not negate:
        return tables.ref(init).literal  # type: ignore[union-attr]
    else:
        return None
    return -value if negate else value


def _eval(e: ast.Expr, env: dict, tables: Tables):
    if isinstance(e, ast.BoolLit):
        return e.value
    if isinstance(e, ast.IntLit):
        return Fraction(e.value)
    if isinstance(e, ast.RealLit):
        return Fraction(e.text)
    if isinstance(e, ast.Name):
        ref = tables.ref(e)
        if isinstance(ref, EnumLitSym):
            return ref.literal
        value = _const_value(e, tables)
        if value is not None:
            return value
    if isinstance(e, ast.Dollar) and ("ev", e.name) in env:
        return env[("ev", e.name)]
    if isinstance(e, ast.DollarInput):
        occurred = env[("ev", e.event)]
        if e.predicate is not None:
            return occurred and env[("opaque", e.predicate)]
        return occurred
    if isinstance(e, ast.Unary):
        v = _eval(e.operand, env, tables)
        return (not v) if e.op == "not" else -v
    if isinstance(e, ast.Binary):
        op = e.op
        if op == "/\\":
            return _eval(e.left, env, tables) and _eval(e.right, env, tables)
        if op == "\\/":
            return _eval(e.left, env, tables) or _eval(e.right, env, tables)
        if op == "=>":
            return (not _eval(e.left, env, tables)) or _eval(e.right, env, tables)
        if op == "iff":
            return _eval(e.left, env, tables) == _eval(e.right, env, tables)
        a, b = _eval(e.left, env, tables), _eval(e.right, env, tables)
        if op == "==":
            return a == b
        if op == "!=":
            return a != b
        if not isinstance(a, Fraction) or not isinstance(b, Fraction):
            raise _Unknown
        return {"<": a < b, "<=": a <= b, ">": a > b, ">=": a >= b, "+": a + b, "-": a - b, "*": a * b}[op]
    key = ("leaf", e)
    if key in env:
        return env[key]
    raise _Unknown


def _assignments(leaves: dict[object, _Leaf]) -> Iterator[dict]:
    keys = list(leaves)
    total = 1
    for k in keys:
        total *= max(1, len(leaves[k].domain))
        if total > _MAX_ASSIGNMENTS:
            raise _Unknown
    for values in itertools.product(*(leaves[k].domain for k in keys)):
        yield dict(zip(keys, values))


def _abstract_satisfiable(g: ast.Expr) -> bool:
    """Is ``g`` satisfiable when every comparison/atom is a free proposition? (sound 'no')"""
    atoms: dict[object, None] = {}

    def norm(e: ast.Expr):
        """A key for an atom and whether it is negated: a > b is not (a <= b)."""
        if isinstance(e, ast.Binary) and e.op in (">", ">="):
            return ("cmp", "<=" if e.op == ">" else "<", e.left, e.right), e.op == ">"
        if isinstance(e, ast.Binary) and e.op == "!=":
            return ("cmp", "==", e.left, e.right), True
        if isinstance(e, ast.Binary) and e.op in ("<", "<=", "=="):
            return ("cmp", e.op, e.left, e.right), False
        if isinstance(e, ast.DollarInput):
            return ("ev", e.event, e.predicate), False
        return ("atom", e), False

    def collect(e: ast.Expr) -> None:
        if isinstance(e, ast.BoolLit):
            return
        if isinstance(e, ast.Unary) and e.op == "not":
            collect(e.operand)
        elif isinstance(e, ast.Binary) and e.op in ("/\\", "\\/", "=>", "iff"):
            collect(e.left)
            collect(e.right)
        else:
            atoms[norm(e)[0]] = None

    def ev(e: ast.Expr, env: dict) -> bool:
        if isinstance(e, ast.BoolLit):
            return e.value
        if isinstance(e, ast.Unary) and e.op == "not":
            return not ev(e.operand, env)
        if isinstance(e, ast.Binary) and e.op in ("/\\", "\\/", "=>", "iff"):
            a, b = ev(e.left, env), ev(e.right, env)
            return {"/\\": a and b, "\\/": a or b, "=>": (not a) or b, "iff": a == b}[e.op]
        key, negated = norm(e)
        return env[key] != negated

    collect(g)
    keys = list(atoms)
    if len(keys) > 12 or _rebinds(g):
        return True
    return any(ev(g, dict(zip(keys, values))) for values in itertools.product((False, True), repeat=len(keys)))


_ORDER = ("<", "<=", ">", ">=")
_LOGIC = ("/\\", "\\/", "=>", "iff")
_EXACT_LIMIT = 512


def _numeric_constant(e: ast.Expr, tables: Tables) -> bool:
    if isinstance(e, ast.Unary) and e.op == "-":
        return _numeric_constant(e.operand, tables)
    if isinstance(e, ast.Name):
        return isinstance(_const_value(e, tables), Fraction)
    return isinstance(e, (ast.IntLit, ast.RealLit))


def _exactly_unsatisfiable(g: ast.Expr, tables: Tables) -> bool:
    """Is ``g`` false for every value of its leaves? Decided by evaluating it over the leaves'
    sample domains, which is exhaustive only when each comparison of numbers sets a leaf
    against a number literal (the samples then meet every interval the literals delimit), so
    the check declines any other guard."""

    def exact(e: ast.Expr) -> bool:
        if isinstance(e, ast.BoolLit):
            return True
        if isinstance(e, ast.Unary) and e.op == "not":
            return exact(e.operand)
        if isinstance(e, ast.Binary) and e.op in _LOGIC:
            return exact(e.left) and exact(e.right)
        if isinstance(e, ast.Binary) and (e.op in _ORDER or (e.op in ("==", "!=") and tables.type_of(e.left) in T.NUMERIC)):
            return any(_numeric_constant(a, tables) and _plain_leaf(b) for a, b in ((e.left, e.right), (e.right, e.left)))
        if isinstance(e, ast.Binary) and e.op in ("==", "!="):
            return _plain_leaf(e.left) and _plain_leaf(e.right) and not isinstance(tables.type_of(e.left), T.Given)
        return _plain_leaf(e)

    if not exact(g) or _rebinds(g):
        return False
    try:
        leaves = _guard_leaves([g], tables)
        total = 1
        for leaf in leaves.values():
            total *= max(1, len(leaf.domain))
        if total > _EXACT_LIMIT:
            return False
        return not any(_eval(g, env, tables) is True for env in _assignments(leaves))
    except _Unknown:
        return False


def _rebinds(g: ast.Expr) -> bool:
    """Does ``g`` bind a variable with `$e?x` that it also reads? Then `x` has one value before
    the binding and another after it (guards bind as they are evaluated, left to right), and
    analyses that give each leaf one value do not apply."""
    bound: set[str] = set()
    names: list[str] = []

    def visit(e: ast.Expr) -> None:
        if isinstance(e, ast.DollarInput):
            bound.add(e.var)
            if e.predicate is not None:
                visit(e.predicate)
        elif isinstance(e, ast.Name):
            names.append(e.last)
        elif isinstance(e, ast.Unary):
            visit(e.operand)
        elif isinstance(e, ast.Binary):
            visit(e.left)
            visit(e.right)

    visit(g)
    return bool(bound) and any(n in bound for n in names)


def _plain_leaf(e: ast.Expr) -> bool:
    """A sub-expression the evaluator takes as one unknown value (or a literal)."""
    return not isinstance(e, (ast.Binary, ast.Unary, ast.IfExpr, ast.Let, ast.Binder))


def _witness(g1: ast.Expr | None, g2: ast.Expr | None, tables: Tables) -> dict | None:
    exprs = [g for g in (g1, g2) if g is not None]
    try:
        leaves = _guard_leaves(exprs, tables)
        for env in _assignments(leaves):
            try:
                if all(_eval(g, env, tables) is True for g in exprs):
                    return env
            except _Unknown:
                return None
    except _Unknown:
        return None
    return None


def _describe_witness(env: dict) -> str:
    parts = []
    for key, value in env.items():
        if key[0] == "ev" and value:
            parts.append(f"${key[1]} occurs")
        elif key[0] == "leaf":
            e = key[1]
            text = _text(e)
            if text is None:
                continue
            if isinstance(value, bool):
                parts.append(f"{text} is {'true' if value else 'false'}")
            elif isinstance(value, Fraction):
                parts.append(f"{text} = {value.numerator if value.denominator == 1 else float(value)}")
            else:
                parts.append(f"{text} = {value}")
    return ", ".join(parts) if parts else "always"


def _text(e: ast.Expr) -> str | None:
    if isinstance(e, ast.Name):
        return e.text
    if isinstance(e, ast.Dollar):
        return f"${e.name}"
    if isinstance(e, ast.Since):
        return f"since({e.clock})"
    if isinstance(e, ast.Field):
        inner = _text(e.obj)
        return f"{inner}.{e.field}" if inner else None
    return None


def _nondeterminism(scope: MachineScope, tables: Tables, never: set[int], sink: DiagnosticSink) -> None:
    for region in _regions(scope):
        for source, ts in _by_source(region).items():
            live = [t for t in ts if id(t) not in never and not t.condition_else and t.probability is None]
            for a, b in itertools.combinations(live, 2):
                if scope.robosim:
                    pass  # every transition of a RoboSim state is tried in the same cycle
                else:
                    ea = a.trigger.event if a.trigger else None
                    eb = b.trigger.event if b.trigger else None
                    if ea != eb:
                        continue
                env = _witness(a.condition, b.condition, tables)
                if env is None:
                    continue
                sink.warning(
                    f"transitions '{a.name}' and '{b.name}' leave '{source}' and can be enabled together "
                    f"(for example when {_describe_witness(env)}); '{a.name}' is taken, as it is declared first",
                    b.name_span,
                    Note(f"'{a.name}' is declared here", a.name_span),
                )


# ---------------------------------------------------------------------------- RoboSim exec


def _flat_graph(scope: MachineScope, never: set[int]):
    """Nodes by identity with their successor edges (transition, target node) and whether being
    in the node runs exec by itself (entry/during action with exec)."""
    succ: dict[int, list[tuple[ast.Transition, int]]] = {}
    nodes: dict[int, tuple[Region, ast.NodeDecl]] = {}
    for region in _regions(scope):
        for name, node in region.nodes.items():
            nodes[id(node)] = (region, node)
            succ.setdefault(id(node), [])

    def entry_target(region: Region, name: str) -> list[int]:
        node = region.nodes.get(name)
        if node is None:
            return []
        return [id(node)]

    for region in _regions(scope):
        for t in region.transitions:
            if id(t) in never or t.source not in region.nodes:
                continue
            src = region.nodes[t.source]
            targets = entry_target(region, t.target)
            sources = [id(src)]
            # transitions of a composite state can fire from any of its inner nodes
            child = region.children.get(t.source)
            if child is not None:
                sources += [id(n) for r in child.walk() for n in r.nodes.values()]
            for s in sources:
                for d in targets:
                    succ[s].append((t, d))
    # entering a composite state enters its initial node
    for region in _regions(scope):
        for name, child in region.children.items():
            node = region.nodes[name]
            for i in child.initials():
                succ[id(node)].append((None, id(i)))  # type: ignore[arg-type]
    return nodes, succ


def _exec_reachability(scope: MachineScope, never: set[int], sink: DiagnosticSink) -> None:
    nodes, succ = _flat_graph(scope, never)
    good: set[int] = set()
    for nid, (region, node) in nodes.items():
        if has_exec(_action(node, "entry")) or has_exec(_action(node, "during")):
            good.add(nid)
        for t, _ in succ[nid]:
            if t is not None and (t.exec or has_exec(t.action)):
                good.add(nid)
    if scope.is_operation:
        for nid, (region, node) in nodes.items():
            if isinstance(node, ast.Final):
                good.add(nid)  # an operation may end without exec: its caller goes on
    changed = True
    while changed:
        changed = False
        for nid in nodes:
            if nid not in good and any(d in good for _, d in succ[nid]):
                good.add(nid)
                changed = True
    for nid, (region, node) in nodes.items():
        if isinstance(node, ast.State) and nid not in good:
            sink.warning(
                f"no path from state '{node.name}' reaches exec: a cycle that enters it may never end",
                node.name_span,
                Note("every RoboSim cycle ends at an exec transition or an exec statement"),
            )


def _exec_free_cycles(scope: MachineScope, never: set[int], sink: DiagnosticSink) -> None:
    nodes, succ = _flat_graph(scope, never)
    runs_exec = {nid for nid, (_, node) in nodes.items() if has_exec(_action(node, "entry")) or has_exec(_action(node, "during"))}
    edges: dict[int, list[tuple[ast.Transition | None, int]]] = {
        nid: [(t, d) for t, d in succ[nid] if (t is None or not (t.exec or has_exec(t.action))) and d not in runs_exec]
        for nid in nodes
    }
    # Tarjan's strongly connected components
    index: dict[int, int] = {}
    low: dict[int, int] = {}
    stack: list[int] = []
    on: set[int] = set()
    sccs: list[list[int]] = []
    counter = [0]

    def strong(v: int) -> None:
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for _, w in edges[v]:
            if w not in index:
                strong(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            sccs.append(comp)

    for v in nodes:
        if v not in index:
            strong(v)
    for comp in sccs:
        members = set(comp)
        inner = [t for v in comp for t, w in edges[v] if w in members and t is not None]
        if not inner:
            continue
        names = sorted({t.name for t in inner})
        first = min(inner, key=lambda t: (t.span.line, t.span.column) if t.span else (0, 0))
        sink.warning(
            "transitions " + ", ".join(f"'{n}'" for n in names) + " form a cycle without exec: a cycle that takes them may never end",
            first.name_span,
            Note("robogen stops such a cycle after a bound and reports an error at run time"),
        )


__all__ = ["analyse_machine", "has_exec"]
