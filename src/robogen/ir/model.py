"""The IR: state machines lowered to control-flow graphs, inside one FMU.

Every state machine becomes a list of basic blocks. A block holds simple statements and ends in
one terminator that says where control goes next:

- ``Goto(b)``: continue at block b;
- ``Suspend(b)``: the cycle (RoboChart: the run to quiescence) ends; it resumes at b next time;
- ``Branch(cases, default)``: guards tried in priority order, the first that holds wins;
- ``Fail(message)``: a deadlock, reported at run time.

A block marked ``step`` starts a transition segment (the exit actions of its source, its action,
the entry into its target). Entering it counts one transition of the cycle (a runaway cycle is
one that counts more than ``Fmu.max_steps``). In stepwise semantics a run stops in front of the
second ``step`` block it reaches, so every ``fmi3UpdateDiscreteStates`` takes exactly one
transition, together with the evaluation of the guards that follow it: the run that enters a
state also finds out whether the state's next transition is an ``exec`` (the cycle ends there,
``discreteStatesNeedUpdate = false``) or another transition (``true``), as
robogen's stepwise semantics asks (README: The two semantics). In exhaustive semantics ``step`` only counts.

That one mechanism expresses RoboSim's exec transitions (decide now, act next cycle), exec
statements in the middle of actions, RoboChart's ``wait(n)`` and quiescence, entry and exit
chains of composite states, and software operations inlined at their call sites. The reference
interpreter (:mod:`robogen.ir.interp`) and the C emitter (:mod:`robogen.codegen`) both execute
the blocks one for one, so they cannot disagree about the semantics.

Types are :mod:`robogen.semantics.types` values in which given types are already replaced by
their concrete scalar type.

Places in the model are spans as the user gave the files; printers name a file relative to the
workspace root (:meth:`Fmu.place`), and run-time messages keep their places apart from their text
(:class:`Text`), so the canonical dump (and the instantiation token hashed from it) holds no path.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Callable

from robogen.diagnostics import Span
from robogen.semantics.types import Type


# ============================================================================ storage


@dataclass(eq=False)
class Var:
    """A memory cell of a machine: a variable, a constant (FMI parameter), an operation
    parameter or local (one per inlined call site)."""

    # the model name, unique within the machine: a variable's own name; 'op#2.x' for x of the
    # second inlined call of operation op; 't1.deadline', 'deadline#3' for deadline bookkeeping
    name: str
    type: Type
    kind: str  # var, const, param, local
    init: "Expr | None" = None  # initial value (computed at exit of initialization)
    span: Span | None = None
    shared: bool = False  # declared by an interface (shared with the controller)
    index: int = 0  # position in the machine's var list
    # a variable its controller provides lives in the memory of the controller's first machine
    # that uses it; the other machines (and inlined operations) refer to that one: its index, or
    # -1 for the machine whose var list holds it
    owner: int = -1


@dataclass(eq=False)
class Param:
    """An FMI parameter: a model constant. ``value`` is the start value (a Python value). A
    constant the model declares without a value (and --set does not give one) is ``free``: its
    start value is its type's default, and it only gets its real value from the importer."""

    fmi_name: str
    var: Var
    machine: int
    value: object
    free: bool = False


@dataclass(frozen=True)
class Field_:
    """One scalar FMI variable of a port payload: its name, scalar type and the path of record
    fields (and array length) inside the payload value."""

    fmi_name: str
    type: Type  # scalar (or a vector or matrix of scalars: an FMI array, a matrix row by row)
    path: tuple[str, ...]


@dataclass(eq=False)
class Port:
    """A clock at the FMU boundary, with its clocked payload variables."""

    name: str  # the FMI clock name
    kind: str  # input-event, output-event, operation
    type: Type | None  # payload type (records flattened in fields); operations: None
    fields: tuple[Field_, ...]
    params: tuple[tuple[str, Type], ...] = ()  # operations: the parameters (name, type)
    span: Span | None = None
    # input ports: where the event goes inside the FMU, (machine index, event index)
    routes: list[tuple[int, int]] = field(default_factory=list)
    index: int = 0
    # the event or operation of the model, when the FMI name differs from it (a name FMI or
    # robogen already uses, or the name of another port: :class:`robogen.ir.ports.Ports`)
    model_name: str = ""
    # operations: an abstract operation (a definition without nodes), whose call leaves the FMU
    # as a platform operation's does; False for an operation the platform provides
    abstract: bool = False

    @property
    def source(self) -> str:
        """The name of the event or operation in the model."""
        return self.model_name or self.name


@dataclass(eq=False)
class Event:
    """An event a machine reads (its input register and sample). ``type`` is what the register
    holds: the event's value, or with ``sender`` (a filter ``e[| x = from |]`` of the machine reads
    the sender) a record of the value (field ``value``, if the event carries one) and the sender's
    number (field ``from``, see :mod:`robogen.ir.bindings`), which every delivery fills in."""

    name: str
    type: Type | None
    index: int
    span: Span | None = None
    sender: bool = False

    @property
    def value_type(self) -> Type | None:
        """The type of the value the event carries (None: it carries none)."""
        if not self.sender:
            return self.type
        return self.type.field("value")  # type: ignore[union-attr]


@dataclass(eq=False)
class Node:
    """A machine node that can be the value of the machine's state output."""

    id: int
    path: tuple[str, ...]
    kind: str  # state, junction, final, initial
    span: Span | None = None

    @property
    def label(self) -> str:
        return ".".join(self.path)


# ============================================================================ expressions

# The FMU's random numbers (nondeterministic waits, probabilistic junctions) come from one
# SplitMix64 generator (Steele, Lea, Flood: "Fast splittable pseudorandom number generators",
# OOPSLA 2014): state += 0x9E3779B97F4A7C15, then the state is mixed into the output. Its state
# starts, when Initialization Mode ends, at the FMU parameter ``random_seed`` (UInt64, this start
# value), so a run is reproducible for a given seed; the generated C (robogen_machine.h) and the
# reference interpreter compute the same numbers bit for bit. An integer in [low, high] is
# low + x mod (high - low + 1) of the 64-bit output x; a real in [0, 1) is (x >> 11) * 2^-53.
RANDOM_SEED = 0
RANDOM_SEED_NAME = "random_seed"
RANDOM_STATE_NAME = "random#state"  # the machine variable holding the generator's state (its init reads the seed)


@dataclass(frozen=True)
class Expr:
    type: Type


@dataclass(frozen=True)
class Lit(Expr):
    value: object  # int, float (Fraction for exact reals), bool, or an enum literal index (int)


@dataclass(frozen=True)
class Ref(Expr):
    var: Var


@dataclass(frozen=True)
class FieldOf(Expr):
    base: Expr
    name: str


@dataclass(frozen=True)
class IndexOf(Expr):
    """1-based element of a vector, or (row, column) of a matrix; out of range is a run-time error."""

    base: Expr
    indices: tuple[Expr, ...]


@dataclass(frozen=True)
class Un(Expr):
    op: str  # neg, not
    operand: Expr


@dataclass(frozen=True)
class Bin(Expr):
    """``op`` in and or implies iff eq ne lt le gt ge add sub mul div mod. Operands of arithmetic
    and ordering have the operation's numeric type already (``Conv`` inserted by lowering)."""

    op: str
    left: Expr
    right: Expr


def bin_chain(e: Expr) -> tuple[Expr, list[Bin]]:
    """A left-nested chain of binary operations as a loop walks it: the leftmost operand, then
    the operations from the innermost out (each one's left operand is the value so far). A flat
    expression of thousands of operands is a chain thousands deep: the printers, the C emitter and
    the interpreter walk it with this, never by recursion (see robogen.syntax.ast.chain)."""
    links: list[Bin] = []
    while isinstance(e, Bin):
        links.append(e)
        e = e.left
    links.reverse()
    return e, links


@dataclass(frozen=True)
class Conv(Expr):
    """Numeric conversion of ``operand`` to ``type`` (nat/int/real)."""

    operand: Expr


@dataclass(frozen=True)
class Cond(Expr):
    cond: Expr
    then: Expr
    otherwise: Expr


@dataclass(frozen=True)
class Occurred(Expr):
    """Input event ``event`` of the machine is present (RoboSim: in this cycle's sample;
    RoboChart: in the machine's event buffer)."""

    event: int


@dataclass(frozen=True)
class Payload(Expr):
    event: int


@dataclass(frozen=True)
class BindIn(Expr):
    """``$e?x`` / ``e?x``: true if event ``event`` is present, and then its value is stored in
    ``target`` (as a side effect of evaluating the guard): the value itself, or ``value`` (an
    expression of it: converted to the target's type)."""

    event: int
    target: Expr
    value: "Expr | None" = None


@dataclass(frozen=True)
class Since(Expr):
    clock: int  # index in the machine's clock list


@dataclass(frozen=True)
class SinceEntry(Expr):
    node: int


@dataclass(frozen=True)
class Now(Expr):
    """The machine's tick count (cycles or tocks seen), a ``nat``: the time base of deadlines."""


@dataclass(frozen=True)
class WaitLeft(Expr):
    """RoboChart: time units left of the current wait (0 when none)."""


@dataclass(frozen=True)
class Draw(Expr):
    """The next number of the FMU's seeded generator, whose state is ``state`` (see
    :data:`RANDOM_SEED`). Of type ``int``: an integer drawn uniformly from ``low`` to ``high``
    (both included; an empty range is a run-time error), a ``wait([a, b])`` or a choice among a
    set's elements. Of type ``real`` (no bounds): a real in [0, 1), the draw of a probabilistic
    junction."""

    state: Var
    low: Expr | None = None
    high: Expr | None = None


@dataclass(frozen=True)
class RecordLit(Expr):
    values: tuple[tuple[str, Expr], ...]


@dataclass(frozen=True)
class VectorLit(Expr):
    items: tuple[Expr, ...]  # row-major for matrices


@dataclass(frozen=True)
class CallB(Expr):
    """A built-in function: min, max, abs."""

    name: str
    args: tuple[Expr, ...]


@dataclass(frozen=True)
class CallU(Expr):
    """A call of a user function (see :class:`UserFunction`): ``name`` the model's, ``instance``
    the instantiation of a generic one ('' for one without type variables)."""

    name: str
    args: tuple[Expr, ...]
    instance: str = ""


@dataclass(frozen=True)
class Coll(Expr):
    """An operation on sets and sequences (RoboChart's set enumeration ``{a, b}``, sequence
    enumeration ``<a, b>``, ``in``, ``^`` and the toolkit functions; :mod:`robogen.ir.collections`
    gives their meaning). Collections hold at most ``Fmu.capacity`` elements: an operation whose
    result would hold more is a run-time error naming ``text`` (the expression as the model
    writes it) and ``span``, as is ``head``/``last``/``min``/``max`` of an empty collection."""

    op: str
    args: tuple[Expr, ...]
    text: str = ""
    span: Span | None = None


@dataclass(frozen=True)
class Domain:
    """The values a bound variable ``var`` of a quantifier or set comprehension takes, in order
    (robogen.ir.finite): ``set``, the elements of a set (``natural``: only those not negative, for
    a ``nat`` variable over integers); ``range``, the integers ``low`` to ``high`` (both ``int``);
    ``values``, every value of the variable's finite type (an enumeration's literals, false then
    true)."""

    var: Var
    kind: str  # set, range, values
    set: Expr | None = None
    low: Expr | None = None
    high: Expr | None = None
    natural: bool = False


@dataclass(frozen=True)
class Quant(Expr):
    """``forall``, ``exists``, ``exists1``, ``the`` (``the x: T | p @ e``: ``e`` for the one x for
    which ``p`` holds) or ``set`` (``{x: T | p @ e}``) over the finite ``domains`` of its bound
    variables (nested loops, the first outermost), ``pred`` its predicate (None: true) and
    ``body`` its expression (a comprehension without one: its variable, or the tuple of them).
    Run-time errors: a comprehension of more elements than the capacity, a range of more than
    robogen.ir.collections.LOOP_LIMIT integers, ``the`` without exactly one value; each names
    ``text`` and ``span``."""

    kind: str
    domains: tuple[Domain, ...]
    pred: Expr | None
    body: Expr | None
    text: str = ""
    span: Span | None = None


@dataclass(frozen=True)
class UserFunction:
    """A function the model declares by its contract only, whose result no postcondition pins
    (:mod:`robogen.ir.declared`); the code generator takes its body from the user
    (``--functions``), the reference interpreter a Python implementation."""

    name: str
    params: tuple[tuple[str, Type], ...]
    result: Type
    span: Span | None  # its declaration
    first_call: Span | None = None  # where the model first calls it
    # a generic function: one UserFunction per instantiation, ``instance`` its C name part
    # (robogen.ir.declared.type_word: ``UpdateValue__int``), ``shown`` its type variables (``?X = int``)
    instance: str = ""
    shown: str = ""

    @property
    def cname(self) -> str:
        """The C function is ``rg_user_<cname>``."""
        return self.instance or self.name


# ============================================================================ messages


@dataclass(frozen=True)
class At:
    """A place of the model that a run-time message names (None: unknown)."""

    span: Span | None


@dataclass(frozen=True)
class Text:
    """A run-time message: its text and the places of the model it names, in order."""

    parts: tuple[str | At, ...]

    def render(self, place: Callable[[Span | None], str]) -> str:
        """The message with each place written by ``place``."""
        return "".join(p if isinstance(p, str) else place(p.span) for p in self.parts)


# ============================================================================ statements


@dataclass(frozen=True)
class Stmt:
    span: Span | None


@dataclass(frozen=True)
class Assign(Stmt):
    target: Expr  # Ref, FieldOf or IndexOf chain
    value: Expr


@dataclass(frozen=True)
class Emit(Stmt):
    """An output event or operation call. ``args`` is () for plain events, (value,) for typed
    events, the arguments for operations. Routes: ("port", port index) for the FMU boundary,
    ("machine", machine index, event index) for a connection inside the FMU."""

    name: str
    args: tuple[Expr, ...]
    routes: tuple[tuple, ...]


@dataclass(frozen=True)
class If(Stmt):
    cond: Expr
    then: tuple[Stmt, ...]
    otherwise: tuple[Stmt, ...]


@dataclass(frozen=True)
class ResetClock(Stmt):
    clock: int


@dataclass(frozen=True)
class Enter(Stmt):
    """The machine rests in, or passes through, ``node`` (its state output; sinceEntry). With
    ``resume``, control only returns to ``node`` (after a software operation call): the state
    output changes, the entry time does not."""

    node: int
    resume: bool = False


@dataclass(frozen=True)
class Consume(Stmt):
    """RoboChart: the taken transition consumes event ``event`` from the buffer."""

    event: int


@dataclass(frozen=True)
class StartWait(Stmt):
    """RoboChart ``wait(n)``: n time units must pass before control goes on."""

    duration: Expr


@dataclass(frozen=True)
class DeadlineMiss(Stmt):
    """A RoboChart deadline was missed: counted in the output ``deadline_misses`` and logged;
    never enforced (README: Known limits)."""

    text: Text


@dataclass(frozen=True)
class Trace(Stmt):
    """A transition was taken (logged in the category logTransitions, and in interpreter traces)."""

    text: str


# ============================================================================ control


@dataclass(frozen=True)
class Terminator:
    pass


@dataclass(frozen=True)
class Goto(Terminator):
    target: int


@dataclass(frozen=True)
class Suspend(Terminator):
    target: int


@dataclass(frozen=True)
class Case:
    guard: Expr
    target: int
    label: str  # the transition, for traces and comments
    span: Span | None
    # the guard as the model writes it (a transition's trigger and condition, an if's condition),
    # quoted by the generated C above its test; '' when the model writes none. Not in the dump:
    # it restates ``guard`` for readers and does not change the model's meaning.
    guard_text: str = ""


@dataclass(frozen=True)
class Branch(Terminator):
    cases: tuple[Case, ...]
    default: Terminator


@dataclass(frozen=True)
class Fail(Terminator):
    message: Text


@dataclass(eq=False)
class Block:
    id: int
    label: str  # what the block does, e.g. "EVAL ArmMove", "t2_1: exit ArmMove"
    span: Span | None
    stmts: list[Stmt] = field(default_factory=list)
    term: Terminator | None = None
    step: bool = False  # a transition segment starts here (see the module documentation)


@dataclass(eq=False)
class Machine:
    name: str
    qname: str
    span: Span | None
    vars: list[Var] = field(default_factory=list)
    clocks: list[str] = field(default_factory=list)
    events: list[Event] = field(default_factory=list)
    nodes: list[Node] = field(default_factory=list)
    blocks: list[Block] = field(default_factory=list)
    start: int = 0  # the block of the first cycle (the initial transition)
    initial_node: int = 0
    index: int = 0

    def event(self, name: str) -> Event | None:
        for e in self.events:
            if e.name == name:
                return e
        return None


@dataclass(eq=False)
class Fmu:
    name: str  # the boundary's model name
    model_identifier: str
    language: str  # robosim or robochart
    semantics: str  # exhaustive or stepwise
    trigger: str  # cycle or on-input (RoboSim)
    period: Fraction  # RoboSim cycle period in model time units; RoboChart: 1 (one tock)
    time_unit: Fraction  # seconds per model time unit
    sources: tuple[str, ...]  # the model files, as given
    span: Span | None
    machines: list[Machine] = field(default_factory=list)
    inputs: list[Port] = field(default_factory=list)
    outputs: list[Port] = field(default_factory=list)
    params: list[Param] = field(default_factory=list)
    user_functions: list[UserFunction] = field(default_factory=list)
    max_steps: int = 1000  # transitions per cycle before a runaway cycle is reported
    capacity: int = 32  # the most elements a set or sequence holds (robogen compile --capacity)
    # the capacity of each nesting level of collections, outermost first (the last for every deeper
    # level; ``--capacity 32,8``); empty: ``capacity`` at every level
    capacities: tuple[int, ...] = ()
    root: str = ""  # the workspace root (absolute), to which generated files name model files
    # RoboChart time (robogen compile --time): "skip", tocks are the FMU's own and it announces the
    # next time anything can happen as nextEventTime (robogen.ir.lookahead); "tick", the master
    # ticks the periodic clock tock every time unit. RoboSim FMUs always tick their cycle clock.
    time: str = "tick"
    # what lowering warns about (constants that become parameters without a value, renamed
    # ports); the front end prints them. Not in the dump: they restate the model's meaning.
    warnings: list = field(default_factory=list)

    def source_name(self, path: str) -> str:
        """A model file's name in generated files: relative to the workspace root, so the same
        model gives the same sources in any checkout."""
        return os.path.relpath(os.path.abspath(path), self.root) if self.root else path

    def place(self, span: Span | None) -> str:
        """``file:line`` of a model element in generated files ('?' when unknown)."""
        return f"{self.source_name(span.path)}:{span.line}" if span is not None else "?"

    @property
    def source_names(self) -> list[str]:
        return sorted(self.source_name(p) for p in self.sources)

    @property
    def levels(self) -> tuple[int, ...]:
        """The capacity of each nesting level of collections (see ``capacities``)."""
        return self.capacities or (self.capacity,)

    def capacity_of(self, t: Type) -> int:
        """The most elements a set or sequence of type ``t`` holds: that of its nesting level
        (robogen.ir.supported.InnerSetT), else the outermost level's."""
        return getattr(t, "capacity", None) or self.capacity

    @property
    def clock_name(self) -> str:
        return "cycle" if self.language == "robosim" else "tock"

    @property
    def clock_interval(self) -> Fraction:
        """Seconds between ticks of the periodic clock (cycle or tock)."""
        return self.period * self.time_unit

    @property
    def robochart(self) -> bool:
        return self.language == "robochart"

    @property
    def time_free(self) -> bool:
        """A RoboChart FMU whose tocks are its own (no tock clock): ``time == "skip"``."""
        return self.language == "robochart" and self.time == "skip"
