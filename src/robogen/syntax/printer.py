"""Print AST expressions, statements and transition labels back in model syntax, with only the
parentheses precedence needs. Used by diagrams, IR dumps and comments in generated code."""

from __future__ import annotations

from robogen.syntax import ast

# Binding strength, loosest first (docs/robosim-robochart.md §2.9).
_LEVEL = {
    "iff": 2,
    "=>": 3,
    "\\/": 4,
    "/\\": 5,
    "not": 6,
    "==": 7, "!=": 7, "<": 7, "<=": 7, ">": 7, ">=": 7, "in": 7,
    "+": 12, "-": 12,
    "*": 13, "/": 13, "%": 13,
    "cat": 14, "^": 14,
    "neg": 15,
}
_ATOM = 19


def _level(e: ast.Expr) -> int:
    if isinstance(e, ast.Binary):
        return _LEVEL[e.op]
    if isinstance(e, ast.Unary):
        return _LEVEL["not"] if e.op == "not" else _LEVEL["neg"]
    if isinstance(e, ast.Binder):
        return 1 if e.kind != "the" else 8
    if isinstance(e, ast.Let):
        return 9
    if isinstance(e, ast.IfExpr):
        return 10
    if isinstance(e, ast.Cast):
        return 11
    if isinstance(e, (ast.Dollar, ast.DollarInput, ast.DollarValue)):
        return 15
    return _ATOM


def expr(e: ast.Expr) -> str:
    return _expr(e)


def _wrap(e: ast.Expr, minimum: int) -> str:
    text = _expr(e)
    return f"({text})" if _level(e) < minimum else text


def _expr(e: ast.Expr) -> str:
    if isinstance(e, ast.IntLit):
        return str(e.value)
    if isinstance(e, ast.RealLit):
        return e.text
    if isinstance(e, ast.BoolLit):
        return "true" if e.value else "false"
    if isinstance(e, ast.StringLit):
        return '"' + e.value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(e, ast.Name):
        return e.text
    if isinstance(e, ast.Keyword):
        return e.word
    if isinstance(e, ast.Unary):
        if e.op == "not":
            return f"not {_wrap(e.operand, _LEVEL['not'])}"
        return f"-{_wrap(e.operand, _LEVEL['neg'])}"
    if isinstance(e, ast.Binary):
        lv = _LEVEL[e.op]
        # left-associative: the right operand needs a strictly tighter level
        return f"{_wrap(e.left, lv)} {e.op} {_wrap(e.right, lv + 1)}"
    if isinstance(e, ast.Field):
        return f"{_wrap(e.obj, _ATOM)}.{e.field}"
    if isinstance(e, ast.Index):
        return f"{_wrap(e.obj, _ATOM)}[{', '.join(_expr(i) for i in e.indices)}]"
    if isinstance(e, ast.Call):
        return f"{_wrap(e.func, _ATOM)}({', '.join(_expr(a) for a in e.args)})"
    if isinstance(e, ast.IfExpr):
        return f"if {_expr(e.cond)} then {_expr(e.then)} else {_expr(e.otherwise)} end"
    if isinstance(e, ast.Cast):
        return f"{_wrap(e.expr, 12)} {e.op} {type_expr(e.type)}"
    if isinstance(e, ast.Binder):
        decls = ", ".join(f"{d.name}: {type_expr(d.type)}" for d in e.decls)
        such = f" | {_expr(e.such_that)}" if e.such_that is not None else ""
        return f"{e.kind} {decls}{such} @ {_expr(e.body)}"
    if isinstance(e, ast.Let):
        defs = ", ".join(f"{d.name} == {_expr(d.value)}" for d in e.defs)
        return f"let {defs} @ {_expr(e.body)}"
    if isinstance(e, ast.RecordLit):
        return f"{e.type.text}(| {', '.join(f'{f.name} = {_expr(f.value)}' for f in e.fields)} |)"
    if isinstance(e, ast.TupleLit):
        return f"(| {', '.join(_expr(i) for i in e.items)} |)"
    if isinstance(e, ast.SeqLit):
        return f"<{', '.join(_wrap(i, 12) for i in e.items)}>"
    if isinstance(e, ast.SetLit):
        return "{" + ", ".join(_expr(i) for i in e.items) + "}"
    if isinstance(e, ast.SetRange):
        return "{" + f"{_expr(e.low)} to {_expr(e.high)}" + "}"
    if isinstance(e, ast.SetComprehension):
        decls = ", ".join(f"{d.name}: {type_expr(d.type)}" for d in e.decls)
        such = f" | {_expr(e.such_that)}" if e.such_that is not None else ""
        body = f" @ {_expr(e.body)}" if e.body is not None else ""
        return "{" + decls + such + body + "}"
    if isinstance(e, ast.Range):
        return f"{'[' if e.low_closed else '('}{_expr(e.low)}, {_expr(e.high)}{']' if e.high_closed else ')'}"
    if isinstance(e, ast.VectorLit):
        return "[| " + "; ".join(", ".join(_expr(x) for x in row) for row in e.rows) + " |]"
    if isinstance(e, ast.Since):
        return f"since({e.clock})"
    if isinstance(e, ast.SinceEntry):
        return f"sinceEntry({e.state.text})"
    if isinstance(e, ast.MatrixOp):
        return f"{e.op}({_expr(e.operand)})"
    if isinstance(e, ast.Dollar):
        return f"${e.name}"
    if isinstance(e, ast.DollarInput):
        pred = f" : {_wrap(e.predicate, _ATOM)}" if e.predicate is not None else ""
        return f"${e.event}?{e.var}{pred}"
    if isinstance(e, ast.DollarValue):
        return f"${e.event}.{_wrap(e.value, _ATOM)}"
    raise TypeError(f"cannot print {type(e).__name__}")  # pragma: no cover


def type_expr(t: ast.TypeExpr) -> str:
    if isinstance(t, ast.TypeRef):
        return t.name.text
    if isinstance(t, ast.SetType):
        return f"Set({type_expr(t.element)})"
    if isinstance(t, ast.SeqType):
        return f"Seq({type_expr(t.element)})"
    if isinstance(t, ast.ProductType):
        return " * ".join(_type_atom(x) for x in t.items)
    if isinstance(t, ast.FunctionType):
        return f"{_type_atom(t.domain)} -> {type_expr(t.range)}"
    if isinstance(t, ast.RelationType):
        return f"{_type_atom(t.domain)} <-> {type_expr(t.range)}"
    if isinstance(t, ast.TypeVar_):
        return f"?{t.name}"
    if isinstance(t, ast.VectorType):
        return f"vector({type_expr(t.element)}, {_expr(t.size)})"
    if isinstance(t, ast.MatrixType):
        return f"matrix({type_expr(t.element)}, {_expr(t.rows)}, {_expr(t.columns)})"
    raise TypeError(f"cannot print {type(t).__name__}")  # pragma: no cover


def _type_atom(t: ast.TypeExpr) -> str:
    text = type_expr(t)
    return f"({text})" if isinstance(t, (ast.ProductType, ast.FunctionType, ast.RelationType)) else text


def communication(c: ast.Communication) -> str:
    filt = ""
    if c.filter is not None:
        f = c.filter
        if f.bind is not None:
            filt = f"[| {f.bind} = {_expr(f.bind_value)}" + (f" | {_expr(f.predicate)}" if f.predicate is not None else "") + " |]"  # type: ignore[arg-type]
        else:
            filt = f"[| {_expr(f.predicate)} |]"  # type: ignore[arg-type]
    if c.kind == "?":
        return f"{c.event}{filt}?{c.var}"
    if c.kind in ("!", "."):
        return f"{c.event}{filt}{c.kind}{_wrap(c.value, _ATOM)}"  # type: ignore[arg-type]
    return c.event + filt


def stmt(s: ast.Stmt) -> str:
    if isinstance(s, ast.Seq):
        return " ; ".join(_stmt_in_seq(x) for x in s.stmts)
    if isinstance(s, ast.Skip):
        return "skip"
    if isinstance(s, ast.Exec):
        return "exec"
    if isinstance(s, ast.Wait):
        return f"wait({_expr(s.duration)})"
    if isinstance(s, ast.ClockReset):
        return f"#{s.clock}"
    if isinstance(s, ast.IfStmt):
        other = f" else {stmt(s.otherwise)}" if s.otherwise is not None else ""
        return f"if {_expr(s.cond)} then {stmt(s.then)}{other} end"
    if isinstance(s, ast.Assign):
        return f"{_expr(s.target)} = {_expr(s.value)}"
    if isinstance(s, ast.CallStmt):
        return _expr(s.call)
    if isinstance(s, ast.Communicate):
        return ("send " if s.send else "") + communication(s.comm)
    if isinstance(s, ast.StmtDeadline):
        return f"{_stmt_in_seq(s.stmt)} <{{ {_expr(s.bound)} }}"
    if isinstance(s, ast.DollarOutput):
        if s.kind == "":
            return f"${s.event}"
        return f"${s.event}{s.kind}{_wrap(s.value, _ATOM)}"  # type: ignore[arg-type]
    if isinstance(s, ast.DollarCall):
        return f"${s.op}({', '.join(_expr(a) for a in s.args)})"
    if isinstance(s, ast.DollarAssign):
        return f"${s.var} = {_expr(s.value)}"
    raise TypeError(f"cannot print {type(s).__name__}")  # pragma: no cover


def _stmt_in_seq(s: ast.Stmt) -> str:
    return f"({stmt(s)})" if isinstance(s, ast.Seq) else stmt(s)


def transition_label(t: ast.Transition) -> str:
    """The diagrams' `trigger [guard] / action` form; `exec` stands where the trigger would."""
    parts = []
    if t.exec:
        parts.append("exec")
    elif t.trigger is not None:
        parts.append(communication(t.trigger))
    elif t.probability is not None:
        parts.append(f"p = {_expr(t.probability)}")
    for r in t.resets:
        parts.append(f"#{r.clock}")
    if t.deadline is not None:
        parts.append(f"<{{{_expr(t.deadline)}}}")
    if t.condition_else:
        parts.append("[else]")
    elif t.condition is not None:
        parts.append(f"[{_expr(t.condition)}]")
    if t.action is not None:
        parts.append(f"/ {stmt(t.action)}")
    return " ".join(parts)
