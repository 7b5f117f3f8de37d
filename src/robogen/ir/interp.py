"""The reference interpreter of the IR: the executable statement of robogen's semantics.

It runs an :class:`~robogen.ir.model.Fmu` the way the generated C does, one FMI instant at a
time, so tests can drive both with the same inputs and compare their traces:

- ``latch(clock, payload)``: an input clock ticks (its clocked payload given by FMI name);
- ``evaluate(periodic)``: the instant's computation, at its first read (``periodic``: the
  ``cycle``/``tock`` clock ticks in this instant);
- ``update()``: closes the instant, deactivates every clock, says whether another instant is
  needed at this time.

Numbers behave as in C99 on x86-64 with the generated helpers: ``int`` is a wrapping 64-bit
two's complement integer, ``nat`` a wrapping unsigned 64-bit integer, division truncates
toward zero, ``real`` is an IEEE double; division by zero and vector indices out of range are
run-time errors (:class:`RuntimeFault`), as is a runaway cycle or a deadlock.

RoboSim (each instant): a tick of ``cycle`` starts a cycle of every machine: first each machine's
input register (events latched since the previous cycle, from the platform or from the other
machines) becomes its sample and is cleared, then the machines run, in declaration order, until
they suspend (exhaustive) or take one transition (stepwise, where later micro-steps of the cycle
run in the following instants without a clock). Because every machine samples before any runs,
what one machine sends another is seen in the next cycle, whatever their order. RoboChart: a tick
of ``tock`` advances time (clocks, waits); events latched in the instant join the machine's
buffer (one place per event; it keeps an event until a transition or an input statement consumes
it, as the README's FMI mapping says) and the machine runs to quiescence (exhaustive) or takes one
transition (stepwise); events that arrive after the evaluation ask for another instant.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field

from robogen.ir import collections as C
from robogen.ir import finite
from robogen.ir import model as ir
from robogen.ir.constants import default_value
from robogen.ir.layout import build, gather, leaves
from robogen.ir.lookahead import first_change, lookaheads
from robogen.ir.supported import ArrayT
from robogen.ir.walk import initial_order
from robogen.semantics import types as T

MASK = (1 << 64) - 1


class RuntimeFault(Exception):
    """A run-time error of the model: the FMU returns fmi3Error with this message."""


def wrap_int(v: int) -> int:
    v &= MASK
    return v - (1 << 64) if v >> 63 else v


def wrap_nat(v: int) -> int:
    return v & MASK


def random_next(state: int) -> tuple[int, int]:
    """SplitMix64 (see robogen.ir.model.RANDOM_SEED): the generator's next state and output."""
    state = (state + 0x9E3779B97F4A7C15) & MASK
    z = ((state ^ (state >> 30)) * 0xBF58476D1CE4E5B9) & MASK
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
    return state, z ^ (z >> 31)


def _zero(t: T.Type):
    return default_value(t, 0.0)


def python_value(v: object, t: T.Type):
    """A literal of the IR as the interpreter's value."""
    if isinstance(t, (T.VectorT, T.MatrixT)) and isinstance(v, list):  # a parameter's start value
        return [python_value(x, t.element) for x in v]
    if t == T.REAL:
        return float(v)  # type: ignore[arg-type]
    if t == T.BOOLEAN:
        return bool(v)
    if t == T.INT:
        return wrap_int(int(v))  # type: ignore[arg-type]
    if t == T.NAT:
        return wrap_nat(int(v))  # type: ignore[arg-type]
    return v


@dataclass
class MachineState:
    pc: int
    node: int
    vars: dict[str, object]
    clocks: list[int]
    entered: dict[int, int]
    ticks: int = 0
    transitions: int = 0  # transitions taken in the current cycle (runaway bound)
    wait_left: int = 0
    in_cycle: bool = False  # stepwise: the current cycle/run has more micro-steps
    pending: int = 0  # stepwise RoboSim: cycle ticks not started yet
    new_input: bool = False  # an input arrived since the last cycle (trigger on-input)
    register: dict[int, object] = field(default_factory=dict)  # RoboSim: latched inputs; RoboChart: incoming
    sample: dict[int, object] = field(default_factory=dict)  # RoboSim: this cycle's inputs; RoboChart: buffer


@dataclass
class Instant:
    """What an instant shows to the outside (the same things the FMU's Gets read)."""

    outputs: dict[str, dict[str, object]]  # active output clocks -> clocked values by FMI name
    states: tuple[int, ...]  # each machine's node
    need_update: bool = False


class Interpreter:
    def __init__(self, fmu: ir.Fmu, parameters: dict[str, object] | None = None, functions: dict | None = None):
        """``functions``: Python implementations of the model's user functions (name -> callable;
        an instantiation of a generic function by its C name part, ``UpdateValue__int``, else by
        the function's name), the counterparts of the C file given to the code generator with --functions."""
        self.fmu = fmu
        self.functions = dict(functions or {})
        self.parameters = {p.fmi_name: p.value for p in fmu.params}
        if parameters:
            self.parameters.update(parameters)
            for p in fmu.params:  # a record's fields are parameters of their own: "<name>.<field>..."
                if isinstance(p.var.type, T.RecordT):
                    value = copy.deepcopy(self.parameters[p.fmi_name])
                    for name, v in parameters.items():
                        if name.startswith(p.fmi_name + "."):
                            _set_path(value, name[len(p.fmi_name) + 1:].split("."), v)
                    self.parameters[p.fmi_name] = value
        self.cycles = 0
        self.dropped = 0
        self.deadline_misses = 0
        self.machines: list[MachineState] = []
        self.active: dict[str, dict[str, object]] = {}
        self.evaluated = False
        self.trace: list[str] = []  # transitions taken (the logTransitions messages)
        self._lookaheads = [lookaheads(m) for m in fmu.machines] if fmu.robochart else []
        self.reset()

    # ------------------------------------------------------------------ life cycle

    def reset(self) -> None:
        self.cycles = 0
        self.dropped = 0
        self.deadline_misses = 0
        self.machines = []
        for m in self.fmu.machines:
            self.machines.append(
                MachineState(
                    pc=m.start,
                    node=m.initial_node,
                    vars={v.name: _zero(v.type) for v in m.vars},
                    clocks=[0] * len(m.clocks),
                    entered={},
                )
            )
        for p in self.fmu.params:
            value = self.parameters.get(p.fmi_name)
            if value is not None:
                self.machines[p.machine].vars[p.var.name] = python_value(value, p.var.type)
        self.active = {}
        self.evaluated = False

    def exit_initialization(self) -> None:
        """Initial values of variables (they may read parameters)."""
        for m, ms in zip(self.fmu.machines, self.machines):
            for v in initial_order(m):  # variables, computed constants and the generator's state
                ms.vars[v.name] = copy.deepcopy(self._eval(v.init, m, ms))

    # ------------------------------------------------------------------ instants

    def latch(self, clock: str, payload: dict[str, object] | None = None) -> None:
        port = next((p for p in self.fmu.inputs if p.name == clock), None)
        if port is None:
            raise KeyError(f"no input clock {clock!r}")
        value = self._assemble(port, payload or {})
        for mi, ei in port.routes:
            self._deliver(mi, ei, value, port.type, 0)

    def _assemble(self, port: ir.Port, payload: dict[str, object]):
        """The value an input port's clocked variables give (robogen.ir.layout.build)."""
        if port.type is None:
            return None
        fields = {f.path: f for f in port.fields}

        def read(path: tuple[str, ...], pos: int, n: int) -> list:
            f = fields[path]
            element = f.type.element if isinstance(f.type, (T.VectorT, T.MatrixT, ArrayT)) else f.type  # type: ignore[attr-defined]
            given = payload.get(f.fmi_name, _zero(f.type))
            entries = list(given) if isinstance(given, (list, tuple)) else [given]  # type: ignore[arg-type]
            return [python_value(x, element) for x in entries[pos * n:(pos + 1) * n]]

        def received(items: list, t: T.Type) -> list:
            return C.received(items, len(items), t, self.fmu.capacity_of(t))

        return build(port.type, (), 0, read, self.fmu.capacity_of, received, _zero)

    def _deliver(self, mi: int, ei: int, value, source: T.Type | None, sender: int) -> None:
        """An occurrence of event ``ei`` of machine ``mi`` carrying ``value`` of type ``source``
        (a number the connection widens to the event's type: converted) from sender number
        ``sender`` (0: the boundary, k: the k-th machine), kept with the value by an event that
        keeps its sender."""
        ms = self.machines[mi]
        event = self.fmu.machines[mi].events[ei]
        if ei in ms.register:
            self.dropped += 1  # several occurrences before they are used: the last one wins
        if value is not None and source in T.NUMERIC and event.value_type in T.NUMERIC and source != event.value_type:
            value = convert(value, source, event.value_type)
        if event.sender:
            value = ({"value": value} if value is not None else {}) | {"from": sender}
        ms.register[ei] = copy.deepcopy(value)
        ms.new_input = True

    def evaluate(self, periodic: bool) -> Instant:
        """The instant's computation (at most once per instant)."""
        if self.evaluated:
            return self._instant()
        self.evaluated = True
        self.active = {}
        if periodic:
            self.cycles += 1
        if self.fmu.robochart:
            for m, ms in zip(self.fmu.machines, self.machines):
                self._evaluate_robochart(m, ms, periodic)
        else:
            # every machine samples its inputs before any machine runs
            running = [self._sample_robosim(ms, periodic) for ms in self.machines]
            micro = self.fmu.semantics == "stepwise"
            for m, ms, run in zip(self.fmu.machines, self.machines, running):
                if run:
                    ms.in_cycle = self._run(m, ms, micro=micro) == "micro"
        return self._instant()

    def _sample_robosim(self, ms: MachineState, periodic: bool) -> bool:
        """Start a cycle if one is due (sample the register); says whether the machine runs."""
        start = periodic or (self.fmu.trigger == "on-input" and ms.new_input)
        if self.fmu.semantics == "stepwise":
            if start:
                ms.pending += 1
            if ms.in_cycle:
                return True
            if ms.pending:
                ms.pending -= 1
                self._start_cycle(ms)
                return True
            return False
        if start:
            self._start_cycle(ms)
        return start

    def _start_cycle(self, ms: MachineState) -> None:
        ms.sample = ms.register
        ms.register = {}
        ms.new_input = False
        ms.ticks += 1
        ms.transitions = 0

    def _evaluate_robochart(self, m: ir.Machine, ms: MachineState, periodic: bool) -> None:
        if periodic:
            ms.ticks += 1
            if ms.wait_left > 0:
                ms.wait_left -= 1
        # Events join the buffer between runs: in the middle of a stepwise run they wait, so that
        # the transition a micro-step decided on finds, in the next one, the buffer it was
        # decided on (docs §7.5: inputs that arrive during the micro-steps are for the next run).
        arrived = bool(ms.register) and not ms.in_cycle
        if arrived:
            for ei, value in ms.register.items():
                if ei in ms.sample:
                    self.dropped += 1
                ms.sample[ei] = value
            ms.register = {}
        if not ms.in_cycle:
            ms.new_input = False
        if periodic or arrived or ms.in_cycle:
            if not ms.in_cycle:
                ms.transitions = 0  # a new run to quiescence
            ms.in_cycle = self._run(m, ms, micro=self.fmu.semantics == "stepwise") == "micro"

    def update(self) -> bool:
        """Close the instant: returns discreteStatesNeedUpdate."""
        if not self.evaluated:
            self.evaluate(False)
        need = any(ms.in_cycle for ms in self.machines)
        if self.fmu.robochart:
            need = need or any(ms.register for ms in self.machines)
        elif self.fmu.trigger == "on-input":
            need = need or any(ms.new_input for ms in self.machines)
        if self.fmu.semantics == "stepwise" and not self.fmu.robochart:
            need = need or any(ms.pending for ms in self.machines)
        self.active = {}
        self.evaluated = False
        return need

    # ------------------------------------------------------------------ time for free (RoboChart, --time skip)

    def idle_tocks(self) -> int | None:
        """After an instant that needs no other: in how many tocks from the last one counted
        something can happen (robogen.ir.lookahead; at least 1), None for never (until an event
        comes). The generated FMU announces that tock's time as nextEventTime."""
        wakes = [self._wake(m, ms) for m, ms in zip(self.fmu.machines, self.machines)]
        known = [w for w in wakes if w is not None]
        return min(known) if known else None

    def pass_idle(self, tocks: int) -> None:
        """``tocks`` tocks at which nothing can happen: counted as the ticking FMU counts them
        (``cycles``, each machine's ticks and wait), with no machine run."""
        self.cycles += tocks
        for ms in self.machines:
            ms.ticks += tocks
            if ms.wait_left > 0:
                ms.wait_left = max(0, ms.wait_left - tocks)

    def _wake(self, m: ir.Machine, ms: MachineState) -> int | None:
        la = self._lookaheads[m.index].get(ms.pc)
        if la is None or ms.in_cycle:
            return 1
        try:
            if any(self._shifted(ms, 1, lambda t=t: self._eval(t, m, ms)) for t in la.tests):
                return 1
            wake = None
            for atom in la.atoms:
                def sign(k: int, atom: ir.Bin = atom) -> int:
                    a, b = self._shifted(ms, k, lambda: (self._eval(atom.left, m, ms), self._eval(atom.right, m, ms)))
                    return (a > b) - (a < b)
                k = first_change(sign)
                wake = k if wake is None else min(wake, k)
        except RuntimeFault:
            return 1
        return wake

    @staticmethod
    def _shifted(ms: MachineState, k: int, compute):
        """``compute()`` as ``k`` tocks from now would see it."""
        ticks, wait = ms.ticks, ms.wait_left
        ms.ticks += k
        if wait > 0:
            ms.wait_left = max(0, wait - k)
        try:
            return compute()
        finally:
            ms.ticks, ms.wait_left = ticks, wait

    def _instant(self) -> Instant:
        return Instant(dict(self.active), tuple(ms.node for ms in self.machines))

    # ------------------------------------------------------------------ observation

    def variables(self) -> dict[str, object]:
        """Every machine variable, flattened to FMI scalar names (Machine.var.field)."""
        out: dict[str, object] = {}
        params = {id(p.var): p.fmi_name for p in self.fmu.params}
        for m, ms in zip(self.fmu.machines, self.machines):
            for v in m.vars:
                if v.kind in ("var", "const"):
                    _flatten_value(params.get(id(v), f"{m.name}.{v.name}"), v.type, ms.vars[v.name], out, self.fmu.capacity_of)
        return out

    # ------------------------------------------------------------------ execution

    def _run(self, m: ir.Machine, ms: MachineState, micro: bool) -> str:
        """Run from ms.pc until the machine suspends ("suspend") or, with ``micro``, until it
        reaches a second transition segment ("micro")."""
        steps = 0
        taken = False
        limit = self.fmu.max_steps
        while True:
            steps += 1
            if steps > 64 * limit:
                raise RuntimeFault(f"machine {m.name}: a cycle ran more than {64 * limit} steps without ending")
            block = m.blocks[ms.pc]
            if block.step:
                if micro and taken:
                    return "micro"
                taken = True
                ms.transitions += 1
                if ms.transitions > limit:
                    raise RuntimeFault(
                        f"machine {m.name}: more than {limit} transitions in one cycle without exec (a runaway cycle) at {block.label}"
                    )
            for s in block.stmts:
                self._exec(s, m, ms)
            term = block.term
            while isinstance(term, ir.Branch):
                for case in term.cases:
                    if self._eval(case.guard, m, ms):
                        term = ir.Goto(case.target)
                        break
                else:
                    term = term.default
            if isinstance(term, ir.Goto):
                ms.pc = term.target
            elif isinstance(term, ir.Suspend):
                ms.pc = term.target
                return "suspend"
            elif isinstance(term, ir.Fail):
                raise RuntimeFault(f"machine {m.name}: {term.message.render(self.fmu.place)}")
            else:  # pragma: no cover
                raise RuntimeFault(f"machine {m.name}: block b{block.id} has no terminator")

    def _exec(self, s: ir.Stmt, m: ir.Machine, ms: MachineState) -> None:
        if isinstance(s, ir.Assign):
            self._store(s.target, copy.deepcopy(self._eval(s.value, m, ms)), m, ms)
        elif isinstance(s, ir.Emit):
            args = [copy.deepcopy(self._eval(a, m, ms)) for a in s.args]
            for route in s.routes:
                if route[0] == "port":
                    port = self.fmu.outputs[route[1]]
                    self.active[port.name] = self._payload(port, args)
                else:
                    self._deliver(route[1], route[2], args[0] if args else None, s.args[0].type if s.args else None, m.index + 1)
        elif isinstance(s, ir.If):
            for x in s.then if self._eval(s.cond, m, ms) else s.otherwise:
                self._exec(x, m, ms)
        elif isinstance(s, ir.ResetClock):
            ms.clocks[s.clock] = ms.ticks
        elif isinstance(s, ir.Enter):
            ms.node = s.node
            if not s.resume:
                ms.entered[s.node] = ms.ticks
        elif isinstance(s, ir.Consume):
            ms.sample.pop(s.event, None)
        elif isinstance(s, ir.StartWait):
            ms.wait_left = max(0, int(self._eval(s.duration, m, ms)))  # type: ignore[arg-type]
        elif isinstance(s, ir.Trace):
            self.trace.append(f"{m.name}: {s.text}")
        elif isinstance(s, ir.DeadlineMiss):
            self.deadline_misses += 1
            self.trace.append(f"{m.name}: {s.text.render(self.fmu.place)}")
        else:  # pragma: no cover
            raise RuntimeFault(f"unknown statement {type(s).__name__}")

    def _payload(self, port: ir.Port, args: list) -> dict[str, object]:
        out: dict[str, object] = {}
        for f in port.fields:
            if port.kind == "operation":
                pi = [n for n, _ in port.params].index(f.path[0])
                value, t, path = args[pi], port.params[pi][1], f.path[1:]
            else:
                value, t, path = args[0], port.type, f.path
            out[f.fmi_name] = _leaf_value(value, t, path, f.type, self.fmu.capacity_of)
        return out

    def _store(self, target: ir.Expr, value, m: ir.Machine, ms: MachineState) -> None:
        if isinstance(target, ir.Ref):
            self._memory(target.var, ms)[target.var.name] = value
            return
        container, key = self._place(target, m, ms)
        container[key] = value

    def _place(self, target: ir.Expr, m: ir.Machine, ms: MachineState):
        """The Python container and key of an assignable location."""
        if isinstance(target, ir.FieldOf):
            return self._location(target.base, m, ms), target.name
        if isinstance(target, ir.IndexOf):
            base = self._location(target.base, m, ms)
            return base, self._offset(target, m, ms, base)
        raise RuntimeFault("bad assignment target")  # pragma: no cover

    def _memory(self, var: ir.Var, ms: MachineState) -> dict[str, object]:
        """The variables of the machine that holds ``var`` (its controller's shared ones live in
        the first machine that uses them)."""
        return ms.vars if var.owner < 0 else self.machines[var.owner].vars

    def _location(self, e: ir.Expr, m: ir.Machine, ms: MachineState):
        if isinstance(e, ir.Ref):
            return self._memory(e.var, ms)[e.var.name]
        container, key = self._place(e, m, ms)
        return container[key]

    def _offset(self, e: ir.IndexOf, m: ir.Machine, ms: MachineState, base) -> int:
        base_t = e.base.type
        idx = [self._eval(i, m, ms) for i in e.indices]
        if isinstance(base_t, T.SeqT):
            try:
                return C.index(base, idx[0], "a sequence")
            except C.CollectionFault as fault:
                raise RuntimeFault(str(fault)) from None
        if isinstance(base_t, T.VectorT):
            i = idx[0]
            if not 1 <= i <= (base_t.size or 0):  # type: ignore[operator]
                raise RuntimeFault(f"index {i} out of range 1..{base_t.size}")
            return i - 1  # type: ignore[operator]
        assert isinstance(base_t, T.MatrixT)
        r, c = idx
        if not (1 <= r <= (base_t.rows or 0) and 1 <= c <= (base_t.columns or 0)):  # type: ignore[operator]
            raise RuntimeFault(f"index [{r}, {c}] out of range [1..{base_t.rows}, 1..{base_t.columns}]")
        return (r - 1) * (base_t.columns or 0) + (c - 1)  # type: ignore[operator]

    # ------------------------------------------------------------------ expressions

    def _eval(self, e: ir.Expr, m: ir.Machine, ms: MachineState):
        if isinstance(e, ir.Lit):
            return python_value(e.value, e.type)
        if isinstance(e, ir.Ref):
            return self._memory(e.var, ms)[e.var.name]
        if isinstance(e, ir.FieldOf):
            return self._eval(e.base, m, ms)[e.name]
        if isinstance(e, ir.IndexOf):
            base = self._eval(e.base, m, ms)
            return base[self._offset(e, m, ms, base)]
        if isinstance(e, ir.Un):
            v = self._eval(e.operand, m, ms)
            if e.op == "not":
                return not v
            return _neg(v, e.type)
        if isinstance(e, ir.Bin):
            return self._binary(e, m, ms)
        if isinstance(e, ir.Conv):
            return convert(self._eval(e.operand, m, ms), e.operand.type, e.type)
        if isinstance(e, ir.Cond):
            return self._eval(e.then if self._eval(e.cond, m, ms) else e.otherwise, m, ms)
        if isinstance(e, ir.Occurred):
            return e.event in ms.sample
        if isinstance(e, ir.Payload):
            return ms.sample.get(e.event)
        if isinstance(e, ir.BindIn):
            if e.event not in ms.sample:
                return False
            value = ms.sample[e.event] if e.value is None else self._eval(e.value, m, ms)
            self._store(e.target, copy.deepcopy(value), m, ms)
            return True
        if isinstance(e, ir.Since):
            return self._since(ms.ticks - ms.clocks[e.clock], e.type)
        if isinstance(e, ir.SinceEntry):
            return self._since(ms.ticks - ms.entered.get(e.node, 0), e.type)
        if isinstance(e, ir.WaitLeft):
            return ms.wait_left
        if isinstance(e, ir.Now):
            return ms.ticks
        if isinstance(e, ir.Draw):
            return self._draw(e, m, ms)
        if isinstance(e, ir.RecordLit):
            return {n: self._eval(v, m, ms) for n, v in e.values}
        if isinstance(e, ir.VectorLit):
            return [self._eval(x, m, ms) for x in e.items]
        if isinstance(e, ir.CallB):
            args = [self._eval(a, m, ms) for a in e.args]
            if e.name == "abs":
                return _neg(args[0], e.type) if args[0] < 0 else args[0]
            if e.name == "min":
                return args[0] if args[0] <= args[1] else args[1]
            return args[0] if args[0] >= args[1] else args[1]
        if isinstance(e, ir.Coll):
            return self._collection(e, m, ms)
        if isinstance(e, ir.Quant):
            return self._quantifier(e, m, ms)
        if isinstance(e, ir.CallU):  # an instantiation of a generic function by its own name, or by the function's
            f = self.functions.get(e.instance) if e.instance else None
            f = f if f is not None else self.functions.get(e.name)
            if f is None:
                raise RuntimeFault(f"user function '{e.instance or e.name}' has no implementation in the reference interpreter")
            return python_value(f(*(self._eval(a, m, ms) for a in e.args)), e.type)
        raise RuntimeFault(f"unknown expression {type(e).__name__}")  # pragma: no cover

    def _collection(self, e: ir.Coll, m: ir.Machine, ms: MachineState):
        args = [self._eval(a, m, ms) for a in e.args]
        where = self.fmu.place(e.span)
        if e.op == "undefined":
            raise RuntimeFault(f"machine {m.name}: {e.text} at {where}")
        capacity = C.site_capacity(e.op, [a.type for a in e.args], e.type, self.fmu.capacity_of)
        overflow = C.overflow_message(e.text, where, capacity)
        try:
            if e.op == "conv":  # numbers converted one by one, as Conv converts them; capacities checked
                return C.convert(args[0], e.args[0].type, e.type, convert, self.fmu.capacity_of, overflow)
            return copy.deepcopy(C.apply(e.op, args, [a.type for a in e.args], self.fmu.capacity_of(e.type), overflow,
                                         C.empty_message(e.op, e.text, where), e.type))
        except C.CollectionFault as fault:
            raise RuntimeFault(f"machine {m.name}: {fault}") from None

    def _quantifier(self, e: ir.Quant, m: ir.Machine, ms: MachineState):
        def store(var: ir.Var, value) -> None:
            self._memory(var, ms)[var.name] = copy.deepcopy(value)

        try:
            return finite.evaluate(e, lambda x: self._eval(x, m, ms), store, convert, self.fmu.capacity_of(e.type),
                                   self.fmu.place(e.span))
        except C.CollectionFault as fault:
            raise RuntimeFault(f"machine {m.name}: {fault}") from None

    def _draw(self, e: ir.Draw, m: ir.Machine, ms: MachineState):
        """The generator's next number, as robogen_machine.h's rg_random_int / rg_random_real."""
        low = high = 0
        if e.type != T.REAL:
            low, high = self._eval(e.low, m, ms), self._eval(e.high, m, ms)  # type: ignore[arg-type]
            if high < low:
                raise RuntimeFault(f"a choice from an empty range: {low} to {high}")
        memory = self._memory(e.state, ms)
        memory[e.state.name], x = random_next(memory[e.state.name])  # type: ignore[arg-type]
        if e.type == T.REAL:
            return float(x >> 11) * (1.0 / 9007199254740992.0)
        span = (high - low + 1) & MASK
        return wrap_int(low + (x if span == 0 else x % span))

    def _since(self, elapsed: int, t: T.Type):
        p = self.fmu.period
        if t == T.REAL:
            return float(elapsed) * float(p)
        return wrap_nat(elapsed * int(p))

    def _binary(self, e: ir.Bin, m: ir.Machine, ms: MachineState):
        first, links = ir.bin_chain(e)  # a loop over a flat chain of operands, not recursion
        value = self._eval(first, m, ms)
        for link in links:
            value = self._operation(link, value, m, ms)
        return value

    def _operation(self, e: ir.Bin, a, m: ir.Machine, ms: MachineState):
        """Operation ``e`` on the value ``a`` of its left operand (its right one evaluated here,
        only when needed for and, or and implies)."""
        op = e.op
        if op == "and":
            return bool(a) and bool(self._eval(e.right, m, ms))
        if op == "or":
            return bool(a) or bool(self._eval(e.right, m, ms))
        if op == "implies":
            return (not a) or bool(self._eval(e.right, m, ms))
        b = self._eval(e.right, m, ms)
        if op == "iff":
            return bool(a) == bool(b)
        if op == "eq":
            return a == b
        if op == "ne":
            return a != b
        if op == "lt":
            return a < b
        if op == "le":
            return a <= b
        if op == "gt":
            return a > b
        if op == "ge":
            return a >= b
        return arith(op, a, b, e.type)


def convert(v, source: T.Type, target: T.Type):
    """A numeric conversion. A real becomes an integer by truncation toward zero; a real outside
    the target's range (or not a number) is a run-time error, as in the generated C."""
    if target == T.REAL:
        return float(v)
    if source == T.REAL and target in (T.INT, T.NAT):
        low, high = (-(2.0**63), 2.0**63) if target == T.INT else (-1.0, 2.0**64)
        if not (low <= v < high) or (target == T.NAT and v <= -1.0):
            raise RuntimeFault(f"the real {v!r} is out of range for {target.show()}")
    if target == T.INT:
        return wrap_int(int(v))
    if target == T.NAT:
        return wrap_nat(int(v))
    return v


def _neg(v, t: T.Type):
    if t == T.REAL:
        return -v
    if t == T.NAT:
        return wrap_nat(-v)
    return wrap_int(-v)


def arith(op: str, a, b, t: T.Type):
    """Arithmetic exactly as the generated C helpers compute it."""
    if t == T.REAL:
        if op == "add":
            return a + b
        if op == "sub":
            return a - b
        if op == "mul":
            return a * b
        if op == "div":
            if b == 0.0:
                raise RuntimeFault("division by zero")
            return a / b
        if op == "mod":  # RoboChart's % on reals: fmod, the sign of the dividend as on integers
            if b == 0.0:
                raise RuntimeFault("division by zero")
            return math.fmod(a, b)
    wrap = wrap_nat if t == T.NAT else wrap_int
    if op == "add":
        return wrap(a + b)
    if op == "sub":
        return wrap(a - b)
    if op == "mul":
        return wrap(a * b)
    if b == 0:
        raise RuntimeFault("division by zero")
    q = abs(a) // abs(b)
    if (a < 0) != (b < 0):
        q = -q
    if op == "div":
        return wrap(q)
    return wrap(a - q * b)  # remainder with the sign of the dividend, as C's %


def _leaf_value(value, t: T.Type, path: tuple[str, ...], leaf: T.Type, capacity_of):
    """What the FMI variable of type ``leaf`` at ``path`` of a value of ``t`` shows."""
    element = leaf.element if isinstance(leaf, (T.VectorT, T.MatrixT, ArrayT)) else leaf  # type: ignore[attr-defined]
    entries = gather(value, t, path, capacity_of, _zero(element))
    return copy.deepcopy(entries if isinstance(leaf, (T.VectorT, T.MatrixT, ArrayT)) else entries[0])


def _set_path(value, path: tuple[str, ...], v) -> None:
    for p in path[:-1]:
        value = value[p]
    value[path[-1]] = v


def _flatten_value(prefix: str, t: T.Type, v, out: dict[str, object], capacity_of) -> None:
    """A machine variable as its local FMI variables show it (robogen.ir.layout)."""
    for leaf in leaves(t, capacity_of):
        out[".".join((prefix,) + leaf.name)] = _leaf_value(v, t, leaf.path, leaf.type, capacity_of)


__all__ = ["Interpreter", "Instant", "RuntimeFault", "arith", "convert", "random_next", "wrap_int", "wrap_nat"]
