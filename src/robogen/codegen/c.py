"""IR expressions, statements and terminators as C99 text.

The C follows the reference interpreter (:mod:`robogen.ir.interp`) operation for operation:
integer arithmetic wraps (through the ``rg_i_*``/``rg_u_*`` helpers of ``model.c``, so no
signed overflow is undefined behaviour), division truncates toward zero, a division by zero or a
vector index out of range sets the model's fault code, which the machine's run function turns
into ``fmi3Error`` after the statement. ``&&`` and ``||`` keep the left-to-right evaluation the
interpreter uses, so the side effects of ``$e?x`` bindings happen in the same order.
"""

from __future__ import annotations

import re

from robogen.ir import model as ir
from robogen.semantics import types as T


def ctype(t: T.Type) -> str:
    if t == T.INT or isinstance(t, T.EnumT):
        return "int64_t"
    if t == T.NAT:
        return "uint64_t"
    if t == T.REAL:
        return "double"
    if t == T.BOOLEAN:
        return "bool"
    if isinstance(t, T.RecordT):
        return "rg_rec_" + mangle(t.qname)
    if isinstance(t, T.VectorT):
        return f"rg_vec_{tag(t.element)}_{t.size}"
    if isinstance(t, T.MatrixT):
        return f"rg_mat_{tag(t.element)}_{t.rows}_{t.columns}"
    raise TypeError(f"no C type for {t.show()}")


def tag(t: T.Type) -> str:
    if t == T.NAT:
        return "u"
    if t == T.REAL:
        return "r"
    if t == T.BOOLEAN:
        return "b"
    return "i"  # int and enumerations


def mangle(name: str) -> str:
    """A C identifier part for a model name (qualified names, '#', '.' become '_')."""
    return re.sub(r"[^A-Za-z0-9_]", "_", name.replace("::", "_"))


def var_identifiers(fmu: ir.Fmu) -> dict[ir.Var, str]:
    """The C member name of every machine variable (the struct member is ``v_<name>``): its
    model name mangled, with a number appended where two names of one machine would clash."""
    names: dict[ir.Var, str] = {}
    for m in fmu.machines:
        taken: set[str] = set()
        for v in m.vars:
            base = name = mangle(v.name)
            n = 2
            while name in taken:
                name, n = f"{base}_{n}", n + 1
            taken.add(name)
            names[v] = name
    return names


def user_function_prototype(u: ir.UserFunction) -> str:
    """The C declaration of a user function, as the --functions file must define it."""
    args = ", ".join(f"{ctype(t)} {n}" for n, t in u.params) or "void"
    return f"static {ctype(u.result)} rg_user_{u.name}({args})"


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


def c_comment(text: str) -> str:
    return text.replace("*/", "* /").replace("/*", "/ *")


def literal(value: object, t: T.Type) -> str:
    if t == T.BOOLEAN:
        return "true" if value else "false"
    if t == T.REAL:
        f = float(value)  # type: ignore[arg-type]
        text = repr(f)
        return text if ("." in text or "e" in text or "inf" in text or "nan" in text) else text + ".0"
    v = int(value)  # type: ignore[arg-type]
    if t == T.NAT:
        return f"UINT64_C({v & ((1 << 64) - 1)})"
    v &= (1 << 64) - 1
    if v >> 63:
        return f"(int64_t)UINT64_C({v})"
    return f"INT64_C({v})"


def zero(t: T.Type) -> str:
    if t == T.BOOLEAN:
        return "false"
    if t == T.REAL:
        return "0.0"
    if isinstance(t, (T.RecordT, T.VectorT, T.MatrixT)):
        return f"rg_zero_{ctype(t)}"
    return "0"


class Emitter:
    """Translates the IR of machine ``m`` (index ``i``) into C text. Machine memory is ``m->``,
    model data ``d->``, the instance ``inst``."""

    def __init__(self, fmu: ir.Fmu, machine: ir.Machine, port_fields, clock_index, names: dict[ir.Var, str]):
        self.fmu = fmu
        self.m = machine
        self.names = names  # variable -> C member name (var_identifiers)
        self.port_fields = port_fields  # port index -> [(c field name, Field_)]
        self.clock_index = clock_index  # port name -> rg_clocks index
        self.fallible = False  # the last expression may set the fault code
        self.equalities: set[str] = set()  # C types whose equality function is needed

    # ---------------------------------------------------------------- expressions

    def expr(self, e: ir.Expr) -> str:
        method = getattr(self, "_" + type(e).__name__)
        return method(e)

    def _Lit(self, e: ir.Lit) -> str:
        return literal(e.value, e.type)

    def _Ref(self, e: ir.Ref) -> str:
        name = self.names[e.var]
        if e.var.owner >= 0 and e.var.owner != self.m.index:
            return f"d->m{e.var.owner}.v_{name}"  # shared, held by another machine
        return f"m->v_{name}"

    def _FieldOf(self, e: ir.FieldOf) -> str:
        return f"{self.expr(e.base)}.{e.name}"

    def _IndexOf(self, e: ir.IndexOf) -> str:
        self.fallible = True
        t = e.base.type
        base = self.expr(e.base)
        if isinstance(t, T.VectorT):
            return f"{base}.a[rg_index(d, {self.expr(e.indices[0])}, {t.size})]"
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
        op = e.op
        a, b = self.expr(e.left), self.expr(e.right)
        if op == "and":
            return f"({a} && {b})"
        if op == "or":
            return f"({a} || {b})"
        if op == "implies":
            return f"(!{a} || {b})"
        if op == "iff":
            return f"(!{a} == !{b})"
        if op in ("eq", "ne"):
            t = e.left.type
            if isinstance(t, (T.RecordT, T.VectorT, T.MatrixT)):
                self.equalities.add(ctype(t))
                test = f"rg_eq_{ctype(t)}({a}, {b})"
                return test if op == "eq" else f"(!{test})"
            return f"({a} {'==' if op == 'eq' else '!='} {b})"
        if op in ("lt", "le", "gt", "ge"):
            return f"({a} {dict(lt='<', le='<=', gt='>', ge='>=')[op]} {b})"
        t = e.type
        if t == T.REAL:
            if op == "div":
                self.fallible = True
                return f"rg_r_div(d, {a}, {b})"
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
        if source == T.NAT and target == T.INT:
            return f"rg_u_to_i({a})"
        return f"(({ctype(target)}){a})"

    def _Cond(self, e: ir.Cond) -> str:
        return f"({self.expr(e.cond)} ? {self.expr(e.then)} : {self.expr(e.otherwise)})"

    def _Occurred(self, e: ir.Occurred) -> str:
        return f"m->smp_present[{e.event}]"

    def _Payload(self, e: ir.Payload) -> str:
        return f"m->smp_e{e.event}"

    def _BindIn(self, e: ir.BindIn) -> str:
        return f"(m->smp_present[{e.event}] ? ({self.expr(e.target)} = m->smp_e{e.event}, true) : false)"

    def _since(self, elapsed: str, t: T.Type) -> str:
        p = self.fmu.period
        if t == T.REAL:
            return f"((double)({elapsed}) * {literal(p, T.REAL)})"
        return f"(({elapsed}) * UINT64_C({int(p)}))"

    def _Since(self, e: ir.Since) -> str:
        return self._since(f"m->ticks - m->clock_reset[{e.clock}]", e.type)

    def _SinceEntry(self, e: ir.SinceEntry) -> str:
        return self._since(f"m->ticks - m->entered[{e.node}]", e.type)

    def _WaitLeft(self, e: ir.WaitLeft) -> str:
        return "m->wait_left"

    def _Now(self, e: ir.Now) -> str:
        return "m->ticks"

    def _RecordLit(self, e: ir.RecordLit) -> str:
        parts = ", ".join(f".{n} = {self.expr(v)}" for n, v in e.values)
        return f"(({ctype(e.type)}){{ {parts} }})"

    def _VectorLit(self, e: ir.VectorLit) -> str:
        return f"(({ctype(e.type)}){{ {{ {', '.join(self.expr(x) for x in e.items)} }} }})"

    def _CallU(self, e: ir.CallU) -> str:
        return f"rg_user_{e.name}({', '.join(self.expr(a) for a in e.args)})"

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
            lines.append(f"{indent}if (d->fault) return rg_fault_{self.m.index}(inst, m->pc);")
        return lines

    def _stmt(self, s: ir.Stmt, indent: str) -> list[str]:
        if isinstance(s, ir.Assign):
            return [f"{indent}{self.expr(s.target)} = {self.expr(s.value)};"]
        if isinstance(s, ir.Emit):
            return self._emit(s, indent)
        if isinstance(s, ir.If):
            fallible = False
            cond = self.expr(s.cond)
            fallible |= self.fallible
            then = self.stmts(s.then, indent + "    ")
            lines = []
            if fallible:
                lines.append(f"{indent}{{")
                lines.append(f"{indent}    bool c_ = {cond};")
                lines.append(f"{indent}    if (d->fault) return rg_fault_{self.m.index}(inst, m->pc);")
                lines.append(f"{indent}    if (c_) {{")
                lines += ["    " + x for x in then]
                if s.otherwise:
                    lines.append(f"{indent}    }} else {{")
                    lines += ["    " + x for x in self.stmts(s.otherwise, indent + "    ")]
                lines.append(f"{indent}    }}")
                lines.append(f"{indent}}}")
            else:
                lines.append(f"{indent}if ({cond}) {{")
                lines += then
                if s.otherwise:
                    lines.append(f"{indent}}} else {{")
                    lines += self.stmts(s.otherwise, indent + "    ")
                lines.append(f"{indent}}}")
            self.fallible = False
            return lines
        if isinstance(s, ir.ResetClock):
            return [f"{indent}m->clock_reset[{s.clock}] = m->ticks;"]
        if isinstance(s, ir.Enter):
            if s.resume:
                return [f"{indent}m->node = {s.node};"]
            return [f"{indent}m->node = {s.node}; m->entered[{s.node}] = m->ticks;"]
        if isinstance(s, ir.DeadlineMiss):
            return [f"{indent}rg_deadline_miss(inst, {c_string(self.m.name + ': ' + s.text.render(self.fmu.place))});"]
        if isinstance(s, ir.Consume):
            return [f"{indent}m->smp_present[{s.event}] = false;"]
        if isinstance(s, ir.StartWait):
            return [f"{indent}{{ int64_t w_ = {self.expr(s.duration)}; m->wait_left = w_ > 0 ? w_ : 0; }}"]
        if isinstance(s, ir.Trace):
            return [f"{indent}RG_TRACE(inst, {c_string(self.m.name + ': ' + s.text)});"]
        raise TypeError(f"no C for {type(s).__name__}")  # pragma: no cover

    def _emit(self, s: ir.Emit, indent: str) -> list[str]:
        lines = [f"{indent}{{"]
        inner = indent + "    "
        for k, a in enumerate(s.args):
            lines.append(f"{inner}{ctype(a.type)} a{k}_ = {self.expr(a)};")
        if self.fallible:
            lines.append(f"{inner}if (d->fault) return rg_fault_{self.m.index}(inst, m->pc);")
            self.fallible = False
        for route in s.routes:
            if route[0] == "port":
                port = self.fmu.outputs[route[1]]
                for cname, f in self.port_fields[route[1]]:
                    if port.kind == "operation":
                        k = [n for n, _ in port.params].index(f.path[0])
                        access = "".join("." + p for p in f.path[1:])
                    else:
                        k = 0
                        access = "".join("." + p for p in f.path)
                    lines.append(f"{inner}d->{cname} = a{k}_{access};")
                lines.append(f"{inner}rg_activate_output_clock(inst, {self.clock_index[port.name]}); /* {c_comment(port.name)} */")
            else:
                _, mi, ei = route
                value = "a0_" if s.args else None
                lines.append(f"{inner}rg_deliver_{mi}_{ei}(d{', ' + value if value else ''});")
        if not s.routes:
            lines.append(f"{inner}/* {c_comment(s.name)} is connected to nothing: evaluated, sent nowhere */")
            lines += [f"{inner}(void)a{k}_;" for k in range(len(s.args))]
        lines.append(f"{indent}}}")
        return lines

    def step(self, indent: str) -> list[str]:
        """The start of a transition segment (a block marked step)."""
        return [
            f"{indent}if (micro && taken) return RG_RUN_MICRO;  /* stepwise: one transition per instant */",
            f"{indent}taken = true;",
            f"{indent}if (++m->transitions > RG_MAX_TRANSITIONS) return rg_runaway_{self.m.index}(inst);",
        ]

    # ---------------------------------------------------------------- terminators

    def _place_suffix(self, span) -> str:
        """' file:line' of a model element for a comment ('' when unknown)."""
        return f" {self.fmu.place(span)}" if span is not None else ""

    def terminator(self, t: ir.Terminator, indent: str) -> list[str]:
        i = self.m.index
        if isinstance(t, ir.Goto):
            return [f"{indent}m->pc = {t.target}; continue;"]
        if isinstance(t, ir.Suspend):
            return [f"{indent}m->pc = {t.target}; return RG_RUN_SUSPENDED;"]
        if isinstance(t, ir.Fail):
            return [f"{indent}return rg_machine_fail(inst, {c_string(self.m.name + ': ' + t.message.render(self.fmu.place))});"]
        if isinstance(t, ir.Branch):
            lines = []
            for case in t.cases:
                self.fallible = False
                guard = self.expr(case.guard)
                where = f"  /* {c_comment(case.label)}{self._place_suffix(case.span)} */"
                if self.fallible:
                    lines.append(f"{indent}{{")
                    lines.append(f"{indent}    bool g_ = {guard};{where}")
                    lines.append(f"{indent}    if (d->fault) return rg_fault_{i}(inst, m->pc);")
                    lines.append(f"{indent}    if (g_) {{ m->pc = {case.target}; continue; }}")
                    lines.append(f"{indent}}}")
                else:
                    lines.append(f"{indent}if ({guard}) {{ m->pc = {case.target}; continue; }}{where}")
            self.fallible = False
            return lines + self.terminator(t.default, indent)
        raise TypeError(f"no C for {type(t).__name__}")  # pragma: no cover


__all__ = ["Emitter", "ctype", "literal", "zero", "mangle", "var_identifiers", "user_function_prototype", "c_string",
           "c_comment", "tag"]
