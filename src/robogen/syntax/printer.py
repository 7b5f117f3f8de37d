"""Print AST expressions, statements and transition labels back in model syntax, with only the
parentheses precedence needs. Used by diagrams, IR dumps and comments in generated code.

:func:`file` prints a whole parsed file in RoboTool's layout (one declaration or transition
clause per line); parsing its output gives back an equal AST (equality ignores spans), which
the tests check on every model they have.
"""

from __future__ import annotations

import contextvars

from robogen.syntax import ast

# Words printed with the keyword escape `^` (set while printing a whole file of one language).
_reserved: contextvars.ContextVar[frozenset[str]] = contextvars.ContextVar("robogen_printer_reserved", default=frozenset())


def _id(name: str) -> str:
    return "^" + name if name in _reserved.get() else name


def _qname(name: ast.Name) -> str:
    return "::".join(_id(p) for p in name.parts)

# Binding strength, loosest first (the precedence of RoboTool's grammar, grammar/robochart.lark).
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
        return _qname(e)
    if isinstance(e, ast.Keyword):
        return e.word
    if isinstance(e, ast.Unary):
        if e.op == "not":
            return f"not {_wrap(e.operand, _LEVEL['not'])}"
        return f"-{_wrap(e.operand, _LEVEL['neg'])}"
    if isinstance(e, ast.Binary):
        return _chain(e)
    if isinstance(e, ast.Field):
        return f"{_wrap(e.obj, _ATOM)}.{_id(e.field)}"
    if isinstance(e, ast.Index):  # `$v[i]` needs no parentheses
        obj = _expr(e.obj) if isinstance(e.obj, ast.Dollar) else _wrap(e.obj, _ATOM)
        return f"{obj}[{', '.join(_expr(i) for i in e.indices)}]"
    if isinstance(e, ast.Call):  # `$f(a)` needs no parentheses either
        func = _expr(e.func) if isinstance(e.func, ast.Dollar) else _wrap(e.func, _ATOM)
        return f"{func}({', '.join(_expr(a) for a in e.args)})"
    if isinstance(e, ast.IfExpr):
        return f"if {_expr(e.cond)} then {_expr(e.then)} else {_expr(e.otherwise)} end"
    if isinstance(e, ast.Cast):
        return f"{_wrap(e.expr, 12)} {e.op} {_type_atom(e.type)}"
    if isinstance(e, ast.Binder):
        decls = ", ".join(f"{_id(d.name)}: {type_expr(d.type)}" for d in e.decls)
        such = f" | {_expr(e.such_that)}" if e.such_that is not None else ""
        # the body of `the` is itself at the level of `the` (the_expr); other binders take any expression
        body = _wrap(e.body, 8) if e.kind == "the" else _expr(e.body)
        return f"{e.kind} {decls}{such} @ {body}"
    if isinstance(e, ast.Let):
        defs = ", ".join(f"{_id(d.name)} == {_expr(d.value)}" for d in e.defs)
        return f"let {defs} @ {_wrap(e.body, 9)}"
    if isinstance(e, ast.RecordLit):
        return f"{_qname(e.type)}(| {', '.join(f'{_id(f.name)} = {_expr(f.value)}' for f in e.fields)} |)"
    if isinstance(e, ast.TupleLit):
        return f"(| {', '.join(_expr(i) for i in e.items)} |)" if e.items else "(||)"
    if isinstance(e, ast.SeqLit):
        return f"<{', '.join(_wrap(i, 12) for i in e.items)}>"
    if isinstance(e, ast.SetLit):
        return "{" + ", ".join(_expr(i) for i in e.items) + "}"
    if isinstance(e, ast.SetRange):
        return "{" + f"{_expr(e.low)} to {_expr(e.high)}" + "}"
    if isinstance(e, ast.SetComprehension):
        decls = ", ".join(f"{_id(d.name)}: {type_expr(d.type)}" for d in e.decls)
        such = f" | {_expr(e.such_that)}" if e.such_that is not None else ""
        body = f" @ {_expr(e.body)}" if e.body is not None else ""
        return "{" + decls + such + body + "}"
    if isinstance(e, ast.Range):
        return f"{'[' if e.low_closed else '('}{_expr(e.low)}, {_expr(e.high)}{']' if e.high_closed else ')'}"
    if isinstance(e, ast.VectorLit):
        return "[| " + "; ".join(", ".join(_expr(x) for x in row) for row in e.rows) + " |]"
    if isinstance(e, ast.Since):
        return f"since({_id(e.clock)})"
    if isinstance(e, ast.SinceEntry):
        return f"sinceEntry({_qname(e.state)})"
    if isinstance(e, ast.MatrixOp):
        return f"{e.op}({_expr(e.operand)})"
    if isinstance(e, ast.Dollar):
        return f"${_path(e.qualifier, e.name)}"
    if isinstance(e, ast.DollarInput):
        pred = f" : {_value(e.predicate)}" if e.predicate is not None else ""
        return f"${_path(e.qualifier, e.event)}?{_path(e.var_qualifier, e.var)}{pred}"
    if isinstance(e, ast.DollarValue):
        return f"${_path(e.qualifier, e.event)}.{_value(e.value)}"
    raise TypeError(f"cannot print {type(e).__name__}")  # pragma: no cover


def _chain(e: ast.Binary) -> str:
    """A chain of binary operators (ast.chain), left to right in a loop. Every operator is
    left-associative: a right operand needs a strictly tighter level, a left operand of a looser
    level is put in parentheses (all those opened at the start, before the leftmost operand)."""
    first, links = ast.chain(e)
    parts = [_expr(first)]
    opened = 0
    for link in links:
        level = _LEVEL[link.op]
        if _level(link.left) < level:
            opened += 1
            parts.append(")")
        parts += [f" {link.op} ", _wrap(link.right, level + 1)]
    return "(" * opened + "".join(parts)


def _path(qualifier: tuple[str, ...], name: str) -> str:
    """A name with the qualifier written before it (``I::x``)."""
    return "::".join(_id(p) for p in qualifier + (name,))


def _value(e: ast.Expr) -> str:
    """The value of a communication, ``$e.v`` or ``$e?x : p``: an atom, a call, or (RoboSim) a
    ``$`` form; anything else in parentheses."""
    if isinstance(e, (ast.Dollar, ast.DollarInput, ast.DollarValue)):
        return _expr(e)
    return _wrap(e, _ATOM)


def type_expr(t: ast.TypeExpr) -> str:
    if isinstance(t, ast.TypeRef):
        return _qname(t.name)
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
        return f"?{_id(t.name)}"
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
            filt = f"[| {_id(f.bind)} = {_expr(f.bind_value)}" + (f" | {_expr(f.predicate)}" if f.predicate is not None else "") + " |]"  # type: ignore[arg-type]
        elif f.predicate is not None:
            filt = f"[| {_expr(f.predicate)} |]"
        else:
            filt = "[||]"
    if c.kind == "?":
        return f"{_id(c.event)}{filt}?{_path(c.var_qualifier, c.var or '')}"
    if c.kind in ("!", "."):
        return f"{_id(c.event)}{filt}{c.kind}{_value(c.value)}"  # type: ignore[arg-type]
    return _id(c.event) + filt


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
        return f"#{_id(s.clock)}"
    if isinstance(s, ast.IfStmt):
        other = f" else {stmt(s.otherwise)}" if s.otherwise is not None else ""
        return f"if {_expr(s.cond)} then {stmt(s.then)}{other} end"
    if isinstance(s, ast.Assign):
        return f"{_expr(s.target)} = {_expr(s.value)}"
    if isinstance(s, ast.CallStmt):
        return _expr(s.call)
    if isinstance(s, ast.Communicate):
        if not s.send and s.comm.kind == "." and s.comm.filter is None and not _sync_value(s.comm.value):
            return f"{_id(s.comm.event)}.({_expr(s.comm.value)})"  # type: ignore[arg-type]
        return ("send " if s.send else "") + communication(s.comm)
    if isinstance(s, ast.StmtDeadline):
        inner = stmt(s.stmt)
        if isinstance(s.stmt, (ast.Seq, ast.StmtDeadline)):  # a deadline applies to a basic statement
            inner = f"({inner})"
        return f"{inner} <{{ {_expr(s.bound)} }}"
    if isinstance(s, ast.DollarOutput):
        if s.kind == "":
            return f"${_path(s.qualifier, s.event)}"
        return f"${_path(s.qualifier, s.event)}{s.kind}{_value(s.value)}"  # type: ignore[arg-type]
    if isinstance(s, ast.DollarCall):
        return f"${_path(s.qualifier, s.op)}({', '.join(_expr(a) for a in s.args)})"
    if isinstance(s, ast.DollarAssign):
        return f"${_path(s.qualifier, s.var)} = {_expr(s.value)}"
    raise TypeError(f"cannot print {type(s).__name__}")  # pragma: no cover


# The atoms that need no parentheses after the `.` of a synchronisation written without `send`
# (`e.v`): the grammar reads a name, or a call, there (`sync_value`), not a record literal or a
# field selection (`e.r.f` would be an assignment target).
_SYNC_ATOMS = (ast.Name, ast.IntLit, ast.RealLit, ast.StringLit, ast.BoolLit, ast.SetLit, ast.SeqLit, ast.SetRange,
               ast.SetComprehension, ast.TupleLit, ast.VectorLit, ast.Range, ast.Since, ast.SinceEntry, ast.MatrixOp)


def _sync_value(e: ast.Expr | None) -> bool:
    """Does the value of an unprefixed synchronisation print as the grammar reads it back?"""
    if isinstance(e, ast.Call):
        return isinstance(e.func, ast.Name) or _level(e.func) < _ATOM
    return isinstance(e, _SYNC_ATOMS) or isinstance(e, ast.Keyword) and e.word in ("result", "from", "to")


def _stmt_in_seq(s: ast.Stmt) -> str:
    return f"({stmt(s)})" if isinstance(s, ast.Seq) else stmt(s)


def _clauses(t: ast.Transition):
    """(kind, text) of each clause a transition has, in the fixed order of the syntax."""
    if t.exec:
        yield "exec", ""
    elif t.trigger is not None:
        yield "trigger", communication(t.trigger)
    elif t.probability is not None:
        yield "probability", _expr(t.probability)
    for r in t.resets:
        yield "reset", _id(r.clock)
    if t.deadline is not None:
        yield "deadline", _expr(t.deadline)
    if t.condition_else:
        yield "else", ""
    elif t.condition is not None:
        yield "condition", _expr(t.condition)
    if t.action is not None:
        yield "action", stmt(t.action)


_LABEL_FORMS = {"exec": "exec", "trigger": "{}", "probability": "p = {}", "reset": "#{}", "deadline": "<{{{}}}",
                "else": "[else]", "condition": "[{}]", "action": "/ {}"}  # fmt: skip
_CLAUSE_FORMS = {"exec": "exec", "trigger": "trigger {}", "probability": "probability {}", "reset": "#{}",
                 "deadline": "<{{ {} }}", "else": "condition else", "condition": "condition {}", "action": "action {}"}  # fmt: skip


def transition_label(t: ast.Transition) -> str:
    """The diagrams' `trigger [guard] / action` form; `exec` stands where the trigger would."""
    return " ".join(_LABEL_FORMS[kind].format(text) for kind, text in _clauses(t))


# ---------------------------------------------------------------------------- whole files


def file(f: ast.File) -> str:
    """A parsed file printed back in RoboTool's layout; keywords used as names are escaped
    with `^` (the reserved words of the file's language)."""
    from robogen.syntax.parser import keywords

    token = _reserved.set(keywords(f.language))
    try:
        out: list[str] = []
        if f.package is not None:
            out.append(f"package {_qname(f.package)}")
        for imp in f.imports:
            out.append(f"import {_qname(imp.name)}{'::*' if imp.wildcard else ''}")
        for item in f.items:
            out.append("")
            out.extend(_decl(item, 0))
        return "\n".join(out) + "\n"
    finally:
        _reserved.reset(token)


_INDENT = "\t"

_CONTAINERS = {
    ast.Interface: "interface",
    ast.Platform: "robotic platform",
    ast.Controller: "controller",
    ast.Module: "module",
    ast.StateMachine: "stm",
    ast.State: "state",
}

_NODE_WORDS = {ast.Initial: "initial", ast.Junction: "junction", ast.Final: "final", ast.Probabilistic: "probabilistic"}


def _params(params: tuple[ast.Param, ...]) -> str:
    return ", ".join(f"{_id(p.name)}: {type_expr(p.type)}" for p in params)


def _block(head: str, members, depth: int) -> list[str]:
    pad = _INDENT * depth
    lines = [f"{pad}{head} {{"]
    for m in members:
        lines.extend(_decl(m, depth + 1))
    lines.append(f"{pad}}}")
    return lines


def _decl(d: ast.Node, depth: int) -> list[str]:
    """The lines of one declaration or member, indented ``depth`` levels."""
    pad = _INDENT * depth
    kind = _CONTAINERS.get(type(d))
    if kind is not None:
        return _block(f"{kind} {_id(d.name)}", d.members, depth)  # type: ignore[attr-defined]
    if isinstance(d, ast.Transition):
        return _transition(d, depth)
    if isinstance(d, ast.OperationDef):
        return _block(f"operation {_id(d.name)}({_params(d.params)})", d.members, depth)
    if isinstance(d, ast.FunctionDef):
        return _block(f"function {_id(d.name)}({_params(d.params)}): {type_expr(d.result)}", d.members, depth)
    if isinstance(d, ast.Record):
        return _block(f"datatype {_id(d.name)}", d.fields, depth)
    if isinstance(d, ast.Enumeration):
        return _block(f"enumeration {_id(d.name)}", d.literals, depth)
    if isinstance(d, ast.Context):
        return _block(f"{d.kind} context", d.members, depth)
    return [pad + _line(d)]


def _line(d: ast.Node) -> str:
    if isinstance(d, ast.GivenType):
        return f"type {_id(d.name)}"
    if isinstance(d, ast.Diagram):
        return f"diagram {_id(d.name)}"
    if isinstance(d, ast.FieldDecl):
        return f"{_id(d.name)}: {type_expr(d.type)}"
    if isinstance(d, ast.EnumLiteral):
        args = f"({', '.join(type_expr(a) for a in d.args)})" if d.args else ""
        return _id(d.name) + args
    if isinstance(d, ast.EventDecl):
        typ = f": {type_expr(d.type)}" if d.type is not None else ""
        return f"{'_broadcast ' if d.broadcast else ''}event {_id(d.name)}{typ}"
    if isinstance(d, ast.VarList):
        decls = ", ".join(
            f"{_id(v.name)}: {type_expr(v.type)}" + (f" = {_expr(v.init)}" if v.init is not None else "") for v in d.vars
        )
        return f"{'const' if d.const else 'var'} {decls}"
    if isinstance(d, ast.ClockDecl):
        return f"clock {_id(d.name)}"
    if isinstance(d, ast.OpSig):
        return f"{_id(d.name)}({_params(d.params)})" + (" [terminates]" if d.terminates else "")
    if isinstance(d, ast.InterfaceRef):
        return f"{d.kind} {_qname(d.name)}"
    if isinstance(d, ast.Reference):
        return f"{d.kind} {_id(d.name)} = {_qname(d.target)}"
    if isinstance(d, ast.Connection):
        text = f"connection {_id(d.source)} on {_id(d.source_event)} to {_id(d.target)} on {_id(d.target_event)}"
        return text + (" ( _async )" if d.asynchronous else "") + (" [ mult ]" if d.bidirectional else "")
    if isinstance(d, ast.CycleDef):
        return f"cycleDef {_expr(d.expr)}"
    if isinstance(d, ast.NodeDecl):
        return f"{_NODE_WORDS[type(d)]} {_id(d.name)}"
    if isinstance(d, ast.StateAction):
        return f"{d.kind} {stmt(d.stmt)}"
    if isinstance(d, ast.Terminates):
        return "terminates"
    if isinstance(d, ast.Precondition):
        return f"precondition {_expr(d.expr)}"
    if isinstance(d, ast.Postcondition):
        return f"postcondition {_expr(d.expr)}"
    raise TypeError(f"cannot print {type(d).__name__}")  # pragma: no cover


def _transition(t: ast.Transition, depth: int) -> list[str]:
    pad = _INDENT * (depth + 1)
    lines = [f"{_INDENT * depth}transition {_id(t.name)} {{", f"{pad}from {_id(t.source)}", f"{pad}to {_id(t.target)}"]
    lines += [pad + _CLAUSE_FORMS[kind].format(text) for kind, text in _clauses(t)]
    lines.append(f"{_INDENT * depth}}}")
    return lines
