"""The transformer that turns the LALR parse into :mod:`robogen.syntax.ast` nodes.

It runs inside the parse (Lark calls its callbacks at each reduction, so no parse tree is
built), computes every node's span from the tokens, reports reserved words used as names, and
measures how deeply constructs nest (see :data:`MAX_NESTING`). Only robogen.syntax uses it.
"""

from __future__ import annotations

import bisect
import dataclasses
import re
from typing import Callable

from lark import Token, Transformer

from robogen.diagnostics import Diagnostic, Span, error
from robogen.syntax import ast

# How deeply expressions, statements, types and states may nest (real models stay below 20).
MAX_NESTING = 100


class _Positioned:
    """Helper values passed between callbacks that are not AST nodes but keep a position."""

    __slots__ = ("pos",)


class _Package(_Positioned):
    __slots__ = ("name",)

    def __init__(self, name: ast.Name):
        self.name = name
        self.pos = _node_pos(name)


class _Flag(_Positioned):
    __slots__ = ("what",)

    def __init__(self, what: str, pos=None):
        self.what = what
        self.pos = pos


class _Clause(_Positioned):
    __slots__ = ("key", "value")

    def __init__(self, key: str, value, pos=None):
        self.key = key
        self.value = value
        self.pos = pos


class _SuchThat(_Positioned):
    __slots__ = ("expr",)

    def __init__(self, expr):
        self.expr = expr
        self.pos = _node_pos(expr)


class _Body(_Positioned):
    __slots__ = ("expr",)

    def __init__(self, expr):
        self.expr = expr
        self.pos = _node_pos(expr)


def _node_pos(x) -> tuple[int, int] | None:
    return _span_pos(getattr(x, "span", None))


def _span_pos(span: Span | None) -> tuple[int, int] | None:
    if span is not None and span.offset >= 0:
        return (span.offset, span.end_offset)
    return None


def _pos(x) -> tuple[int, int] | None:
    """(start, end) character offsets of a callback child, if it has any."""
    if isinstance(x, Token):
        return (x.start_pos, x.end_pos) if x.start_pos is not None else None
    if isinstance(x, ast.Node):
        return _node_pos(x)
    if isinstance(x, _Positioned):
        return x.pos
    if isinstance(x, (tuple, list)) and x:
        a, b = _pos(x[0]), _pos(x[-1])
        if a and b:
            return (a[0], b[1])
    return None


class ToAst(Transformer):
    """Builds AST nodes bottom-up, with spans computed from the children's positions.

    Lark drops the anonymous keyword and punctuation tokens, so a rule's span starts at its
    first kept child; where the grammar guarantees a token before or after (a leading keyword,
    a closing parenthesis), ``_span(children, left=..., right=...)`` grows the span over it.
    Reserved words used as names are reported, not raised, so all such problems are listed.
    """

    def __init__(self, language: str, reserved: Callable[[], frozenset[str]]):
        super().__init__(visit_tokens=False)
        self.language = language
        self._reserved = reserved  # the language's keywords, asked for once the parser exists
        self._keywords: frozenset[str] | None = None
        self.begin("<string>", "")

    def begin(self, path: str, text: str) -> None:
        self.path = path
        self.text = text
        self.problems: list[Diagnostic] = []
        self._line_starts = [0] + [m.end() for m in re.finditer("\n", text)]
        # nesting depth of the nodes of recursive constructs, by id (see _nest)
        self._depth: dict[int, int] = {}
        self._alive: list = []  # keeps those nodes alive, so that their ids stay unique
        self._too_deep = False

    def end(self) -> list[Diagnostic]:
        # in source order (callbacks run at reductions, an enclosing construct after its parts)
        problems = sorted(self.problems, key=lambda d: (d.span.line, d.span.column) if d.span else (0, 0))
        self.begin("<string>", "")
        return problems

    @property
    def keywords(self) -> frozenset[str]:
        if self._keywords is None:
            self._keywords = self._reserved()
        return self._keywords

    # -- nesting

    def _nest(self, node, c):
        """Record how deeply ``node`` nests constructs of its own kind (expressions, statements,
        types, states), from the depths of its children. Later stages walk the tree
        recursively, so a file nested deeper than MAX_NESTING is rejected here, with its
        location, rather than overflowing the interpreter's stack somewhere downstream."""
        depth = self._depth
        d = 0
        for x in c:
            if type(x) is tuple:
                for y in x:
                    if type(y) is tuple:
                        for z in y:
                            v = depth.get(id(z), 0)
                            d = v if v > d else d
                    else:
                        v = depth.get(id(y), 0)
                        d = v if v > d else d
            else:
                v = depth.get(id(x), 0)
                d = v if v > d else d
        d += 1
        depth[id(node)] = d
        self._alive.append(node)
        if d > MAX_NESTING and not self._too_deep:
            self._too_deep = True
            self.problems.append(
                error(
                    f"nested too deeply: robogen accepts at most {MAX_NESTING} levels of nested expressions, "
                    "statements, types or states",
                    getattr(node, "span", None) or self._span(c),
                )
            )
        return node

    # -- positions

    def _line_col(self, offset: int) -> tuple[int, int]:
        line = bisect.bisect_right(self._line_starts, offset)
        return line, offset - self._line_starts[line - 1] + 1

    def _make(self, start: int, end: int) -> Span:
        line, col = self._line_col(start)
        end_line, end_col = self._line_col(end)
        return Span(self.path, line, col, end_line, end_col, start, end)

    def _span(self, children, left: tuple[str, ...] = (), right: tuple[str, ...] = ()) -> Span | None:
        first = last = None
        for c in children:
            first = _pos(c)
            if first:
                break
        for c in reversed(children):
            last = _pos(c)
            if last:
                break
        if first is None or last is None:
            return None
        start, end = first[0], last[1]
        text = self.text
        for word in reversed(left):
            p = start
            while p > 0 and text[p - 1].isspace():
                p -= 1
            if p >= len(word) and text.startswith(word, p - len(word)):
                start = p - len(word)
            else:
                break
        for word in right:
            p = end
            n = len(text)
            while p < n and text[p].isspace():
                p += 1
            if text.startswith(word, p):
                end = p + len(word)
            else:
                break
        return self._make(start, end)

    def _tspan(self, token: Token) -> Span:
        return Span(
            self.path, token.line or 1, token.column or 1, token.end_line or token.line or 1,
            token.end_column or (token.column or 1) + len(token), token.start_pos if token.start_pos is not None else -1,
            token.end_pos if token.end_pos is not None else -1,
        )

    def _name(self, token: Token) -> str:
        text = str(token)
        if text.startswith("^"):
            return text[1:]
        if text in self.keywords:
            self.problems.append(
                error(f"'{text}' is a reserved word and cannot be used as a name (write ^{text} to escape it)", self._tspan(token))
            )
        return text

    # -- file structure

    def start(self, c):
        package = None
        imports, items = [], []
        for x in c:
            if isinstance(x, _Package):
                package = x.name
            elif isinstance(x, ast.Import):
                imports.append(x)
            else:
                items.append(x)
        return ast.File(self.path, self.language, package, tuple(imports), tuple(items), span=self._span(c))

    def package(self, c):
        package = _Package(c[0])
        package.pos = _span_pos(self._span(c, left=("package",)))
        return package

    def import_(self, c):
        return ast.Import(c[0], len(c) > 1, span=self._span(c, left=("import",)))

    def diagram(self, c):
        return ast.Diagram(self._name(c[0]), span=self._span(c, left=("diagram",)), name_span=self._tspan(c[0]))

    def qname(self, c):
        return ast.Name(tuple(self._name(t) for t in c), span=self._span(c))

    # -- types

    def given_type(self, c):
        return ast.GivenType(self._name(c[0]), span=self._span(c, left=("type",)), name_span=self._tspan(c[0]))

    def record(self, c):
        right = ("}",) if len(c) > 1 else ("{", "}")
        span = self._span(c, left=("datatype",), right=right)
        if span is not None and span.offset == c[0].start_pos:
            span = self._span(c, left=("record",), right=right)
        return ast.Record(self._name(c[0]), tuple(c[1:]), span=span, name_span=self._tspan(c[0]))

    def record_field(self, c):
        return ast.FieldDecl(self._name(c[0]), c[1], span=self._span(c), name_span=self._tspan(c[0]))

    def enumeration(self, c):
        right = ("}",) if len(c) > 1 else ("{", "}")
        return ast.Enumeration(
            self._name(c[0]), tuple(c[1:]), span=self._span(c, left=("enumeration",), right=right), name_span=self._tspan(c[0])
        )

    def literal(self, c):
        return ast.EnumLiteral(self._name(c[0]), tuple(c[1:]), span=self._span(c, right=(")",) if len(c) > 1 else ()), name_span=self._tspan(c[0]))

    def function_type(self, c):
        return ast.FunctionType(c[0], c[1], span=self._span(c))

    def relation_type(self, c):
        return ast.RelationType(c[0], c[1], span=self._span(c))

    def product_type(self, c):
        return ast.ProductType(tuple(c), span=self._span(c))

    def type_ref(self, c):
        return ast.TypeRef(c[0], span=self._span(c))

    def set_type(self, c):
        return ast.SetType(c[0], span=self._span(c, left=("Set", "("), right=(")",)))

    def seq_type(self, c):
        return ast.SeqType(c[0], span=self._span(c, left=("Seq", "("), right=(")",)))

    def type_var(self, c):
        return ast.TypeVar_(self._name(c[0]), span=self._span(c, left=("?",)))

    def vector_type(self, c):
        return ast.VectorType(c[0], c[1], span=self._span(c, left=("vector", "("), right=(")",)))

    def matrix_type(self, c):
        return ast.MatrixType(c[0], c[1], c[2], span=self._span(c, left=("matrix", "("), right=(")",)))

    # -- declarations

    def broadcast(self, c):
        return _Flag("broadcast", _pos(c[0]))

    def event_decl(self, c):
        broadcast = bool(c) and isinstance(c[0], _Flag)
        rest = c[1:] if broadcast else c
        return ast.EventDecl(
            self._name(rest[0]),
            rest[1] if len(rest) > 1 else None,
            broadcast,
            span=self._span(c, left=() if broadcast else ("event",)),
            name_span=self._tspan(rest[0]),
        )

    def var_kind(self, c):
        return c[0]

    def var_list(self, c):
        return ast.VarList(c[0] == "const", tuple(c[1:]), span=self._span(c))

    def var_decl(self, c):
        return ast.VarDecl(self._name(c[0]), c[1], c[2] if len(c) > 2 else None, span=self._span(c), name_span=self._tspan(c[0]))

    def clock_decl(self, c):
        return ast.ClockDecl(self._name(c[0]), span=self._span(c, left=("clock",)), name_span=self._tspan(c[0]))

    def op_sig(self, c):
        params: tuple = ()
        terminates = False
        for x in c[1:]:
            if isinstance(x, tuple):
                params = x
            elif isinstance(x, _Flag):
                terminates = True
        return ast.OpSig(
            self._name(c[0]), params, terminates, span=self._span(c, right=() if terminates else (")",)) if params or terminates else self._span(c, right=("(", ")")),
            name_span=self._tspan(c[0]),
        )

    def terminates_flag(self, c):
        return _Flag("terminates", _span_pos(self._span(c, left=("[",), right=("]",))))

    def params(self, c):
        return tuple(c)

    def param(self, c):
        return ast.Param(self._name(c[0]), c[1], span=self._span(c), name_span=self._tspan(c[0]))

    def iface_kind(self, c):
        return c[0]

    def iface_ref(self, c):
        return ast.InterfaceRef(str(c[0]), c[1], span=self._span(c))

    def _container(self, cls, c, keyword: tuple[str, ...]):
        right = ("}",) if len(c) > 1 else ("{", "}")
        return cls(self._name(c[0]), tuple(c[1:]), span=self._span(c, left=keyword, right=right), name_span=self._tspan(c[0]))

    def interface(self, c):
        return self._container(ast.Interface, c, ("interface",))

    def platform(self, c):
        return self._container(ast.Platform, c, ("robotic", "platform"))

    def controller(self, c):
        return self._container(ast.Controller, c, ("controller",))

    def module(self, c):
        return self._container(ast.Module, c, ("module",))

    def stm(self, c):
        return self._container(ast.StateMachine, c, ("stm",))

    def ref_kind(self, c):
        return c[0]

    def reference(self, c):
        return ast.Reference(self._name(c[1]), str(c[0]), c[2], span=self._span(c), name_span=self._tspan(c[1]))

    def async_flag(self, c):
        return _Flag("async", _span_pos(self._span(c, left=("(",), right=(")",))))

    def mult_flag(self, c):
        return _Flag("mult", _span_pos(self._span(c, left=("[",), right=("]",))))

    def connection(self, c):
        names, flags = c[:4], {f.what for f in c[4:]}
        return ast.Connection(
            *(self._name(t) for t in names),
            asynchronous="async" in flags,
            mult="mult" in flags,
            span=self._span(c, left=("connection",)),
            spans=tuple(self._tspan(t) for t in names),
        )

    def _with_params(self, c):
        params: tuple = ()
        rest = c[1:]
        if rest and isinstance(rest[0], tuple):
            params, rest = rest[0], rest[1:]
        return params, rest

    def operation_def(self, c):
        params, rest = self._with_params(c)
        right = ("}",) if rest else ("(", ")", "{", "}")[0 if not params else 1:]
        return ast.OperationDef(
            self._name(c[0]), params, tuple(rest), span=self._span(c, left=("operation",), right=right), name_span=self._tspan(c[0])
        )

    def function_def(self, c):
        params, rest = self._with_params(c)
        right = ("}",) if len(rest) > 1 else ("{", "}")
        return ast.FunctionDef(
            self._name(c[0]), params, rest[0], tuple(rest[1:]), span=self._span(c, left=("function",), right=right), name_span=self._tspan(c[0])
        )

    def terminates(self, c):
        return ast.Terminates(span=self._span(c))

    def precondition(self, c):
        return ast.Precondition(c[0], span=self._span(c, left=("precondition",)))

    def postcondition(self, c):
        return ast.Postcondition(c[0], span=self._span(c, left=("postcondition",)))

    def cycle_def(self, c):
        return ast.CycleDef(c[0], span=self._span(c, left=("cycleDef",)))

    def context_kind(self, c):
        return c[0]

    def context(self, c):
        return ast.Context(str(c[0]), tuple(c[1:]), span=self._span(c, right=("}",)) if len(c) > 1 else self._span(c, right=("context", "{", "}")))

    # -- nodes and transitions

    def _node(self, cls, c, keyword: str):
        return cls(self._name(c[0]), span=self._span(c, left=(keyword,)), name_span=self._tspan(c[0]))

    def initial(self, c):
        return self._node(ast.Initial, c, "initial")

    def junction(self, c):
        return self._node(ast.Junction, c, "junction")

    def final(self, c):
        return self._node(ast.Final, c, "final")

    def probabilistic(self, c):
        return self._node(ast.Probabilistic, c, "probabilistic")

    def state(self, c):
        return self._container(ast.State, c, ("state",))

    def action_kind(self, c):
        return c[0]

    def state_action(self, c):
        return ast.StateAction(str(c[0]), c[1], span=self._span(c))

    def transition(self, c):
        name, source, target = c[0], c[1], c[2]
        fields: dict = {}
        resets = []
        for x in c[3:]:
            if isinstance(x, _Clause):
                fields[x.key] = x.value
            elif isinstance(x, ast.ClockReset):
                resets.append(x)
        return ast.Transition(
            self._name(name),
            self._name(source),
            self._name(target),
            trigger=fields.get("trigger"),
            exec=fields.get("exec", False),
            probability=fields.get("probability"),
            resets=tuple(resets),
            deadline=fields.get("deadline"),
            condition=fields.get("condition"),
            condition_else=fields.get("condition_else", False),
            action=fields.get("action"),
            span=self._span(c, left=("transition",), right=("}",)),
            name_span=self._tspan(name),
            source_span=self._tspan(source),
            target_span=self._tspan(target),
        )

    def trigger(self, c):
        return _Clause("trigger", c[0], _pos(c[0]))

    def exec_trigger(self, c):
        return _Clause("exec", True, _pos(c[0]))

    def probability(self, c):
        return _Clause("probability", c[0], _pos(c[0]))

    def reset(self, c):
        return ast.ClockReset(self._name(c[0]), span=self._span(c, left=("#",)), clock_span=self._tspan(c[0]))

    def deadline(self, c):
        return _Clause("deadline", c[0], _span_pos(self._span(c, left=("<{",), right=("}",))))

    def condition(self, c):
        return _Clause("condition", c[0], _pos(c[0]))

    def condition_else(self, c):
        return _Clause("condition_else", True, _pos(c[0]))

    def action(self, c):
        return _Clause("action", c[0], _pos(c[0]))

    def communication(self, c):
        event = c[0]
        filt = None
        suffix = None
        for x in c[1:]:
            if isinstance(x, ast.Filter):
                filt = x
            else:
                suffix = x
        kind, var, value, var_span = "", None, None, None
        if suffix is not None:
            kind, payload = suffix
            if kind == "?":
                var, var_span = self._name(payload), self._tspan(payload)
            else:
                value = payload
        parts = [event] + ([filt] if filt else []) + ([suffix[1]] if suffix else [])
        return ast.Communication(
            self._name(event), kind, var, value, filt, span=self._span(parts), event_span=self._tspan(event), var_span=var_span
        )

    def comm_input(self, c):
        return ("?", c[0])

    def comm_output(self, c):
        return ("!", c[0])

    def comm_sync(self, c):
        return (".", c[0])

    def filter_bind(self, c):
        return ast.Filter(self._name(c[0]), c[1], c[2] if len(c) > 2 else None, span=self._span(c, left=("[|",), right=("|]",)))

    def filter_pred(self, c):
        return ast.Filter(None, None, c[0], span=self._span(c, left=("[|",), right=("|]",)))

    # -- statements

    def seq(self, c):
        left, right = c
        items = left.stmts if isinstance(left, ast.Seq) else (left,)
        node = ast.Seq(items + (right,), span=self._span(c))
        # a sequence is flat: its depth is one more than its deepest statement
        if isinstance(left, ast.Seq):
            depth = self._depth
            d = max(depth.get(id(left), 1), depth.get(id(right), 0) + 1)
            depth[id(node)] = d
            self._alive.append(node)
            return node
        return self._nest(node, c)

    def stmt_deadline(self, c):
        return ast.StmtDeadline(c[0], c[1], span=self._span(c, right=("}",)))

    def skip(self, c):
        return ast.Skip(span=self._span(c))

    def exec_stmt(self, c):
        return ast.Exec(span=self._span(c))

    def wait(self, c):
        return ast.Wait(c[0], span=self._span(c, left=("wait", "("), right=(")",)))

    def clock_reset(self, c):
        return ast.ClockReset(self._name(c[0]), span=self._span(c, left=("#",)), clock_span=self._tspan(c[0]))

    def if_stmt(self, c):
        return ast.IfStmt(c[0], c[1], c[2] if len(c) > 2 else None, span=self._span(c, left=("if",), right=("end",)))

    def send(self, c):
        return ast.Communicate(c[0], True, span=self._span(c, left=("send",)))

    def bare_stmt(self, c):
        """A statement that is only a target: a call `op(args)`, a plain event `e`, or `e.v`."""
        target = c[0]
        span = self._span(c)
        if isinstance(target, ast.Call):
            return ast.CallStmt(target, span=span)
        if isinstance(target, ast.Name) and not target.qualified:
            comm = ast.Communication(target.last, span=span, event_span=target.span)
            return ast.Communicate(comm, False, span=span)
        if isinstance(target, ast.Field) and isinstance(target.obj, ast.Name) and not target.obj.qualified:
            value = ast.Name((target.field,), span=target.field_span)
            comm = ast.Communication(target.obj.last, ".", value=value, span=span, event_span=target.obj.span)
            return ast.Communicate(comm, False, span=span)
        self.problems.append(error("this expression is not a statement (expected an assignment, a call or a communication)", span))
        return ast.Skip(span=span)

    def assign(self, c):
        return ast.Assign(c[0], c[1], span=self._span(c))

    def _stmt_comm(self, c, kind):
        target, payload = c
        span = self._span(c)
        if not (isinstance(target, ast.Name) and not target.qualified):
            self.problems.append(error("a communication must name an event", target.span or span))
            return ast.Skip(span=span)
        if kind == "?":
            comm = ast.Communication(target.last, "?", self._name(payload), span=span, event_span=target.span, var_span=self._tspan(payload))
        else:
            comm = ast.Communication(target.last, "!", value=payload, span=span, event_span=target.span)
        return ast.Communicate(comm, False, span=span)

    def comm_input_stmt(self, c):
        return self._stmt_comm(c, "?")

    def comm_output_stmt(self, c):
        return self._stmt_comm(c, "!")

    def dollar_stmt(self, c):
        return ast.DollarOutput(self._name(c[0]), "", None, span=self._span(c, left=("$",)), event_span=self._tspan(c[0]))

    def dollar_output(self, c):
        return ast.DollarOutput(self._name(c[0]), "!", c[1], span=self._span(c, left=("$",)), event_span=self._tspan(c[0]))

    def dollar_sync(self, c):
        return ast.DollarOutput(self._name(c[0]), ".", c[1], span=self._span(c, left=("$",)), event_span=self._tspan(c[0]))

    def dollar_call(self, c):
        args = c[1] if len(c) > 1 else ()
        right = (")",) if args else ("(", ")")
        return ast.DollarCall(self._name(c[0]), args, span=self._span(c, left=("$",), right=right), op_span=self._tspan(c[0]))

    def dollar_assign(self, c):
        return ast.DollarAssign(self._name(c[0]), c[1], span=self._span(c, left=("$",)), var_span=self._tspan(c[0]))

    # -- expressions

    def binder_kind(self, c):
        return c[0]

    def binder(self, c):
        kind, decls = c[0], c[1]
        such_that = c[2].expr if len(c) == 4 else None
        return ast.Binder(str(kind), decls, such_that, c[-1], span=self._span(c))

    def decls(self, c):
        return tuple(c)

    def decl(self, c):
        return ast.Decl(self._name(c[0]), c[1], span=self._span(c), name_span=self._tspan(c[0]))

    def such_that(self, c):
        return _SuchThat(c[0])

    def _binary(self, op, c):
        return ast.Binary(op, c[0], c[-1], span=self._span(c))

    def iff(self, c):
        return self._binary("iff", c)

    def implies(self, c):
        return self._binary("=>", c)

    def or_(self, c):
        return self._binary("\\/", c)

    def and_(self, c):
        return self._binary("/\\", c)

    def not_(self, c):
        return ast.Unary("not", c[0], span=self._span(c, left=("not",)))

    def cmp_op(self, c):
        return c[0]

    def compare(self, c):
        return ast.Binary(str(c[1]), c[0], c[2], span=self._span(c))

    def member(self, c):
        return self._binary("in", c)

    def the(self, c):
        decls = c[0]
        such_that = c[1].expr if len(c) == 3 else None
        return ast.Binder("the", decls, such_that, c[-1], span=self._span(c, left=("the",)))

    def let(self, c):
        return ast.Let(tuple(c[:-1]), c[-1], span=self._span(c, left=("let",)))

    def let_def(self, c):
        return ast.LetDef(self._name(c[0]), c[1], span=self._span(c), name_span=self._tspan(c[0]))

    def if_expr(self, c):
        return ast.IfExpr(c[0], c[1], c[2], span=self._span(c, left=("if",), right=("end",)))

    def cast_op(self, c):
        return c[0]

    def cast(self, c):
        return ast.Cast(str(c[1]), c[0], c[2], span=self._span(c))

    add_op = mul_op = cat_op = cast_op

    def arith(self, c):
        return ast.Binary(str(c[1]), c[0], c[2], span=self._span(c))

    def neg(self, c):
        return ast.Unary("-", c[0], span=self._span(c, left=("-",)))

    def field(self, c):
        return ast.Field(c[0], self._name(c[1]), span=self._span(c), field_span=self._tspan(c[1]))

    def index(self, c):
        return ast.Index(c[0], c[1], span=self._span(c, right=("]",)))

    def call(self, c):
        args = c[1] if len(c) > 1 else ()
        return ast.Call(c[0], args, span=self._span(c, right=(")",) if args else ("(", ")")))

    def args(self, c):
        return tuple(c)

    def int_lit(self, c):
        return ast.IntLit(int(c[0]), span=self._span(c))

    def real_lit(self, c):
        return ast.RealLit(str(c[0]), span=self._span(c))

    def string_lit(self, c):
        raw = str(c[0])[1:-1]
        return ast.StringLit(re.sub(r"\\(.)", r"\1", raw), span=self._span(c))

    def true_lit(self, c):
        return ast.BoolLit(True, span=self._span(c))

    def false_lit(self, c):
        return ast.BoolLit(False, span=self._span(c))

    def name(self, c):
        return c[0]  # a qname already built as ast.Name

    def result(self, c):
        return ast.Keyword("result", span=self._span(c))

    def from_atom(self, c):
        return ast.Keyword("from", span=self._span(c))

    def to_atom(self, c):
        return ast.Keyword("to", span=self._span(c))

    def cycle_atom(self, c):
        return ast.Keyword("cycle", span=self._span(c))

    def _range(self, c, low_closed, high_closed):
        return ast.Range(
            c[0], c[1], low_closed, high_closed,
            span=self._span(c, left=("[" if low_closed else "(",), right=("]" if high_closed else ")",)),
        )

    def range_oo(self, c):
        return self._range(c, False, False)

    def range_oc(self, c):
        return self._range(c, False, True)

    def range_cc(self, c):
        return self._range(c, True, True)

    def range_co(self, c):
        return self._range(c, True, False)

    def since(self, c):
        return ast.Since(self._name(c[0]), span=self._span(c, left=("since", "("), right=(")",)), clock_span=self._tspan(c[0]))

    def since_entry(self, c):
        return ast.SinceEntry(c[0], span=self._span(c, left=("sinceEntry", "("), right=(")",)))

    def seq_lit(self, c):
        items = c[0] if len(c) > 1 else ()
        return ast.SeqLit(items, span=self._span(c, left=("<",)))

    def paren(self, c):
        """`( e )`, `( S )` or `( T )`: the node inside, its span widened over the parentheses."""
        node = c[0]
        span = self._span(c, left=("(",), right=(")",))
        if span is None or node.span is None:
            return node
        wider = dataclasses.replace(node, span=span)
        self._depth[id(wider)] = self._depth.get(id(node), 0)
        self._alive.append(wider)
        return wider

    def seq_items(self, c):
        return tuple(c)

    def set_empty(self, c):
        return ast.SetLit((), span=self._span(c, left=("{",)))

    def set_lit(self, c):
        return ast.SetLit(tuple(c), span=self._span(c, left=("{",), right=("}",)))

    def set_range(self, c):
        return ast.SetRange(c[0], c[1], span=self._span(c, left=("{",), right=("}",)))

    def set_comprehension(self, c):
        decls = c[0]
        such_that = next((x.expr for x in c[1:] if isinstance(x, _SuchThat)), None)
        body = next((x.expr for x in c[1:] if isinstance(x, _Body)), None)
        return ast.SetComprehension(decls, such_that, body, span=self._span(c, left=("{",), right=("}",)))

    def set_body(self, c):
        return _Body(c[0])

    def tuple_lit(self, c):
        return ast.TupleLit(tuple(c), span=self._span(c, left=("(|",), right=("|)",)))

    def record_lit(self, c):
        return ast.RecordLit(c[0], tuple(c[1:]), span=self._span(c, right=("|)",)))

    def field_value(self, c):
        return ast.FieldValue(self._name(c[0]), c[1], span=self._span(c), name_span=self._tspan(c[0]))

    def vector_lit(self, c):
        return ast.VectorLit(c[0], span=self._span(c, left=("[|",), right=("|]",)))

    def matrix_rows(self, c):
        return tuple(c)

    def matrix_row(self, c):
        return tuple(c)

    def inverse(self, c):
        return ast.MatrixOp("inverse", c[0], span=self._span(c, left=("inverse", "("), right=(")",)))

    def transpose(self, c):
        return ast.MatrixOp("transpose", c[0], span=self._span(c, left=("transpose", "("), right=(")",)))

    def dollar(self, c):
        return ast.Dollar(self._name(c[0]), span=self._span(c, left=("$",)), name_span=self._tspan(c[0]))

    def dollar_input(self, c):
        return ast.DollarInput(
            self._name(c[0]),
            self._name(c[1]),
            c[2] if len(c) > 2 else None,
            span=self._span(c, left=("$",)),
            event_span=self._tspan(c[0]),
            var_span=self._tspan(c[1]),
        )

    def dollar_value(self, c):
        return ast.DollarValue(self._name(c[0]), c[1], span=self._span(c, left=("$",)), event_span=self._tspan(c[0]))


def _tracked(method):
    def callback(self, c):
        return self._nest(method(self, c), c)

    callback.__name__ = method.__name__
    return callback


# The callbacks of recursive constructs, whose nodes _nest measures.
for _callback in (
    # types
    "function_type", "relation_type", "product_type", "set_type", "seq_type", "vector_type", "matrix_type",
    # states (only nested states count: transitions and actions have no depth entry)
    "state",
    # statements (seq and paren keep their own accounts)
    "stmt_deadline", "if_stmt", "assign", "bare_stmt", "comm_input_stmt", "comm_output_stmt", "send", "wait",
    "dollar_output", "dollar_sync", "dollar_call", "dollar_assign",
    # expressions
    "binder", "decl", "such_that", "iff", "implies", "or_", "and_", "not_", "compare", "member", "the", "let",
    "let_def", "if_expr", "cast", "arith", "neg", "field", "index", "call", "range_oo", "range_oc", "range_cc", "range_co", "seq_lit", "set_lit",
    "set_range", "set_comprehension", "set_body", "tuple_lit", "record_lit", "field_value", "vector_lit", "inverse",
    "transpose", "dollar_input", "dollar_value", "communication",
):
    setattr(ToAst, _callback, _tracked(getattr(ToAst, _callback)))
del _callback
