"""IR expressions, statements and terminators as C99 text.

The C follows the reference interpreter (:mod:`robogen.ir.interp`) operation for operation:
integer arithmetic wraps (through the ``rg_i_*``/``rg_u_*`` helpers of the runtime's
``robogen_machine.h``, so no signed overflow is undefined behaviour), division truncates toward
zero, a division by zero or a vector index out of range sets the model's fault code, which the
machine's run function turns into ``fmi3Error`` after the statement. ``&&`` and ``||`` keep the
left-to-right evaluation the interpreter uses, so the side effects of ``$e?x`` bindings happen in
the same order.

This module and :mod:`robogen.codegen.cnames` (the C types, :func:`mangle`) are the one place
that makes C names from model names (:class:`CNames`): the IR keeps the model's names.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from robogen.codegen.cnames import ctype, elem_tag, literal, mangle, tag
from robogen.codegen.layout_code import write
from robogen.codegen.quantifiers import quantifier
from robogen.ir import model as ir
from robogen.ir.layout import nested
from robogen.ir.supported import holds_string
from robogen.ir.collections import CAN_OVERFLOW, SECOND_FAULTS, empty_message, overflow_message, site_capacity
from robogen.semantics import types as T


_COMPARISONS = ("eq", "ne", "lt", "le", "gt", "ge")


def _binds(e: ir.Expr) -> bool:
    """Does evaluating ``e`` bind a variable (RoboSim ``$e?x``)?"""
    todo: list = [e]
    while todo:
        x = todo.pop()
        if isinstance(x, ir.BindIn):
            return True
        if isinstance(x, ir.Expr):
            todo.extend(getattr(x, f) for f in x.__dataclass_fields__)
        elif isinstance(x, tuple):
            todo.extend(x)
    return False


def _against_zero(op: str, t: T.Type, a: str, b: str) -> str | None:
    """``a op b`` of nats when one side is the literal 0 and the types decide it (``n < 0``,
    ``n >= 0``, ``0 > n``, ``0 <= n``; the checker gives the value of those it can see, this
    is for a 0 that lowering made, ``let z == 0 @ z``): the other side still evaluated (it may
    stop the cycle with a run-time error)."""
    zero = "UINT64_C(0)"
    if t != T.NAT or zero not in (a, b):
        return None
    if b == zero and op in ("lt", "ge"):
        return f"((void)({a}), {'false' if op == 'lt' else 'true'})"
    if a == zero and op in ("gt", "le"):
        return f"((void)({b}), {'false' if op == 'gt' else 'true'})"
    return None


# a C literal or name that needs no parentheses (UINT64_C(0), true, m_x)
_ATOM = re.compile(r"\w+(\(\w*\))?")

def _bare(text: str) -> str:
    """A C expression's text without the parentheses around all of it (``(m->x)`` is ``m->x``)."""
    while text.startswith("(") and text.endswith(")"):
        depth = 0
        for k, ch in enumerate(text):
            depth += ch == "("
            depth -= ch == ")"
            if depth == 0 and k < len(text) - 1:
                return text  # the first parenthesis closes before the end: (a) + (b)
        text = text[1:-1]
    return text


# a C call in an expression's text (a name, then its arguments' parenthesis)
_CALL = re.compile(r"[A-Za-z0-9_]\s*\(")


def _exact(t: T.Type) -> bool:
    """Is every value of ``t`` equal to itself (unlike a NaN, or a record holding one)?"""
    return t in (T.INT, T.NAT, T.BOOLEAN, T.STRING) or isinstance(t, T.EnumT)


class Identifiers:
    """Unique C identifiers made from model names: each name mangled, and numbered (``_2``,
    ``_3``, ...) where it would clash with one made before."""

    def __init__(self) -> None:
        self._taken: set[str] = set()

    def make(self, name: str) -> str:
        base = ident = mangle(name)
        n = 2
        while ident in self._taken:
            ident, n = f"{base}_{n}", n + 1
        self._taken.add(ident)
        return ident


def var_identifiers(fmu: ir.Fmu) -> dict[ir.Var, str]:
    """The C member name of every machine variable (the struct member is ``v_<name>``): its
    model name mangled, with a number appended where two names of one machine would clash."""
    names: dict[ir.Var, str] = {}
    for m in fmu.machines:
        members = Identifiers()
        for v in m.vars:
            names[v] = members.make(v.name)
    return names


@dataclass(frozen=True)
class MachineNames:
    """The C names of one state machine's nodes and events, StateSmith-like: an enum per kind
    whose constants carry the machine's name (``Arm_Node_Idle``, ``Arm_Event_collision``)."""

    node_type: str  # the enum of its nodes (the values of its FMI state output)
    node_name: str  # the function that names a node, for log messages
    nodes: dict[int, str]  # node id -> enum constant
    event_type: str  # the enum of its input events (indices into reg_present / smp_present)
    events: tuple[str, ...]  # event index -> enum constant
    event_values: tuple[str, ...]  # event index -> x of its value members reg_e_x / smp_e_x
    event_table: str  # its rg_event_slot table


@dataclass(frozen=True)
class CNames:
    """Every C name the generated sources make from model names, unique in the FMU's unity file."""

    vars: dict[ir.Var, str]  # machine variable -> struct member v_<name>
    machines: tuple[MachineNames, ...]  # by machine index
    clocks: dict[str, str]  # FMI clock name -> enum constant of its index in rg_clocks

    @classmethod
    def of(cls, fmu: ir.Fmu) -> "CNames":
        """The names of ``fmu``, made in a fixed order (the clocks, then each machine), so that a
        clash is numbered the same way every time."""
        made = Identifiers()
        clocks = {c: made.make(f"CLOCK_{c}") for c in [fmu.clock_name, *(p.name for p in fmu.inputs + fmu.outputs)]}
        machines = []
        for m in fmu.machines:
            members = Identifiers()  # value members share the machine struct with fixed names of other prefixes
            machines.append(MachineNames(
                node_type=made.make(f"{m.name}_Node"),
                node_name=made.make(f"{m.name}_node_name"),
                nodes={n.id: made.make(f"{m.name}_Node_{n.label}") for n in m.nodes},
                event_type=made.make(f"{m.name}_Event"),
                events=tuple(made.make(f"{m.name}_Event_{e.name}") for e in m.events),
                event_values=tuple(members.make(e.name) for e in m.events),
                event_table=f"rg_events_{m.index}"))
        return cls(var_identifiers(fmu), tuple(machines), clocks)


def integral_cast(a: str, source: T.Type, target: T.Type) -> str:
    """C converting ``a`` from number type ``source`` to ``target``, but a real to an integer
    (which may fail): nat to int wraps (rg_u_to_i), as the interpreter's convert does."""
    if source == T.NAT and target == T.INT:
        return f"rg_u_to_i({a})"
    return f"(({ctype(target)}){a})"


def deliver(target: MachineNames, event: ir.Event, value: str | None, source: T.Type | None, sender: int,
            indent: str) -> list[str]:
    """The C that delivers an occurrence of ``event`` of the machine named ``target``, carrying the
    C variable ``value`` (None: no value) of type ``source`` (a connection may widen a number to
    the event's type: converted), from sender number ``sender`` (0: the FMU's boundary, k: its
    k-th machine) to its register; an event that keeps its sender gets it with the value
    (robogen.ir.bindings)."""
    slot = f"&{target.event_table}[{target.events[event.index]}]"
    lines = []
    if value is not None and source in T.NUMERIC and event.value_type in T.NUMERIC and source != event.value_type:
        lines.append(f"{ctype(event.value_type)} conv_ = {integral_cast(value, source, event.value_type)};")
        value = "conv_"
    if not event.sender:
        lines.append(f"rg_deliver(d, {slot}, {'&' + value if value else 'NULL'});")
    else:
        fields = ([f".value = {value}"] if value else []) + [f".from = {sender}"]
        lines.append(f"{ctype(event.type)} sent_ = {{ {', '.join(fields)} }}; rg_deliver(d, {slot}, &sent_);")  # type: ignore[arg-type]
    plain = len(lines) == 1 and not event.sender  # no declaration: no block of its own
    return [indent + (lines[0] if plain else "{ " + " ".join(lines) + " }")]


def user_function_prototype(u: ir.UserFunction) -> str:
    """The C declaration of a user function, as the --functions file must define it (a generic
    one per instantiation): a string parameter is its text; where a record or collection
    parameter holds strings (their numbers), the model data comes first, for ``rg_text(d, number)``."""
    args = [f"const char *{n}" if t == T.STRING else f"{ctype(t)} {n}" for n, t in u.params]
    if strings_inside(u):
        args.insert(0, "const rg_model_data *d")
    return f"static {ctype(u.result)} rg_user_{u.cname}({', '.join(args) or 'void'})"


def strings_inside(u: ir.UserFunction) -> bool:
    """Whether a parameter of user function ``u`` holds strings inside a record or collection."""
    return any(t != T.STRING and holds_string(t) for _, t in u.params)


def c_string(text: str) -> str:
    out = []
    for ch in text:
        if ch in '"\\':
            out.append("\\" + ch)
        elif ch == "\n":
            out.append("\\n")
        elif 32 <= ord(ch) < 127:
            out.append(ch)
        else:
            out.extend(f"\\{b:03o}" for b in ch.encode("utf-8"))
    return '"' + "".join(out) + '"'


def string_literal(strings: list[str], text: str) -> str:
    """A string in C: its number among the FMU's strings (``strings``, where it is added if new),
    the text quoted beside."""
    if text not in strings:
        strings.append(text)
    return f"INT64_C({strings.index(text)}) /* {c_comment(c_string(text))} */"


def c_comment(text: str) -> str:
    return text.replace("*/", "* /").replace("/*", "/ *")


def truth(e: ir.Expr) -> bool | None:
    """The value of a boolean literal (None for any other expression): the emitter folds tests of
    constants away instead of writing ``if (true)``."""
    return e.value if isinstance(e, ir.Lit) and isinstance(e.value, bool) else None  # type: ignore[return-value]


def bare(text: str) -> str:
    """A C expression without the parentheses around the whole of it (``(!a)`` -> ``!a``), for
    the test of an ``if``, which brings its own."""
    while text.startswith("(") and text.endswith(")"):
        depth = 0
        for i, ch in enumerate(text):
            depth += {"(": 1, ")": -1}.get(ch, 0)
            if depth == 0 and i < len(text) - 1:
                return text  # the first parenthesis closes before the end: (a) && (b)
            if depth == 1 and ch == ",":
                return text  # a comma expression: ((void)(x), true)
        text = text[1:-1]
    return text


def _fixed_offset(e: ir.IndexOf) -> int | None:
    """The array offset of an element whose indices are literals in range (None otherwise)."""
    if not all(isinstance(i, ir.Lit) and not isinstance(i.value, bool) for i in e.indices):
        return None
    ks = [int(i.value) - 1 for i in e.indices]  # type: ignore[attr-defined]
    t = e.base.type
    if not isinstance(t, (T.VectorT, T.MatrixT)):
        return None  # a sequence's length is known only at run time
    dims = [t.size] if isinstance(t, T.VectorT) else [t.rows, t.columns]  # type: ignore[attr-defined]
    if len(ks) != len(dims) or not all(0 <= k < (n or 0) for k, n in zip(ks, dims)):
        return None
    return ks[0] if len(ks) == 1 else ks[0] * dims[1] + ks[1]


class Emitter:
    """Translates the IR of machine ``machine`` into C text, inside its run function
    ``rg_run_<index>``: machine memory is ``m->``, model data ``d->``, the instance ``inst``."""

    def __init__(self, fmu: ir.Fmu, machine: ir.Machine, port_fields, names: CNames, line_comments: bool = True):
        self.fmu = fmu
        self.m = machine
        self.names = names
        self.own = names.machines[machine.index]
        self.port_fields = port_fields  # output port index -> [(c field name, Field_)]
        self.line_comments = line_comments
        self.fallible = False  # the last expression may set the fault code
        self.equalities: dict[str, T.Type] = {}  # C type -> the type, for each equality function needed
        self.delivers_to: set[int] = set()  # machines this one sends events to (their event tables)
        self.collections = None  # the CollectionCode of the FMU (robogen.codegen.collections)
        self.sites: list[str] = []  # run-time messages of collection operations (model.c's rg_sites)
        self.strings: list[str] = [""]  # the model's strings, numbered: a string is its number in C
        self.texts = False  # a string is passed by its text (rg_text)
        self.helpers: list[str] = []  # the functions of its quantifiers (robogen.codegen.quantifiers)

    @property
    def fault_return(self) -> str:
        """The statement that ends the run when the last expression set the fault code."""
        return f"if (d->fault) return rg_fault_{self.m.index}(inst);"

    # ---------------------------------------------------------------- expressions

    def expr(self, e: ir.Expr) -> str:
        method = getattr(self, "_" + type(e).__name__)
        return method(e)

    def _Lit(self, e: ir.Lit) -> str:
        if e.type == T.STRING:  # strings are only literals (and equality): a string is its number
            return string_literal(self.strings, e.value)  # type: ignore[arg-type]
        return literal(e.value, e.type)

    def _Ref(self, e: ir.Ref) -> str:
        name = self.names.vars[e.var]
        if e.var.owner >= 0 and e.var.owner != self.m.index:
            return f"d->m{e.var.owner}.v_{name}"  # shared, held by another machine
        return f"m->v_{name}"

    def _FieldOf(self, e: ir.FieldOf) -> str:
        return f"{self.expr(e.base)}.{e.name}"

    def _IndexOf(self, e: ir.IndexOf) -> str:
        t = e.base.type
        base = self.expr(e.base)
        fixed = _fixed_offset(e)
        if fixed is not None:  # literal indices in range (vector arithmetic): no run-time check
            return f"{base}.a[{fixed}]"
        self.fallible = True
        if isinstance(t, T.VectorT):
            return f"{base}.a[rg_index(d, {self.expr(e.indices[0])}, {t.size})]"
        if isinstance(t, T.SeqT):
            return f"{base}.a[rg_index(d, {self.expr(e.indices[0])}, (int64_t){base}.n)]"
        assert isinstance(t, T.MatrixT)
        r, c = (self.expr(i) for i in e.indices)
        return f"{base}.a[rg_index(d, {r}, {t.rows}) * {t.columns} + rg_index(d, {c}, {t.columns})]"

    def _Un(self, e: ir.Un) -> str:
        a = self.expr(e.operand)
        if e.op == "not":
            return f"(!{a})"
        if e.type == T.REAL:
            return f"(-{a})"
        return f"rg_{tag(e.type)}_neg({a})"

    def _Bin(self, e: ir.Bin) -> str:
        first, links = ir.bin_chain(e)  # a loop over a flat chain of operands, not recursion
        text = self.expr(first)
        for link in links:
            text = self._binary(link, text, self.expr(link.right))
        return text

    def _binary(self, e: ir.Bin, a: str, b: str) -> str:
        """Operation ``e`` on the C texts of its operands."""
        op = e.op
        if op == "and":
            return f"({a} && {b})"
        if op == "or":
            return f"({a} || {b})"
        if op == "implies":
            return f"(!{a} || {b})"
        if op in (*_COMPARISONS, "iff") and _bare(a) == _bare(b) and not _CALL.search(a) and _exact(e.left.type):
            # a variable compared with itself (`x == x`, `size(q) >= size(q)`, `b iff b`: no call in
            # it, so nothing it reads changes between the two): its value, as C's
            # -Wtautological-compare rejects the comparison (reals are compared: a NaN differs from itself)
            return "true" if op in ("eq", "le", "ge", "iff") else "false"
        if op in ("iff", "eq", "ne") and e.left.type == T.BOOLEAN and (_binds(e.left) or _binds(e.right)):
            # `$e?x iff $f?y`: the binding on the left before the right's, as the interpreter reads
            # them (C does not order the operands of ==: gcc's -Wsequence-point)
            return f"({a} ? {b} : !{b})" if op != "ne" else f"({a} ? !{b} : {b})"
        if op == "iff":
            return f"(!{a} == !{b})"
        if op in ("eq", "ne"):
            t = e.left.type
            if isinstance(t, (T.RecordT, T.VectorT, T.MatrixT, T.SetT, T.SeqT)):
                self.equalities[ctype(t)] = t
                test = f"rg_eq_{ctype(t)}({a}, {b})"
                return test if op == "eq" else f"(!{test})"
            return f"({a} {'==' if op == 'eq' else '!='} {b})"
        if op in ("lt", "le", "gt", "ge"):
            decided = _against_zero(op, e.left.type, a, b)
            if decided is not None:  # a nat against 0: C's -Wtype-limits rejects the test; its value
                return decided
            return f"({a} {dict(lt='<', le='<=', gt='>', ge='>=')[op]} {b})"
        t = e.type
        if t == T.REAL:
            if op in ("div", "mod"):
                self.fallible = True
                return f"rg_r_{op}(d, {a}, {b})"
            return f"({a} {dict(add='+', sub='-', mul='*')[op]} {b})"
        if op in ("div", "mod"):
            self.fallible = True
            return f"rg_{tag(t)}_{op}(d, {a}, {b})"
        return f"rg_{tag(t)}_{op}({a}, {b})"

    def _Conv(self, e: ir.Conv) -> str:
        source, target = e.operand.type, e.type
        a = self.expr(e.operand)
        if source == T.REAL and target in (T.INT, T.NAT):  # out of range is a run-time error, not UB
            self.fallible = True
            return f"rg_r_to_{tag(target)}(d, {a})"
        return integral_cast(a, source, target)

    def _Cond(self, e: ir.Cond) -> str:
        cond = self.expr(e.cond)
        if cond in ("true", "false"):  # `if false then 10 else 0 end <= n`: the branch (C's -Wtype-limits
            # sees a constant 0 against a nat; a literal bare, for _against_zero). The other branch is
            # never written: the functions its quantifiers would add would be unused (-Wunused-function)
            chosen = self.expr(e.then if cond == "true" else e.otherwise)
            return chosen if _ATOM.fullmatch(chosen) else f"({chosen})"
        return f"({cond} ? {self.expr(e.then)} : {self.expr(e.otherwise)})"

    def _present(self, event: int) -> str:
        return f"m->smp_present[{self.own.events[event]}]"

    def _Occurred(self, e: ir.Occurred) -> str:
        return self._present(e.event)

    def _value(self, event: int) -> str:
        return f"m->smp_e_{self.own.event_values[event]}"

    def _Payload(self, e: ir.Payload) -> str:
        return self._value(e.event)

    def _BindIn(self, e: ir.BindIn) -> str:
        value = self._value(e.event) if e.value is None else self.expr(e.value)
        return f"({self._present(e.event)} ? ({self.expr(e.target)} = {value}, true) : false)"

    def _since(self, elapsed: str, t: T.Type) -> str:
        p = self.fmu.period
        if t == T.REAL:
            return f"((double)({elapsed}) * {literal(p, T.REAL)})"
        return f"(({elapsed}) * UINT64_C({int(p)}))"

    def _Since(self, e: ir.Since) -> str:
        return self._since(f"m->ticks - m->clock_reset[{e.clock}]", e.type)

    def _SinceEntry(self, e: ir.SinceEntry) -> str:
        return self._since(f"m->ticks - m->entered[{self.own.nodes[e.node]}]", e.type)

    def _WaitLeft(self, e: ir.WaitLeft) -> str:
        return "m->wait_left"

    def _Now(self, e: ir.Now) -> str:
        return "m->ticks"

    def _Draw(self, e: ir.Draw) -> str:
        state = "&" + self._Ref(ir.Ref(T.NAT, e.state))
        if e.type == T.REAL:
            return f"rg_random_real({state})"
        assert e.low is not None and e.high is not None
        low, high = self.expr(e.low), self.expr(e.high)
        self.fallible = True
        return f"rg_random_int(d, {state}, {low}, {high})"

    def _RecordLit(self, e: ir.RecordLit) -> str:
        parts = ", ".join(f".{n} = {self.expr(v)}" for n, v in e.values)
        return f"(({ctype(e.type)}){{ {parts} }})"

    def _VectorLit(self, e: ir.VectorLit) -> str:
        return f"(({ctype(e.type)}){{ {{ {', '.join(self.expr(x) for x in e.items)} }} }})"

    def _Coll(self, e: ir.Coll) -> str:
        """A collection operation: a function of robogen.codegen.collections, with its site (the
        index of its run-time messages in rg_sites) where it can fail."""
        args = [self.expr(a) for a in e.args]
        site = len(self.sites)
        if self.collections.fallible(e.op):  # type: ignore[attr-defined]
            self.fallible = True
            where = self.fmu.place(e.span)
            if e.op == "undefined":
                self.sites += [f"{e.text} at {where}", ""]
            else:
                capacity = site_capacity(e.op, [a.type for a in e.args], e.type, self.fmu.capacity_of)
                self.sites += [overflow_message(e.text, where, capacity) if e.op in CAN_OVERFLOW else "",
                               empty_message(e.op, e.text, where) if e.op in SECOND_FAULTS else ""]
        return self.collections.call(e, args, site)  # type: ignore[attr-defined]

    def _Quant(self, e: ir.Quant) -> str:
        return quantifier(self, e)

    def _CallU(self, e: ir.CallU) -> str:
        """A user function's call (of the instantiation of a generic one): a string argument as
        its text, the model data first where a record or collection argument holds strings
        (user_function_prototype)."""
        args = [f"rg_text(d, {self.expr(a)})" if a.type == T.STRING else self.expr(a) for a in e.args]
        if any(holds_string(a.type) for a in e.args):
            self.texts = True
        if any(a.type != T.STRING and holds_string(a.type) for a in e.args):
            args.insert(0, "d")
        return f"rg_user_{e.instance or e.name}({', '.join(args)})"

    def _CallB(self, e: ir.CallB) -> str:
        args = [self.expr(a) for a in e.args]
        t = tag(e.type) if e.type != T.REAL else "r"
        if e.name == "abs":
            return f"rg_{t}_abs({args[0]})"
        return f"rg_{t}_{e.name}({args[0]}, {args[1]})"

    # ---------------------------------------------------------------- statements

    def stmts(self, stmts, indent: str) -> list[str]:
        out: list[str] = []
        for s in stmts:
            out += self.stmt(s, indent)
        return out

    def stmt(self, s: ir.Stmt, indent: str) -> list[str]:
        self.fallible = False
        lines = self._stmt(s, indent)
        if self.fallible:
            lines.append(f"{indent}{self.fault_return}")
        return lines

    def _stmt(self, s: ir.Stmt, indent: str) -> list[str]:
        if isinstance(s, ir.Assign):
            return [f"{indent}{self.expr(s.target)} = {self.expr(s.value)};"]
        if isinstance(s, ir.Emit):
            return self._emit(s, indent)
        if isinstance(s, ir.If):
            return self._if(s, indent)
        if isinstance(s, ir.ResetClock):
            return [f"{indent}m->clock_reset[{s.clock}] = m->ticks;"]
        if isinstance(s, ir.Enter):
            node = self.own.nodes[s.node]
            return [f"{indent}m->node = {node};" if s.resume else f"{indent}RG_ENTER({node});"]
        if isinstance(s, ir.DeadlineMiss):
            return [f"{indent}rg_deadline_miss(inst, {c_string(self.m.name + ': ' + s.text.render(self.fmu.place))});"]
        if isinstance(s, ir.Consume):
            return [f"{indent}{self._present(s.event)} = false;"]
        if isinstance(s, ir.StartWait):
            return [f"{indent}{{ int64_t w_ = {self.expr(s.duration)}; m->wait_left = w_ > 0 ? w_ : 0; }}"]
        if isinstance(s, ir.Trace):
            return [f"{indent}RG_TRACE(inst, {c_string(self.m.name + ': ' + s.text)});"]
        raise TypeError(f"no C for {type(s).__name__}")  # pragma: no cover

    def _if(self, s: ir.If, indent: str) -> list[str]:
        """An if statement; one whose condition is a constant is its taken branch alone."""
        known = truth(s.cond)
        if known is not None:
            return self.stmts(s.then if known else s.otherwise, indent)
        cond = self.expr(s.cond)
        fallible = self.fallible
        inner = indent + "    " if fallible else indent
        lines = []
        if fallible:  # the condition may fault: test the fault code before either branch runs
            lines += [f"{indent}{{", f"{inner}bool c_ = {bare(cond)};", f"{inner}{self.fault_return}"]
            cond = "c_"
        lines.append(f"{inner}if ({bare(cond)}) {{")
        lines += self.stmts(s.then, inner + "    ")
        if s.otherwise:
            lines.append(f"{inner}}} else {{")
            lines += self.stmts(s.otherwise, inner + "    ")
        lines.append(f"{inner}}}")
        if fallible:
            lines.append(f"{indent}}}")
        self.fallible = False
        return lines

    def _emit(self, s: ir.Emit, indent: str) -> list[str]:
        """An output event or operation call: each argument evaluated once, left to right, then
        handed to every route (a port's clocked outputs and clock, or another machine's register).
        An argument read once by the one port it goes to is assigned straight to its output."""
        values = [self.expr(a) for a in s.args]
        collection = any(isinstance(a.type, (T.SetT, T.SeqT)) for a in s.args)  # copied from a temporary
        if not self.fallible and len(s.routes) == 1 and s.routes[0][0] == "port" and not collection:
            port = s.routes[0][1]
            if [k for k, _ in self._port_reads(port)] == list(range(len(values))):
                return self._to_port(port, values, indent)
        lines = [f"{indent}{{"]
        inner = indent + "    "
        lines += [f"{inner}{ctype(a.type)} a{k}_ = {v};" for k, (a, v) in enumerate(zip(s.args, values))]
        if self.fallible:
            lines.append(f"{inner}{self.fault_return}")
            self.fallible = False
        temporaries = [f"a{k}_" for k in range(len(values))]
        read: set[int] = set()  # arguments some route reads: the others are evaluated for their faults only
        for route in s.routes:
            if route[0] == "port":
                lines += self._to_port(route[1], temporaries, inner)
                read |= {k for k, _ in self._port_reads(route[1])}
            else:
                read.add(0)
                _, mi, ei = route
                self.delivers_to.add(mi)
                event = self.fmu.machines[mi].events[ei]
                assert len(s.args) == (event.value_type is not None), f"{s.name} sends another value than event {event.name} carries"
                source = s.args[0].type if s.args else None
                lines += deliver(self.names.machines[mi], event, "a0_" if s.args else None, source, self.m.index + 1, inner)
        if not s.routes:
            lines.append(f"{inner}/* {c_comment(s.name)} is connected to nothing: evaluated, sent nowhere */")
        lines += [f"{inner}(void){t};" for k, t in enumerate(temporaries) if k not in read]
        lines.append(f"{indent}}}")
        return lines

    def _port_reads(self, index: int) -> list[tuple[int, str]]:
        """(argument index, access inside it) of each clocked output of output port ``index``."""
        port = self.fmu.outputs[index]
        reads = []
        for _, f in self.port_fields[index]:
            if port.kind == "operation":
                reads.append(([n for n, _ in port.params].index(f.path[0]), "".join("." + p for p in f.path[1:])))
            else:
                reads.append((0, "".join("." + p for p in f.path)))
        return reads

    def _to_port(self, index: int, values: list[str], indent: str) -> list[str]:
        """Write ``values`` (C expressions of the arguments) to output port ``index`` and activate its clock."""
        port = self.fmu.outputs[index]
        lines: list[str] = []
        if port.kind == "operation" and any(nested(t) for _, t in port.params):
            for k, (pname, t) in enumerate(port.params):
                mine = [(c, f) for c, f in self.port_fields[index] if f.path[0] == pname]
                lines += write(t, values[k], mine, self.fmu.capacity_of, indent, skip=1)
        elif port.kind != "operation" and port.type is not None and nested(port.type):
            lines += write(port.type, values[0], self.port_fields[index], self.fmu.capacity_of, indent)
        else:
            lines += self._flat_to_port(index, values, indent)
        clock = self.names.clocks[port.name]
        return lines + [f"{indent}rg_activate_output_clock(inst, {clock});"]

    def _flat_to_port(self, index: int, values: list[str], indent: str) -> list[str]:
        """The writes of ``_to_port`` where every collection holds scalars or records of scalars."""
        lines = []
        for (cname, _), (k, access) in zip(self.port_fields[index], self._port_reads(index)):
            if access.endswith(".#elements"):  # a collection's elements: an array, copied
                source = f"{values[k]}{access[:-len('.#elements')]}.a"
                lines.append(f"{indent}memcpy(d->{cname}.a, {source}, sizeof d->{cname}.a);")
            elif ".#elements." in access:  # one field of a collection's records, element by element
                at, field = access.split(".#elements", 1)
                source = f"{values[k]}{at}"
                lines += [f"{indent}{{",
                          f"{indent}    uint64_t i;",
                          f"{indent}    for (i = 0; i < sizeof d->{cname}.a / sizeof d->{cname}.a[0]; i++)",
                          f"{indent}        d->{cname}.a[i] = i < {source}.n ? {source}.a[i]{field} : 0;",
                          f"{indent}}}"]
            else:
                lines.append(f"{indent}d->{cname} = {values[k]}{access.replace('.#size', '.n')};")
        return lines

    def step(self, indent: str) -> list[str]:
        """The start of a transition segment (a block marked step)."""
        return [f"{indent}RG_BEGIN_TRANSITION(rg_runaway_{self.m.index}(inst));"]

    # ---------------------------------------------------------------- terminators

    def _where(self, span) -> str:
        """'  file:line' of a model element for a comment ('' when unknown or switched off)."""
        return f"  {self.fmu.place(span)}" if (self.line_comments and span is not None) else ""

    def terminator(self, t: ir.Terminator, indent: str) -> list[str]:
        if isinstance(t, ir.Goto):
            return [f"{indent}m->pc = {t.target}; continue;"]
        if isinstance(t, ir.Suspend):
            return [f"{indent}m->pc = {t.target}; return RG_RUN_SUSPENDED;"]
        if isinstance(t, ir.Fail):
            return [f"{indent}return rg_machine_fail(inst, {c_string(self.m.name + ': ' + t.message.render(self.fmu.place))});"]
        if isinstance(t, ir.Branch):
            return self._branch(t, indent)
        raise TypeError(f"no C for {type(t).__name__}")  # pragma: no cover

    def _branch(self, t: ir.Branch, indent: str) -> list[str]:
        """The cases in priority order, each under a comment quoting its guard as the model writes
        it. A case whose guard is the constant true ends the list: what follows is unreachable."""
        lines = []
        for case in t.cases:
            comment = f"{c_comment(case.label)}{' ' + c_comment(case.guard_text) if case.guard_text else ''}"
            known = truth(case.guard)
            if known is False:
                lines.append(f"{indent}/* {comment}: never taken{self._where(case.span)} */")
                continue
            lines.append(f"{indent}/* {comment}{self._where(case.span)} */")
            if known:
                return lines + [f"{indent}m->pc = {case.target}; continue;"]
            self.fallible = False
            guard = self.expr(case.guard)
            if self.fallible:  # the guard may fault: test the fault code before taking the case
                inner = indent + "    "
                lines += [f"{indent}{{", f"{inner}bool g_ = {bare(guard)};", f"{inner}{self.fault_return}",
                          f"{inner}if (g_) {{ m->pc = {case.target}; continue; }}", f"{indent}}}"]
            else:
                lines.append(f"{indent}if ({bare(guard)}) {{ m->pc = {case.target}; continue; }}")
        self.fallible = False
        return lines + self.terminator(t.default, indent)


__all__ = ["Emitter", "CNames", "MachineNames", "Identifiers", "ctype", "literal", "mangle", "var_identifiers",
           "user_function_prototype", "c_string", "c_comment", "tag", "elem_tag", "truth", "bare"]
