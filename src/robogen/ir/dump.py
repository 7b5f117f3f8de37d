"""The canonical text form of the IR, used by tests (pass tests compare dumps), by
`robogen compile --dump-ir`, as the FMU's documentation/ir.txt, and as what the instantiation
token is hashed from. Stable: no addresses, no timestamps, declaration order; and path-free: a
place in the model shows as its line only, so the same model gives the same dump (and token)
wherever its files are."""

from __future__ import annotations

from fractions import Fraction

from robogen.diagnostics import Span
from robogen.ir import model as ir
from robogen.semantics import types as T

_BIN = {
    "and": "/\\", "or": "\\/", "implies": "=>", "iff": "iff", "eq": "==", "ne": "!=", "lt": "<", "le": "<=",
    "gt": ">", "ge": ">=", "add": "+", "sub": "-", "mul": "*", "div": "/", "mod": "%",
}


def dump(fmu: ir.Fmu) -> str:
    out = [
        f"fmu {fmu.name} ({fmu.model_identifier}) {fmu.language} {fmu.semantics}"
        + (f" trigger={fmu.trigger}" if fmu.language == "robosim" else ""),
        f"  {'time' if fmu.time_free else 'clock'} {fmu.clock_name}: every {_num(fmu.period)} time unit(s) x "
        f"{_num(fmu.time_unit)} s = {_num(fmu.clock_interval)} s" + (", idle ones skipped" if fmu.time_free else ""),
    ]
    for p in fmu.inputs:
        out.append(f"  input {p.name}" + _fields(p) + "".join(f" -> m{m}.e{e}" for m, e in p.routes))
    for p in fmu.outputs:
        out.append(f"  output {'abstract ' if p.abstract else ''}{p.kind} {p.name}" + _fields(p))
    for p in fmu.params:
        out.append(f"  parameter {p.fmi_name}: {p.var.type.show()} = {_value(p.value)}" + (" (no value in the model)" if p.free else ""))
    for m in fmu.machines:
        out.append(machine(m))
    text = "\n".join(out) + "\n"
    if "Set(" in text or "Seq(" in text:  # the capacity of collections is part of the model's meaning
        text = text.replace("\n", f"\n  capacity {','.join(map(str, fmu.levels))}\n", 1)
    return text


def _line(span: Span | None) -> str:
    """A place in the dump: its line (no file name)."""
    return f"line {span.line}" if span is not None else "?"


def _fields(p: ir.Port) -> str:
    if not p.fields:
        return ""
    return " (" + ", ".join(f"{f.fmi_name}: {f.type.show()}" for f in p.fields) + ")"


def _value(v: object) -> str:
    if v is None:
        return "<unset>"
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, Fraction):
        return _num(v)
    return str(v)


def _num(v: Fraction | int) -> str:
    if isinstance(v, Fraction):
        return str(v.numerator) if v.denominator == 1 else repr(float(v))
    return str(v)


def machine(m: ir.Machine) -> str:
    out = [f"  machine m{m.index} {m.qname}"]
    for v in m.vars:
        init = f" = {expr(v.init)}" if v.init is not None else ""
        out.append(f"    {v.kind} {v.name}: {v.type.show()}{init}")
    for i, c in enumerate(m.clocks):
        out.append(f"    clock c{i} {c}")
    for e in m.events:
        out.append(f"    event e{e.index} {e.name}" + (f": {e.type.show()}" if e.type is not None else ""))
    for n in m.nodes:
        out.append(f"    node n{n.id} {n.kind} {n.label}")
    out.append(f"    start b{m.start}")
    for b in m.blocks:
        out.append(f"    b{b.id}: {b.label}" + ("  [step]" if b.step else ""))
        for s in b.stmts:
            out.extend("      " + line for line in stmt(s))
        out.append(f"      {terminator(b.term)}")
    return "\n".join(out)


def terminator(t: ir.Terminator | None) -> str:
    if isinstance(t, ir.Goto):
        return f"goto b{t.target}"
    if isinstance(t, ir.Suspend):
        return f"suspend b{t.target}"
    if isinstance(t, ir.Fail):
        return f"fail {t.message.render(_line)!r}"
    if isinstance(t, ir.Branch):
        parts = [f"if {expr(c.guard)} -> b{c.target}  # {c.label}" for c in t.cases]
        return "branch " + ("; ".join(parts) if parts else "(none)") + f"; else {terminator(t.default)}"
    return "<no terminator>"


def stmt(s: ir.Stmt) -> list[str]:
    if isinstance(s, ir.Assign):
        return [f"{expr(s.target)} := {expr(s.value)}"]
    if isinstance(s, ir.Emit):
        routes = ", ".join("port " + str(r[1]) if r[0] == "port" else f"m{r[1]}.e{r[2]}" for r in s.routes) or "nowhere"
        return [f"emit {s.name}({', '.join(expr(a) for a in s.args)}) -> {routes}"]
    if isinstance(s, ir.If):
        lines = [f"if {expr(s.cond)}"]
        lines += ["  " + x for st in s.then for x in stmt(st)]
        if s.otherwise:
            lines.append("else")
            lines += ["  " + x for st in s.otherwise for x in stmt(st)]
        lines.append("end")
        return lines
    if isinstance(s, ir.ResetClock):
        return [f"reset c{s.clock}"]
    if isinstance(s, ir.Enter):
        return [f"resume n{s.node}" if s.resume else f"enter n{s.node}"]
    if isinstance(s, ir.DeadlineMiss):
        return [f"deadline missed {s.text.render(_line)!r}"]
    if isinstance(s, ir.Consume):
        return [f"consume e{s.event}"]
    if isinstance(s, ir.StartWait):
        return [f"wait {expr(s.duration)}"]
    if isinstance(s, ir.Trace):
        return [f"trace {s.text!r}"]
    return [f"<{type(s).__name__}>"]


def expr(e: ir.Expr | None) -> str:
    if e is None:
        return "<none>"
    if isinstance(e, ir.Lit):
        if isinstance(e.type, T.EnumT):
            return f"{e.type.simple}::{e.type.literals[e.value]}"  # type: ignore[index]
        if isinstance(e.value, bool):
            return "true" if e.value else "false"
        if isinstance(e.value, Fraction):
            return repr(float(e.value))
        if isinstance(e.value, str):
            return '"' + e.value.replace("\\", "\\\\").replace('"', '\\"') + '"'
        return str(e.value)
    if isinstance(e, ir.Ref):
        return e.var.name
    if isinstance(e, ir.FieldOf):
        return f"{expr(e.base)}.{e.name}"
    if isinstance(e, ir.IndexOf):
        return f"{expr(e.base)}[{', '.join(expr(i) for i in e.indices)}]"
    if isinstance(e, ir.Un):
        return f"(not {expr(e.operand)})" if e.op == "not" else f"(-{expr(e.operand)})"
    if isinstance(e, ir.Bin):
        first, links = ir.bin_chain(e)
        text = expr(first)
        for link in links:
            text = f"({text} {_BIN[link.op]} {expr(link.right)})"
        return text
    if isinstance(e, ir.Conv):
        return f"{e.type.show()}({expr(e.operand)})"
    if isinstance(e, ir.Cond):
        return f"(if {expr(e.cond)} then {expr(e.then)} else {expr(e.otherwise)})"
    if isinstance(e, ir.Occurred):
        return f"present(e{e.event})"
    if isinstance(e, ir.Payload):
        return f"value(e{e.event})"
    if isinstance(e, ir.BindIn):
        return f"bind(e{e.event} -> {expr(e.target)})" if e.value is None else f"bind(e{e.event}: {expr(e.value)} -> {expr(e.target)})"
    if isinstance(e, ir.Since):
        return f"since(c{e.clock})"
    if isinstance(e, ir.SinceEntry):
        return f"sinceEntry(n{e.node})"
    if isinstance(e, ir.WaitLeft):
        return "wait_left"
    if isinstance(e, ir.Now):
        return "now"
    if isinstance(e, ir.Draw):
        bounds = f"{expr(e.low)}..{expr(e.high)}" if e.low is not None else "[0, 1)"
        return f"random {bounds} ({e.state.name})"
    if isinstance(e, ir.RecordLit):
        return "{" + ", ".join(f"{n} = {expr(v)}" for n, v in e.values) + "}"
    if isinstance(e, ir.VectorLit):
        return "[" + ", ".join(expr(x) for x in e.items) + "]"
    if isinstance(e, ir.CallU):
        return f"user {e.instance or e.name}({', '.join(expr(a) for a in e.args)})"
    if isinstance(e, ir.CallB):
        return f"{e.name}({', '.join(expr(a) for a in e.args)})"
    if isinstance(e, ir.Coll):
        return f"{e.op}<{e.type.show()}>({', '.join(expr(a) for a in e.args)}) @{_line(e.span)}"
    if isinstance(e, ir.Quant):
        domains = ", ".join(_domain(d) for d in e.domains)
        return f"({e.kind} {domains} | {expr(e.pred) if e.pred is not None else 'true'} @ {expr(e.body)}) @{_line(e.span)}"
    return f"<{type(e).__name__}>"


def _domain(d: ir.Domain) -> str:
    if d.kind == "set":
        return f"{d.var.name} in{' nat' if d.natural else ''} {expr(d.set)}"
    if d.kind == "range":
        return f"{d.var.name} in {expr(d.low)}..{expr(d.high)}"
    return f"{d.var.name}: every {d.var.type.show()}"
