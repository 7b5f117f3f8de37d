"""The resolved semantic model: what the checker hands to later stages.

:func:`robogen.semantics.check` returns a :class:`SemanticModel`, a finished product: every
value in it is frozen once the checker returns, and nothing in it refers back to the checker.
Later stages (IR lowering, diagrams) read only this module and :mod:`robogen.semantics.types`.

- :class:`MachineScope`: each state machine and software operation with what its body can name
  (variables, constants, clocks, events, operations, each a symbol with a resolved type), its
  region tree (nodes and transitions), its cycle period, and the software operation definitions
  visible from its file;
- :class:`Controller` and :class:`Module`: the containers with their parts, connections,
  events and periods; a module's :class:`Platform` with its events and operations;
- the model's tables: the type of every expression and resolved type expression, the symbol
  every name resolves to (``type_of``, ``symbol``, ``bound_var``, ``scope_of``), the comparisons
  the operands' types decide (``constant_comparison``);
- what bodies do, known in one place for every stage: the walk over a body's triggers and
  statements (:meth:`MachineScope.body`, :func:`statements`, ``communications``), and which
  software operation a call runs (``operation_called``).

New constructs extend this vocabulary (a symbol kind, a field of a container) rather than
giving later stages a way back into the checker.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from types import MappingProxyType
from typing import Callable, Iterator, Mapping

from robogen.diagnostics import Diagnostic, Span
from robogen.semantics.types import UNKNOWN, Type
from robogen.syntax import ast
from robogen.syntax.printer import communication as _communication_text
from robogen.syntax.printer import expr as _expr_text

_EMPTY: Mapping = MappingProxyType({})


def _empty():
    """A field whose default is the empty read-only mapping."""
    return field(default_factory=lambda: _EMPTY)


# ============================================================================ symbols


@dataclass(frozen=True, eq=False)
class VarSym:
    """A variable, constant, operation parameter, binder or let name, with its resolved type."""

    name: str
    type: Type
    kind: str  # var, const, param, binder, let
    decl: ast.Node | None
    origin: str
    init: ast.Expr | None = None
    shared: bool = False  # declared by an interface (provided by a controller or platform)

    @property
    def assignable(self) -> bool:
        return self.kind == "var"

    @property
    def span(self) -> Span | None:
        return getattr(self.decl, "name_span", None)


# How messages name the kinds of VarSym.
KIND_WORDS = {"var": "variable", "const": "constant", "param": "parameter", "binder": "bound variable", "let": "let-bound name"}


@dataclass(frozen=True, eq=False)
class ClockSym:
    name: str
    decl: ast.Node
    origin: str

    @property
    def span(self) -> Span | None:
        return getattr(self.decl, "name_span", None)

    @property
    def from_interface(self) -> bool:
        """Declared by an interface the container requires (shared with the caller), not by the
        container itself."""
        return self.origin.startswith("interface")


@dataclass(frozen=True, eq=False)
class EventSym:
    name: str
    type: Type | None
    decl: ast.EventDecl
    origin: str
    input: bool = False  # RoboSim: named by the input context (RoboChart: always)
    output: bool = False  # RoboSim: named by the output context (RoboChart: always)
    broadcast: bool = False

    @property
    def span(self) -> Span | None:
        return self.decl.name_span


@dataclass(frozen=True, eq=False)
class OpSym:
    name: str
    params: tuple[tuple[str, Type], ...]
    decl: ast.Node  # OpSig or OperationDef
    origin: str
    platform: bool = False  # RoboSim: called with $op (an output-context operation)

    @property
    def span(self) -> Span | None:
        return getattr(self.decl, "name_span", None)


@dataclass(frozen=True, eq=False)
class FuncSym:
    name: str
    params: tuple[tuple[str, Type], ...]
    result: Type
    decl: ast.FunctionDef | None
    builtin: object | None = None  # toolkit.Builtin (a toolkit function) or toolkit.Extension (robogen's)
    qname: str = ""


@dataclass(frozen=True, eq=False)
class EnumLitSym:
    enum: Type  # EnumT
    literal: str


Symbol = VarSym | ClockSym | EventSym | OpSym | FuncSym | EnumLitSym


# ============================================================================ machines


@dataclass(frozen=True, eq=False)
class Region:
    """A container of nodes: a machine, an operation, or a composite state."""

    owner: ast.Node  # StateMachine, OperationDef or State
    path: tuple[str, ...]  # the composite states from the machine down to this one (() at the top)
    nodes: Mapping[str, ast.NodeDecl] = _empty()
    transitions: tuple[ast.Transition, ...] = ()
    children: Mapping[str, "Region"] = _empty()  # composite states by name

    @property
    def nested(self) -> bool:
        """A composite state's region (not the machine's or operation's own)."""
        return bool(self.path)

    @property
    def description(self) -> str:
        """How messages name the container: state 'S', operation 'o' or state machine 'M'."""
        owner = self.owner
        if isinstance(owner, ast.State):
            return f"state '{owner.name}'"
        if isinstance(owner, ast.OperationDef):
            return f"operation '{owner.name}'"
        return f"state machine '{owner.name}'"  # type: ignore[attr-defined]

    def initials(self) -> list[ast.Initial]:
        return [n for n in self.nodes.values() if isinstance(n, ast.Initial)]

    def walk(self) -> Iterator["Region"]:
        yield self
        for child in self.children.values():
            yield from child.walk()


@dataclass(frozen=True, eq=False)
class MachineScope:
    """What the body of a state machine or operation (or the initialisers of a container's
    variables, or a function's contract) can name, and the machine's structure."""

    node: ast.Node  # StateMachine or OperationDef (a container or a function for their checks)
    file: ast.File
    qname: str
    vars: Mapping[str, VarSym] = _empty()
    clocks: Mapping[str, ClockSym] = _empty()
    events: Mapping[str, EventSym] = _empty()
    ops: Mapping[str, OpSym] = _empty()
    region: Region | None = None
    cycle_defs: tuple[ast.CycleDef, ...] = ()
    interfaces: tuple[tuple[str, ast.InterfaceRef, ast.Interface | None], ...] = ()
    period: Fraction | None = None  # RoboSim: the cycle period its cycleDef declares
    # required operations that have a software definition visible from the file (its package,
    # imports, files without a package): name -> definition (see SemanticModel.scope_of)
    definitions: Mapping[str, ast.OperationDef] = _empty()

    @property
    def name(self) -> str:
        return self.node.name  # type: ignore[attr-defined]

    @property
    def language(self) -> str:
        return self.file.language

    @property
    def robosim(self) -> bool:
        return self.file.language == "robosim"

    @property
    def is_operation(self) -> bool:
        return isinstance(self.node, ast.OperationDef)

    @property
    def is_machine(self) -> bool:
        return isinstance(self.node, ast.StateMachine)

    @property
    def kind(self) -> str:
        return "operation" if self.is_operation else "state machine"

    def all_states(self) -> Iterator[tuple[tuple[str, ...], ast.NodeDecl]]:
        """Every node with its path from the machine: ('Outer', 'Inner')."""
        assert self.region is not None
        for region in self.region.walk():
            for name, node in region.nodes.items():
                yield region.path + (name,), node

    def body(self) -> Iterator[ast.Communication | ast.Stmt]:
        """What the body does, in declaration order, region by region: each transition's trigger
        and every statement of its action, then every statement of each node's entry, during and
        exit actions (statements inside sequences, conditionals and deadlines included, see
        :func:`statements`). Nothing for a body without nodes."""
        if self.region is None:
            return
        for region in self.region.walk():
            for t in region.transitions:
                if t.trigger is not None:
                    yield t.trigger
                yield from statements(t.action)
            for node in region.nodes.values():
                for m in getattr(node, "members", ()):
                    if isinstance(m, ast.StateAction):
                        yield from statements(m.stmt)

    def communications(self) -> Iterator["EventUse"]:
        """The RoboChart communications of the body, in the order of :meth:`body`: a trigger (``e``,
        ``e?x``) is an input; in an action, ``e?x`` is an input and ``e``, ``e!v``, ``e.v`` are
        outputs. (A RoboSim machine's ``$`` forms have the directions its contexts declare.)"""
        for x in self.body():
            use = communication_of(x)
            if use is not None:
                yield use

    def calls(self) -> Iterator[ast.CallStmt | ast.DollarCall]:
        """The operation calls of the body (``op(a)``, RoboSim's ``$op(a)``), in the order of :meth:`body`."""
        for x in self.body():
            if isinstance(x, (ast.CallStmt, ast.DollarCall)):
                yield x


IN, OUT = "in", "out"


@dataclass(frozen=True)
class EventUse:
    """One communication of a body (see :meth:`MachineScope.communications`)."""

    event: str  # the event's name, as the body declares it (MachineScope.events)
    direction: str  # IN or OUT
    node: ast.Communication | ast.Communicate  # the trigger, or the statement


def communication_of(x: ast.Communication | ast.Stmt) -> EventUse | None:
    """The communication that a trigger or a statement of a body is, if it is one (see
    :meth:`MachineScope.communications`)."""
    if isinstance(x, ast.Communication):
        return EventUse(x.event, IN if x.kind in ("", "?") else OUT, x)
    if isinstance(x, ast.Communicate):
        return EventUse(x.comm.event, IN if x.comm.kind == "?" else OUT, x)
    return None


def statements(s: ast.Stmt | None) -> Iterator[ast.Stmt]:
    """``s`` and every statement inside it, in textual order (through sequences, conditionals and
    deadlines ``S <{ d }``); nothing for None. A loop, not a recursion."""
    todo = [s] if s is not None else []
    while todo:
        x = todo.pop()
        yield x
        if isinstance(x, ast.Seq):
            todo.extend(reversed(x.stmts))
        elif isinstance(x, ast.IfStmt):
            todo.extend(y for y in (x.otherwise, x.then) if y is not None)
        elif isinstance(x, ast.StmtDeadline):
            todo.append(x.stmt)


def state_action(node: ast.Node, kind: str) -> ast.Stmt | None:
    """The ``entry``, ``during`` or ``exit`` action of a state, if it has one."""
    for m in getattr(node, "members", ()):
        if isinstance(m, ast.StateAction) and m.kind == kind:
            return m.stmt
    return None


# ============================================================================ containers


@dataclass(frozen=True, eq=False)
class Platform:
    """A module's robotic platform, declared inline or referenced (rref)."""

    name: str  # the name connections use (the rref name or the inline platform's name)
    node: ast.Platform
    file: ast.File
    events: Mapping[str, EventSym] = _empty()  # its own and those of the interfaces it uses
    operations: Mapping[str, OpSym] = _empty()  # its own and those of the interfaces it provides


@dataclass(frozen=True, eq=False)
class Controller:
    node: ast.Controller
    file: ast.File
    qname: str
    machines: tuple[tuple[str, MachineScope], ...] = ()  # (name used in the controller, machine)
    operations: tuple[tuple[str, MachineScope], ...] = ()  # (name used, definition): opref or inline
    events: Mapping[str, EventSym] = _empty()
    connections: tuple[ast.Connection, ...] = ()
    period: Fraction | None = None

    @property
    def name(self) -> str:
        return self.node.name


@dataclass(frozen=True, eq=False)
class Module:
    node: ast.Module
    file: ast.File
    qname: str
    platform: Platform | None = None
    controllers: tuple[tuple[str, Controller], ...] = ()  # (name used in the module, controller)
    connections: tuple[ast.Connection, ...] = ()
    period: Fraction | None = None  # the one period of every part (RoboSim), if any declares one

    @property
    def name(self) -> str:
        return self.node.name


def called_operation(op: "OpSym | None", caller: MachineScope, controller: Controller | None, module: Module | None,
                     scope_of: Callable[[ast.Node], MachineScope | None]) -> MachineScope | None:
    """The software operation definition that a call of ``op`` in ``caller`` runs, or None when the
    call goes to the robotic platform: an operation of RoboSim's output context (``$op``) or of the
    ``module``'s platform; else the ``controller``'s operation of that name (an inline definition
    or an ``opref``, matched by the name it is used under or its own), else the definition
    visible from the caller's file (its package, its imports, files without a package), never
    an operation of the same name elsewhere in the workspace. ``scope_of`` gives a definition's
    scope. (The one resolution of calls: :meth:`SemanticModel.operation_called` and the checks.)"""
    if op is None or op.platform:
        return None
    if module is not None and module.platform is not None and op.name in module.platform.operations:
        return None
    if controller is not None:
        for used, definition in controller.operations:
            if op.name in (used, definition.name):
                return definition
    visible = caller.definitions.get(op.name)
    return scope_of(visible) if visible is not None else None


# ============================================================================ the model


@dataclass(frozen=True, eq=False)
class Tables:
    """The checker's findings about single AST nodes, keyed by ``id(node)`` (the AST is immutable
    and the model's files keep it alive). Filled while checking; read-only afterwards."""

    types: dict[int, Type] = field(default_factory=dict)  # expressions
    # id(node) -> symbol; ("bind", id(node)) -> the variable a $e?x or e?x binds
    refs: dict[object, object] = field(default_factory=dict)
    # resolved type expressions: id(node) -> (node, type); the node is held so its id stays unique
    type_exprs: dict[int, tuple[ast.TypeExpr, Type]] = field(default_factory=dict)
    # comparisons whose value the operands' types decide: id(node) -> value (robogen.semantics.limits)
    comparisons: dict[int, bool] = field(default_factory=dict)
    # the enumerations and records declared, by qualified name, in full: inside a recursive one
    # the checker refers to it by a stand-in without literals' arguments or fields
    declared: dict[str, Type] = field(default_factory=dict)

    def type_of(self, e: ast.Expr) -> Type:
        return self.types.get(id(e), UNKNOWN)

    def ref(self, node: ast.Node):
        return self.refs.get(id(node))

    def bound_var(self, node: ast.Node):
        return self.refs.get(("bind", id(node)))

    def sender_var(self, node: ast.Node):
        return self.refs.get(("from", id(node)))


@dataclass(frozen=True, eq=False)
class SemanticModel:
    """A checked workspace. ``diagnostics`` holds every problem found, in source order; the rest
    is meaningful where no error was reported."""

    files: tuple[ast.File, ...]
    root: str  # the workspace root: the common folder of the paths robogen was given
    diagnostics: tuple[Diagnostic, ...]
    scopes: tuple[MachineScope, ...]  # every state machine and operation definition
    controllers: tuple[Controller, ...]
    modules: tuple[Module, ...]
    tables: Tables = field(repr=False, default_factory=Tables)
    _by_node: dict[int, MachineScope] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "_by_node", {id(s.node): s for s in self.scopes})

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.is_error]

    @property
    def warnings(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if not d.is_error]

    @property
    def machines(self) -> list[MachineScope]:
        return [s for s in self.scopes if s.is_machine]

    def scope_of(self, node: ast.Node) -> MachineScope | None:
        """The scope of a state machine or operation definition node."""
        return self._by_node.get(id(node))

    def type_of(self, node: ast.Expr | ast.TypeExpr) -> Type:
        """The type of an expression, or the type a type expression resolves to."""
        entry = self.tables.type_exprs.get(id(node))
        if entry is not None and entry[0] is node:
            return entry[1]
        return self.tables.type_of(node)  # type: ignore[arg-type]

    def symbol(self, node: ast.Node):
        """The symbol a name (or communication, $-statement, clock reset) resolves to."""
        return self.tables.ref(node)

    def bound_var(self, node: ast.Node) -> VarSym | None:
        """The variable an input ``e?x`` or ``$e?x`` stores the event's value in."""
        return self.tables.bound_var(node)

    def sender_var(self, node: ast.Communication) -> VarSym | None:
        """The variable a filter ``e[| x = from |]`` stores the sender in."""
        return self.tables.sender_var(node)

    def communications(self, body: MachineScope) -> Iterator[EventUse]:
        """The RoboChart communications of a machine's or operation's body, each with its event,
        its direction (IN or OUT) and its trigger or statement (:meth:`MachineScope.communications`)."""
        return body.communications()

    def operation_called(self, call: ast.CallStmt | ast.DollarCall, caller: MachineScope,
                         controller: Controller | None = None, module: Module | None = None) -> MachineScope | None:
        """The software operation definition a call statement of ``caller`` runs inside
        ``controller`` (and ``module``), or None when the robotic platform performs it (see
        :func:`called_operation`)."""
        op = self.symbol(call.call.func if isinstance(call, ast.CallStmt) else call)
        return called_operation(op if isinstance(op, OpSym) else None, caller, controller, module, self.scope_of)

    def constant_comparison(self, e: ast.Binary) -> bool | None:
        """The value of a comparison that its operands' types decide, whatever their values: True
        for ``k >= 0`` and False for ``k < 0`` when ``k`` is a nat (a nat compared with a number
        literal, on either side, where every nat gives one value: ``k > -1``, ``0 > k``, ``k == -2``,
        ...; see :mod:`robogen.semantics.limits`). None for every other expression. The checker
        warned about each; code generation uses the value rather than generate a comparison that
        C compilers flag as always true or false (``-Wtype-limits``)."""
        return self.tables.comparisons.get(id(e))

    @staticmethod
    def text(node: ast.Expr | ast.Communication) -> str:
        """An expression or a communication (a trigger) as model text, for messages and generated
        comments that quote the model."""
        return _communication_text(node) if isinstance(node, ast.Communication) else _expr_text(node)


__all__ = [
    "VarSym", "KIND_WORDS", "ClockSym", "EventSym", "OpSym", "FuncSym", "EnumLitSym", "Symbol",
    "Region", "MachineScope", "IN", "OUT", "EventUse", "communication_of", "statements", "state_action",
    "Platform", "Controller", "Module", "called_operation", "Tables", "SemanticModel",
]
