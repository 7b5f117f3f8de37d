"""The region tree being lowered: a machine's body, or a software operation inlined at one call
site (each call site gets its own nodes, variables and clocks)."""

from __future__ import annotations

from dataclasses import dataclass, field

from robogen.ir import model as ir
from robogen.semantics.model import MachineScope, Region
from robogen.syntax import ast


@dataclass
class Graph:
    """One region tree being lowered. Names resolve first in ``env`` (the call site's parameters
    and locals), then in the machine's variables."""

    scope: MachineScope
    prefix: tuple[str, ...]  # node path prefix (empty for the machine)
    env: dict[str, ir.Var]
    clocks: dict[str, int]  # clock name -> index in the machine's clock list
    exit_block: int | None  # operations: where control goes when the final node is reached
    regions: dict[int, Region] = field(default_factory=dict)  # id(owner node) -> region
    node_ids: dict[int, int] = field(default_factory=dict)  # id(ast node) -> ir node id
    parent: dict[int, ast.Node | None] = field(default_factory=dict)  # id(ast node) -> enclosing state


def state_action(state: ast.Node, kind: str) -> ast.Stmt | None:
    """The entry, during or exit action of a state, if it has one."""
    for m in getattr(state, "members", ()):
        if isinstance(m, ast.StateAction) and m.kind == kind:
            return m.stmt
    return None


def place_of(node: ast.Node) -> ir.At:
    """The place of a model element in a run-time message: its name, or the whole element."""
    return ir.At(getattr(node, "name_span", None) or node.span)


__all__ = ["Graph", "state_action", "place_of"]
