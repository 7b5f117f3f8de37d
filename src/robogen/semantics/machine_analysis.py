"""Static analyses of one state machine that produce warnings (never errors):

- states no path from the initial node reaches;
- transitions that can never fire (a guard that no assignment satisfies, or an earlier
  transition of the same source that is always enabled and has priority);
- non-determinism: two transitions of one source (same trigger) whose guards can hold together,
  reported only with a concrete witness, so the warning is never speculative;
- RoboSim: states from which no path reaches ``exec``, and cycles of transitions without ``exec``.

Guards are evaluated by :mod:`robogen.semantics.guards` over small sample domains. "Never
fires" is claimed when an abstraction in which every comparison is an independent proposition
is unsatisfiable (an over-approximation: then so is the guard), or when the sampling is
exhaustive for the guard and no sample satisfies it.
"""

from __future__ import annotations

import itertools
from typing import Iterator

from robogen.diagnostics import DiagnosticSink, Note
from robogen.semantics.guards import Guards, number
from robogen.semantics.model import MachineScope, Region, Tables, state_action, statements
from robogen.syntax import ast


def analyse_machine(scope: MachineScope, tables: Tables, sink: DiagnosticSink) -> None:
    """Run the analyses, unless the machine has errors: warnings built on a name that did not
    resolve would only repeat, less clearly, what the errors already say."""
    assert scope.region is not None
    if sink.errors and any(_in_machine(d.span, scope) for d in sink.errors):
        return
    guards = Guards(tables, number(scope.period) if scope.period is not None else None)
    never = _never_firing(scope, guards, sink)
    _unreachable(scope, never, sink)
    _nondeterminism(scope, guards, never, sink)
    if scope.robosim:
        graph = _flat_graph(scope, never)
        _exec_reachability(graph, scope.is_operation, sink)
        _exec_free_cycles(graph, sink)


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


def has_exec(s: ast.Stmt | None) -> bool:
    return any(isinstance(x, ast.Exec) for x in statements(s))


def _runs_exec(node: ast.NodeDecl) -> bool:
    """Does being in ``node`` run exec by itself (an entry or during action with exec)?"""
    return has_exec(state_action(node, "entry")) or has_exec(state_action(node, "during"))


def _always_enabled(t: ast.Transition) -> bool:
    return t.trigger is None and t.probability is None and not t.condition_else and (
        t.condition is None or (isinstance(t.condition, ast.BoolLit) and t.condition.value)
    )


# ---------------------------------------------------------------------------- never firing


def _never_firing(scope: MachineScope, guards: Guards, sink: DiagnosticSink) -> set[int]:
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
                if t.condition is not None and guards.never_true(t.condition):
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
    for i in scope.region.initials():
        _enter(scope.region, i.name, reached, todo)
    outgoing = {id(region): _by_source(region) for region in _regions(scope)}
    while todo:
        region, name = todo.pop()
        for t in outgoing[id(region)].get(name, ()):
            if id(t) not in never:
                _enter(region, t.target, reached, todo)
    for region in _regions(scope):
        if region.nested and id(region.owner) not in reached:
            continue  # inside an unreachable composite state: reported once, for the composite
        for name, node in region.nodes.items():
            if isinstance(node, ast.State) and id(node) not in reached:
                sink.warning(f"state '{name}' is unreachable: no path from the initial node enters it", node.name_span)


def _enter(region: Region, name: str, reached: set[int], todo: list[tuple[Region, str]]) -> None:
    """Mark node ``name`` of ``region`` reached (and, for a composite state, the initial nodes
    inside it), queueing each newly reached node in ``todo``."""
    node = region.nodes.get(name)
    if node is None or id(node) in reached:
        return
    reached.add(id(node))
    todo.append((region, name))
    child = region.children.get(name)
    if child is not None:
        for i in child.initials():
            _enter(child, i.name, reached, todo)


def _nondeterminism(scope: MachineScope, guards: Guards, never: set[int], sink: DiagnosticSink) -> None:
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
                env = guards.common_witness(a.condition, b.condition)
                if env is None:
                    continue
                sink.warning(
                    f"transitions '{a.name}' and '{b.name}' leave '{source}' and can be enabled together "
                    f"(for example when {guards.describe(env)}); '{a.name}' is taken, as it is declared first",
                    b.name_span,
                    Note(f"'{a.name}' is declared here", a.name_span),
                )


# ---------------------------------------------------------------------------- RoboSim exec


def _flat_graph(scope: MachineScope, never: set[int]):
    """Nodes by identity with their successor edges (transition, target node), the nodes where
    being runs exec by itself (entry/during action with exec) and the transitions that run exec
    (exec transitions, actions with exec), each found once."""
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
    runs_exec = {nid for nid, (_, node) in nodes.items() if _runs_exec(node)}
    exec_transitions = {id(t) for region in _regions(scope) for t in region.transitions if t.exec or has_exec(t.action)}
    return nodes, succ, runs_exec, exec_transitions


def _exec_reachability(graph, is_operation: bool, sink: DiagnosticSink) -> None:
    nodes, succ, runs_exec, exec_transitions = graph
    good: set[int] = set(runs_exec)
    for nid in nodes:
        for t, _ in succ[nid]:
            if t is not None and id(t) in exec_transitions:
                good.add(nid)
    if is_operation:
        for nid, (region, node) in nodes.items():
            if isinstance(node, ast.Final):
                good.add(nid)  # an operation may end without exec: its caller goes on
    # backwards from the nodes that reach exec by themselves (linear, not a fixpoint over all nodes)
    predecessors: dict[int, list[int]] = {nid: [] for nid in nodes}
    for nid, edges in succ.items():
        for _, d in edges:
            predecessors[d].append(nid)
    todo = list(good)
    while todo:
        for p in predecessors[todo.pop()]:
            if p not in good:
                good.add(p)
                todo.append(p)
    for nid, (region, node) in nodes.items():
        if isinstance(node, ast.State) and nid not in good:
            sink.warning(
                f"no path from state '{node.name}' reaches exec: a cycle that enters it may never end",
                node.name_span,
                Note("every RoboSim cycle ends at an exec transition or an exec statement"),
            )


def _exec_free_cycles(graph, sink: DiagnosticSink) -> None:
    nodes, succ, runs_exec, exec_transitions = graph
    edges: dict[int, list[tuple[ast.Transition | None, int]]] = {
        nid: [(t, d) for t, d in succ[nid] if (t is None or id(t) not in exec_transitions) and d not in runs_exec]
        for nid in nodes
    }
    for comp in _strongly_connected(nodes, edges):
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


def _strongly_connected(nodes, edges: dict[int, list[tuple[ast.Transition | None, int]]]) -> list[list[int]]:
    """Tarjan's strongly connected components, with an explicit stack: a machine may have
    thousands of states in a row, deeper than Python's recursion allows."""
    index: dict[int, int] = {}
    low: dict[int, int] = {}
    stack: list[int] = []
    on: set[int] = set()
    sccs: list[list[int]] = []
    for root in nodes:
        if root in index:
            continue
        index[root] = low[root] = len(index)
        stack.append(root)
        on.add(root)
        work = [(root, 0)]  # (node, position of its next edge)
        while work:
            v, i = work[-1]
            out = edges[v]
            if i < len(out):
                work[-1] = (v, i + 1)
                w = out[i][1]
                if w not in index:
                    index[w] = low[w] = len(index)
                    stack.append(w)
                    on.add(w)
                    work.append((w, 0))
                elif w in on:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[v])
            if low[v] == index[v]:
                component = []
                while True:
                    w = stack.pop()
                    on.discard(w)
                    component.append(w)
                    if w == v:
                        break
                sccs.append(component)
    return sccs


__all__ = ["analyse_machine", "has_exec"]
