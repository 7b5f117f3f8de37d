"""The abstract syntax of RoboChart and RoboSim models.

Frozen dataclasses. Every node carries a ``span`` (and named declarations a ``name_span``) that
equality and hashing ignore, so tests compare hand-built trees with ``==``. Lark's trees never
leave :mod:`robogen.syntax`; everything later in the pipeline sees only these classes.

Members of containers (interfaces, machines, states, ...) are kept as one tuple in source order;
the ``members_of`` helpers select them by class.
"""

from __future__ import annotations

from dataclasses import MISSING, dataclass, field, fields, is_dataclass
from typing import Container, Iterator, TypeVar

from robogen.diagnostics import Span

T = TypeVar("T")


def _span() -> Span | None:
    return field(default=None, compare=False, hash=False, repr=False, kw_only=True)  # type: ignore[return-value]


@dataclass(frozen=True, slots=True)
class Node:
    span: Span | None = _span()


@dataclass(frozen=True, slots=True)
class Named(Node):
    name: str
    name_span: Span | None = _span()


def members_of(members: tuple, cls: type[T]) -> Iterator[T]:
    return (m for m in members if isinstance(m, cls))


# ============================================================================ types


@dataclass(frozen=True, slots=True)
class TypeExpr(Node):
    pass


@dataclass(frozen=True, slots=True)
class TypeRef(TypeExpr):
    name: "Name"


@dataclass(frozen=True, slots=True)
class SetType(TypeExpr):
    element: TypeExpr


@dataclass(frozen=True, slots=True)
class SeqType(TypeExpr):
    element: TypeExpr


@dataclass(frozen=True, slots=True)
class ProductType(TypeExpr):
    items: tuple[TypeExpr, ...]


@dataclass(frozen=True, slots=True)
class FunctionType(TypeExpr):
    domain: TypeExpr
    range: TypeExpr


@dataclass(frozen=True, slots=True)
class RelationType(TypeExpr):
    domain: TypeExpr
    range: TypeExpr


@dataclass(frozen=True, slots=True)
class TypeVar_(TypeExpr):
    """A type variable ``?X`` of the generic toolkit functions."""

    name: str


@dataclass(frozen=True, slots=True)
class VectorType(TypeExpr):
    element: TypeExpr
    size: "Expr"


@dataclass(frozen=True, slots=True)
class MatrixType(TypeExpr):
    element: TypeExpr
    rows: "Expr"
    columns: "Expr"


# ============================================================================ expressions


@dataclass(frozen=True, slots=True)
class Expr(Node):
    pass


@dataclass(frozen=True, slots=True)
class IntLit(Expr):
    value: int


@dataclass(frozen=True, slots=True)
class RealLit(Expr):
    text: str  # as written, e.g. "0.5"; exact for code generation

    @property
    def value(self) -> float:
        return float(self.text)


@dataclass(frozen=True, slots=True)
class BoolLit(Expr):
    value: bool


@dataclass(frozen=True, slots=True)
class StringLit(Expr):
    value: str


@dataclass(frozen=True, slots=True)
class Name(Expr):
    """A (possibly package-qualified) name: ``x``, ``Position::left``, ``pkg::Stm``."""

    parts: tuple[str, ...]

    @property
    def text(self) -> str:
        return "::".join(self.parts)

    @property
    def last(self) -> str:
        return self.parts[-1]

    @property
    def qualified(self) -> bool:
        return len(self.parts) > 1


@dataclass(frozen=True, slots=True)
class Keyword(Expr):
    """``result`` (postconditions), ``from``/``to`` (filters), ``cycle`` (RoboSim period)."""

    word: str


@dataclass(frozen=True, slots=True)
class Unary(Expr):
    op: str  # "-" or "not"
    operand: Expr


@dataclass(frozen=True, slots=True)
class Binary(Expr):
    """Infix operators: iff => \\/ /\\ == != < <= > >= in + - * / % cat ^."""

    op: str
    left: Expr
    right: Expr


def chain(e: Expr, ops: Container[str] | None = None) -> tuple[Expr, list[Binary]]:
    """A left-nested chain of binary operators, as a loop can walk it: the leftmost operand and the
    binary nodes from the innermost out. ``a + b * c - d`` is ``(a, [a + b * c, ... - d])``: each
    node's left operand is the one before it (the first node's is ``a``), and the value of the
    chain is built by combining, node by node, with its right operand. The chain follows left
    operands while they are binary nodes (of ``ops``, if given), parenthesised ones included.

    Every binary operator associates to the left, so a flat expression of thousands of operands
    is a chain thousands deep: stages walk it with this, never by recursion (the parser counts
    such a chain as one level of nesting, see robogen.syntax.transform_base.MAX_NESTING)."""
    links: list[Binary] = []
    while isinstance(e, Binary) and (ops is None or e.op in ops):
        links.append(e)
        e = e.left
    links.reverse()
    return e, links


@dataclass(frozen=True, slots=True)
class Field(Expr):
    obj: Expr
    field: str
    field_span: Span | None = _span()


@dataclass(frozen=True, slots=True)
class Index(Expr):
    obj: Expr
    indices: tuple[Expr, ...]


@dataclass(frozen=True, slots=True)
class Call(Expr):
    func: Expr
    args: tuple[Expr, ...]


@dataclass(frozen=True, slots=True)
class IfExpr(Expr):
    cond: Expr
    then: Expr
    otherwise: Expr


@dataclass(frozen=True, slots=True)
class Cast(Expr):
    op: str  # "as" or "is"
    expr: Expr
    type: TypeExpr


@dataclass(frozen=True, slots=True)
class Decl(Named):
    """A bound variable of a binder or comprehension: ``x: T``."""

    type: TypeExpr


@dataclass(frozen=True, slots=True)
class Binder(Expr):
    kind: str  # forall exists exists1 lambda the
    decls: tuple[Decl, ...]
    such_that: Expr | None
    body: Expr


@dataclass(frozen=True, slots=True)
class LetDef(Named):
    value: Expr


@dataclass(frozen=True, slots=True)
class Let(Expr):
    defs: tuple[LetDef, ...]
    body: Expr


@dataclass(frozen=True, slots=True)
class FieldValue(Named):
    value: Expr


@dataclass(frozen=True, slots=True)
class RecordLit(Expr):
    type: Name
    fields: tuple[FieldValue, ...]


@dataclass(frozen=True, slots=True)
class TupleLit(Expr):
    items: tuple[Expr, ...]


@dataclass(frozen=True, slots=True)
class SeqLit(Expr):
    items: tuple[Expr, ...]


@dataclass(frozen=True, slots=True)
class SetLit(Expr):
    items: tuple[Expr, ...]


@dataclass(frozen=True, slots=True)
class SetRange(Expr):
    """``{ a to b }``"""

    low: Expr
    high: Expr


@dataclass(frozen=True, slots=True)
class SetComprehension(Expr):
    decls: tuple[Decl, ...]
    such_that: Expr | None
    body: Expr | None


@dataclass(frozen=True, slots=True)
class Range(Expr):
    """``[a, b]``, ``[a, b)``, ``(a, b]``, ``(a, b)``"""

    low: Expr
    high: Expr
    low_closed: bool
    high_closed: bool


@dataclass(frozen=True, slots=True)
class VectorLit(Expr):
    """``[| 1, 2 |]`` (one row) or ``[| 1, 2; 3, 4 |]`` (a matrix)."""

    rows: tuple[tuple[Expr, ...], ...]


@dataclass(frozen=True, slots=True)
class Since(Expr):
    clock: str
    clock_span: Span | None = _span()


@dataclass(frozen=True, slots=True)
class SinceEntry(Expr):
    state: Name


@dataclass(frozen=True, slots=True)
class MatrixOp(Expr):
    op: str  # inverse, transpose
    operand: Expr


@dataclass(frozen=True, slots=True)
class Dollar(Expr):
    """RoboSim ``$e`` (input event occurred) or ``$x`` (platform/shared variable value).

    ``name`` is the simple name; ``qualifier`` the parts written before it (``$I::x``), which
    name the interface or machine that declares it. The other ``$`` forms do the same."""

    name: str
    qualifier: tuple[str, ...] = ()
    name_span: Span | None = _span()


@dataclass(frozen=True, slots=True)
class DollarInput(Expr):
    """RoboSim ``$e?x`` or ``$e?x : p``: ``e`` occurred; its value is bound to ``x``."""

    event: str
    var: str
    predicate: Expr | None
    qualifier: tuple[str, ...] = ()
    var_qualifier: tuple[str, ...] = ()
    event_span: Span | None = _span()
    var_span: Span | None = _span()


@dataclass(frozen=True, slots=True)
class DollarValue(Expr):
    """RoboSim ``$e.v``: ``e`` occurred with value ``v``; for a variable ``$r.f``, field ``f`` of ``r``."""

    event: str
    value: Expr
    qualifier: tuple[str, ...] = ()
    event_span: Span | None = _span()


# ============================================================================ statements


@dataclass(frozen=True, slots=True)
class Stmt(Node):
    pass


@dataclass(frozen=True, slots=True)
class Skip(Stmt):
    pass


@dataclass(frozen=True, slots=True)
class Exec(Stmt):
    pass


@dataclass(frozen=True, slots=True)
class Wait(Stmt):
    duration: Expr


@dataclass(frozen=True, slots=True)
class ClockReset(Stmt):
    clock: str
    clock_span: Span | None = _span()


@dataclass(frozen=True, slots=True)
class Seq(Stmt):
    stmts: tuple[Stmt, ...]


@dataclass(frozen=True, slots=True)
class IfStmt(Stmt):
    cond: Expr
    then: Stmt
    otherwise: Stmt | None


@dataclass(frozen=True, slots=True)
class Assign(Stmt):
    target: Expr  # Name, Field or Index
    value: Expr


@dataclass(frozen=True, slots=True)
class CallStmt(Stmt):
    call: Call


@dataclass(frozen=True, slots=True)
class Filter(Node):
    """``[| x = e | p |]``, ``[| x = e |]``, ``[| p |]`` or ``[||]`` on a communication."""

    bind: str | None
    bind_value: Expr | None
    predicate: Expr | None


@dataclass(frozen=True, slots=True)
class Communication(Node):
    """``e``, ``e?x``, ``e!v`` or ``e.v`` (kind "", "?", "!", "."), as trigger or statement.
    ``var_qualifier`` holds the parts written before the variable of ``e?P::x``."""

    event: str
    kind: str = ""
    var: str | None = None
    value: Expr | None = None
    filter: Filter | None = None
    var_qualifier: tuple[str, ...] = ()
    event_span: Span | None = _span()
    var_span: Span | None = _span()


@dataclass(frozen=True, slots=True)
class Communicate(Stmt):
    comm: Communication
    send: bool  # written with the `send` keyword


@dataclass(frozen=True, slots=True)
class StmtDeadline(Stmt):
    stmt: Stmt
    bound: Expr


@dataclass(frozen=True, slots=True)
class DollarOutput(Stmt):
    """RoboSim ``$e``, ``$e!v``, ``$e.v`` as a statement: register output event ``e``."""

    event: str
    kind: str  # "", "!" or "."
    value: Expr | None
    qualifier: tuple[str, ...] = ()
    event_span: Span | None = _span()


@dataclass(frozen=True, slots=True)
class DollarCall(Stmt):
    """RoboSim ``$op(args)``: call a platform operation."""

    op: str
    args: tuple[Expr, ...]
    qualifier: tuple[str, ...] = ()
    op_span: Span | None = _span()


@dataclass(frozen=True, slots=True)
class DollarAssign(Stmt):
    """RoboSim ``$x = e``: write a platform/shared variable."""

    var: str
    value: Expr
    qualifier: tuple[str, ...] = ()
    var_span: Span | None = _span()


# ============================================================================ declarations


@dataclass(frozen=True, slots=True)
class Import(Node):
    name: Name
    wildcard: bool


@dataclass(frozen=True, slots=True)
class GivenType(Named):
    pass


@dataclass(frozen=True, slots=True)
class FieldDecl(Named):
    type: TypeExpr


@dataclass(frozen=True, slots=True)
class Record(Named):
    fields: tuple[FieldDecl, ...]


@dataclass(frozen=True, slots=True)
class EnumLiteral(Named):
    args: tuple[TypeExpr, ...] = ()


@dataclass(frozen=True, slots=True)
class Enumeration(Named):
    literals: tuple[EnumLiteral, ...]


@dataclass(frozen=True, slots=True)
class EventDecl(Named):
    type: TypeExpr | None = None
    broadcast: bool = False


@dataclass(frozen=True, slots=True)
class VarDecl(Named):
    type: TypeExpr
    init: Expr | None = None


@dataclass(frozen=True, slots=True)
class VarList(Node):
    const: bool
    vars: tuple[VarDecl, ...]


@dataclass(frozen=True, slots=True)
class ClockDecl(Named):
    pass


@dataclass(frozen=True, slots=True)
class Param(Named):
    type: TypeExpr


@dataclass(frozen=True, slots=True)
class OpSig(Named):
    params: tuple[Param, ...]
    terminates: bool = False


@dataclass(frozen=True, slots=True)
class InterfaceRef(Node):
    kind: str  # uses, provides, requires
    name: Name


@dataclass(frozen=True, slots=True)
class Interface(Named):
    members: tuple[Node, ...]


@dataclass(frozen=True, slots=True)
class Platform(Named):
    members: tuple[Node, ...]


@dataclass(frozen=True, slots=True)
class Reference(Named):
    """``rref p = P``, ``cref c = C``, ``sref s = S``, ``opref o = O``."""

    kind: str
    target: Name


@dataclass(frozen=True, slots=True)
class Connection(Node):
    source: str
    source_event: str
    target: str
    target_event: str
    asynchronous: bool = False
    bidirectional: bool = False  # RoboChart's [ mult ] flag: the connection carries events both ways
    spans: tuple[Span | None, ...] = field(default=(), compare=False, hash=False, repr=False, kw_only=True)
    # spans of source, source_event, target, target_event


@dataclass(frozen=True, slots=True)
class CycleDef(Node):
    expr: Expr


@dataclass(frozen=True, slots=True)
class Context(Node):
    kind: str  # input, output
    members: tuple[Node, ...]


@dataclass(frozen=True, slots=True)
class Controller(Named):
    members: tuple[Node, ...]


@dataclass(frozen=True, slots=True)
class Module(Named):
    members: tuple[Node, ...]


@dataclass(frozen=True, slots=True)
class NodeDecl(Named):
    """A state-machine node: initial, junction, final, probabilistic, or a state."""


@dataclass(frozen=True, slots=True)
class Initial(NodeDecl):
    pass


@dataclass(frozen=True, slots=True)
class Junction(NodeDecl):
    pass


@dataclass(frozen=True, slots=True)
class Final(NodeDecl):
    pass


@dataclass(frozen=True, slots=True)
class Probabilistic(NodeDecl):
    pass


@dataclass(frozen=True, slots=True)
class StateAction(Node):
    kind: str  # entry, during, exit
    stmt: Stmt


@dataclass(frozen=True, slots=True)
class State(NodeDecl):
    members: tuple[Node, ...] = ()


@dataclass(frozen=True, slots=True)
class Transition(Named):
    source: str
    target: str
    trigger: Communication | None = None
    exec: bool = False
    probability: Expr | None = None
    resets: tuple[ClockReset, ...] = ()
    deadline: Expr | None = None
    condition: Expr | None = None
    condition_else: bool = False
    action: Stmt | None = None
    source_span: Span | None = _span()
    target_span: Span | None = _span()


@dataclass(frozen=True, slots=True)
class StateMachine(Named):
    members: tuple[Node, ...]


@dataclass(frozen=True, slots=True)
class Terminates(Node):
    pass


@dataclass(frozen=True, slots=True)
class Precondition(Node):
    expr: Expr


@dataclass(frozen=True, slots=True)
class Postcondition(Node):
    expr: Expr


@dataclass(frozen=True, slots=True)
class OperationDef(Named):
    params: tuple[Param, ...]
    members: tuple[Node, ...]


@dataclass(frozen=True, slots=True)
class FunctionDef(Named):
    params: tuple[Param, ...]
    result: TypeExpr
    members: tuple[Node, ...] = ()


@dataclass(frozen=True, slots=True)
class Diagram(Named):
    pass


@dataclass(frozen=True, slots=True)
class File(Node):
    path: str
    language: str  # "robochart" or "robosim"
    package: Name | None
    imports: tuple[Import, ...]
    items: tuple[Node, ...]
    # warnings about the text (an obsolete form read as its current one: robogen.syntax.transform_obsolete);
    # like spans, not part of the tree's equality
    notices: tuple = field(default=(), compare=False, hash=False, repr=False, kw_only=True)


# Containers whose members are state-machine bodies.
MachineLike = StateMachine | OperationDef


# ============================================================================ construction


def _quick_init(cls: type) -> None:
    """Give a frozen slots dataclass an ``__init__`` with the same signature and effect as the
    generated one, that sets each slot through its member descriptor instead of
    ``object.__setattr__`` with the field's name (the parser builds tens of thousands of nodes
    per large model; this makes each about a third cheaper). Equality, hashing, repr, pickling
    and immutability are the dataclass's, unchanged."""
    if "__slots__" not in cls.__dict__ or not cls.__dataclass_params__.frozen or hasattr(cls, "__post_init__"):
        return
    namespace: dict = {}
    positional, keywords, body = [], [], []
    for f in fields(cls):
        if f.default_factory is not MISSING or not f.init:  # fields() lists neither ClassVars nor InitVars
            return
        namespace[f"_set_{f.name}"] = getattr(cls, f.name).__set__  # the slot's member descriptor
        param = f.name
        if f.default is not MISSING:
            namespace[f"_default_{f.name}"] = f.default
            param += f"=_default_{f.name}"
        (keywords if f.kw_only else positional).append(param)
        body.append(f"    _set_{f.name}(self, {f.name})")
    params = ", ".join(["self", *positional, *(["*", *keywords] if keywords else [])])
    exec(f"def __init__({params}):\n" + "\n".join(body or ["    pass"]), namespace)
    init = namespace["__init__"]
    init.__qualname__ = f"{cls.__qualname__}.__init__"
    init.__module__ = cls.__module__
    init.generated = cls.__init__  # the dataclass's own, which tests compare it with
    cls.__init__ = init  # type: ignore[misc]


for _cls in [c for c in globals().values() if isinstance(c, type) and is_dataclass(c) and c.__module__ == __name__]:
    _quick_init(_cls)
del _cls
