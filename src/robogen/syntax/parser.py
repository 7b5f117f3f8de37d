"""Parse RoboChart (.rct) and RoboSim (.rst, .rsim) text into :mod:`robogen.syntax.ast`.

The grammars are loaded from the package data ``robogen.grammar`` (the top-level ``grammar/``
folder of the repository): ``robochart.lark``, and for RoboSim the same text followed by
``robosim.lark``, which only extends it. Both are LALR(1) with Lark's contextual lexer,
``strict=True`` (conflicts fail at load time) and ``propagate_positions=True``.

This module is the only one that sees Lark: syntax errors are translated here into located
:class:`~robogen.diagnostics.Diagnostic` values, and the tree is transformed into AST nodes.
"""

from __future__ import annotations

import functools
import importlib.resources
import os
import re
from pathlib import Path

from lark import Lark, Token, Transformer, v_args
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken, VisitError

from robogen.diagnostics import Diagnostic, RobogenError, Span, error
from robogen.syntax import ast

ROBOCHART = "robochart"
ROBOSIM = "robosim"

EXTENSIONS = {".rct": ROBOCHART, ".rst": ROBOSIM, ".rsim": ROBOSIM}


def language_of(path: str | os.PathLike) -> str | None:
    return EXTENSIONS.get(Path(path).suffix.lower())


# ---------------------------------------------------------------------------- grammar loading


def _grammar_text(name: str) -> str:
    return (importlib.resources.files("robogen.grammar") / name).read_text(encoding="utf-8")


@functools.lru_cache(maxsize=None)
def _parser(language: str) -> Lark:
    text = _grammar_text("robochart.lark")
    if language == ROBOSIM:
        text += "\n" + _grammar_text("robosim.lark")
    return Lark(
        text,
        parser="lalr",
        lexer="contextual",
        strict=True,
        propagate_positions=True,
        maybe_placeholders=False,
    )


@functools.lru_cache(maxsize=None)
def keywords(language: str) -> frozenset[str]:
    """The reserved words of a language: every word the grammar uses as a literal."""
    words = set()
    for terminal in _parser(language).terminals:
        pattern = terminal.pattern
        if pattern.type == "str" and re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", pattern.value):
            words.add(pattern.value)
    return frozenset(words)


@functools.lru_cache(maxsize=None)
def _terminal_texts(language: str) -> dict[str, str]:
    """Terminal name -> how to show it in an error message."""
    names = {
        "NAME": "a name",
        "INT": "an integer",
        "REAL": "a real number",
        "STRING": "a string",
        "$END": "end of file",
    }
    for terminal in _parser(language).terminals:
        if terminal.name in names:
            continue
        if terminal.pattern.type == "str":
            names[terminal.name] = f"'{terminal.pattern.value}'"
        else:
            names[terminal.name] = terminal.name.lower()
    return names


# ---------------------------------------------------------------------------- entry points


def parse_text(text: str, path: str = "<string>", language: str | None = None) -> ast.File:
    """Parse one model. Raises RobogenError with located diagnostics on bad input."""
    language = language or language_of(path) or ROBOCHART
    if "\x00" in text:
        line = text.count("\n", 0, text.index("\x00")) + 1
        raise RobogenError(error("file contains NUL bytes; is it a binary file, not a model?", Span.point(path, line, 1)))
    parser = _parser(language)
    try:
        tree = parser.parse(text)
    except UnexpectedInput as exc:
        raise RobogenError(_syntax_error(exc, text, path, language)) from None
    transformer = _ToAst(path, language)
    try:
        items = transformer.transform(tree)
    except VisitError as exc:
        if isinstance(exc.orig_exc, RobogenError):
            raise exc.orig_exc from None
        raise exc.orig_exc from None
    if transformer.problems:
        raise RobogenError(transformer.problems)
    return items


def parse_file(path: str | os.PathLike, language: str | None = None) -> ast.File:
    path = os.fspath(path)
    try:
        data = Path(path).read_bytes()
    except FileNotFoundError:
        raise RobogenError(error(f"no such file: {path}", None)) from None
    except IsADirectoryError:
        raise RobogenError(error(f"{path} is a directory, not a model file", None)) from None
    except OSError as exc:
        raise RobogenError(error(f"cannot read {path}: {exc.strerror}", None)) from None
    return parse_text(decode(data, path), path, language)


def decode(data: bytes, path: str) -> str:
    """UTF-8 text of a model file (a BOM is allowed); a located error otherwise."""
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        good = data[: exc.start].decode("utf-8", errors="replace")
        line = good.count("\n") + 1
        column = len(good) - (good.rfind("\n") + 1) + 1
        raise RobogenError(
            error(
                f"not valid UTF-8 text (byte 0x{data[exc.start]:02x} at offset {exc.start}); models must be UTF-8",
                Span.point(path, line, column),
            )
        ) from None


# ---------------------------------------------------------------------------- syntax errors

_MAX_EXPECTED = 8

# Terminals that can start an expression: a list containing all of these is shown as
# "an expression" rather than token by token.
_EXPRESSION_STARTERS = {"NAME", "INT", "REAL", "STRING", "LPAR"}

_TRANSITION_CLAUSES = ("trigger", "exec", "probability", "#", "<{", "condition", "action", "from", "to")


def _syntax_error(exc: UnexpectedInput, text: str, path: str, language: str) -> Diagnostic:
    names = _terminal_texts(language)
    line, column = getattr(exc, "line", 1) or 1, getattr(exc, "column", 1) or 1
    if isinstance(exc, UnexpectedCharacters):
        ch = text[exc.pos_in_stream] if exc.pos_in_stream < len(text) else ""
        what = f"character {ch!r}" if ch.isprintable() else f"character U+{ord(ch):04X}"
        span = Span(path, line, column, line, column + 1)
        return error(f"unexpected {what}", span)
    expected = _expected(exc, names)
    if isinstance(exc, UnexpectedEOF) or (isinstance(exc, UnexpectedToken) and exc.token.type == "$END"):
        lines = text.splitlines() or [""]
        last = len(lines)
        end_col = len(lines[-1]) + 1
        return error(f"unexpected end of file; expected {expected}", Span(path, last, end_col, last, end_col + 1))
    assert isinstance(exc, UnexpectedToken)
    token = exc.token
    span = _token_span(path, token)
    word = str(token.value)
    if token.type == "NAME" and word in keywords(language):
        shown = f"'{word}'"
    elif token.type in ("NAME", "INT", "REAL", "STRING"):
        shown = f"{names[token.type].split(' ', 1)[1]} '{word}'"
    else:
        shown = f"'{word}'"
    diagnostic = error(f"unexpected {shown}; expected {expected}", span)
    if word in _TRANSITION_CLAUSES:
        diagnostic = diagnostic.with_note(
            "the clauses of a transition come in this order: from, to, trigger (or exec, or probability), "
            "#clock resets, <{deadline}, condition, action"
        )
    return diagnostic


def _expected(exc: UnexpectedInput, names: dict[str, str]) -> str:
    expected: set[str] = set(getattr(exc, "expected", None) or ())
    interactive = getattr(exc, "interactive_parser", None)
    if interactive is not None:
        try:  # exact: simulates the reductions LALR's default actions may already have made
            expected = set(interactive.accepts()) or expected
        except Exception:  # pragma: no cover - fall back to Lark's own set
            pass
    shown: list[str] = []
    if _EXPRESSION_STARTERS <= expected:
        expected = {t for t in expected - _EXPRESSION_STARTERS if not _starts_expression(names.get(t, ""))}
        shown.append("an expression")
    words = sorted({names.get(t, t.lower()) for t in expected})
    words.sort(key=lambda s: (s.startswith("a ") or s.startswith("an "), s))
    shown = words + shown if shown else words
    if not shown:
        return "something else"
    if len(shown) > _MAX_EXPECTED:
        return f"one of {', '.join(shown[:_MAX_EXPECTED])}, ... ({len(shown) - _MAX_EXPECTED} more)"
    if len(shown) == 1:
        return shown[0]
    return ", ".join(shown[:-1]) + " or " + shown[-1]


def _starts_expression(shown: str) -> bool:
    return shown in {"'('", "'(|'", "'['", "'[|'", "'{'", "'<'", "'-'", "'$'", "'not'", "'if'", "'let'", "'the'",
                     "'forall'", "'exists'", "'exists1'", "'lambda'", "'since'", "'sinceEntry'", "'result'",
                     "'from'", "'to'", "'true'", "'false'", "'inverse'", "'transpose'", "'cycle'"}


def _token_span(path: str, token: Token) -> Span:
    line = token.line or 1
    column = token.column or 1
    end_line = token.end_line or line
    end_column = token.end_column or column + max(1, len(str(token.value)))
    return Span(path, line, column, end_line, end_column)


# ---------------------------------------------------------------------------- tree -> AST


def _strip(name: str) -> str:
    return name[1:] if name.startswith("^") else name


@v_args(meta=True)
class _ToAst(Transformer):
    """Builds AST nodes bottom-up. Reserved words used as names are reported, not raised, so
    that every such problem in a file is listed."""

    def __init__(self, path: str, language: str):
        super().__init__(visit_tokens=False)
        self.path = path
        self.language = language
        self.keywords = keywords(language)
        self.problems: list[Diagnostic] = []

    # -- helpers

    def _span(self, meta) -> Span | None:
        if getattr(meta, "empty", True):
            return None
        return Span(self.path, meta.line, meta.column, meta.end_line, meta.end_column)

    def _tspan(self, token: Token) -> Span:
        return _token_span(self.path, token)

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

    def start(self, meta, children):
        package = None
        imports, items = [], []
        for c in children:
            if isinstance(c, _Package):
                package = c.name
            elif isinstance(c, ast.Import):
                imports.append(c)
            else:
                items.append(c)
        return ast.File(self.path, self.language, package, tuple(imports), tuple(items), span=self._span(meta))

    def package(self, meta, children):
        return _Package(children[0])

    def import_(self, meta, children):
        return ast.Import(children[0], len(children) > 1, span=self._span(meta))

    def diagram(self, meta, children):
        return ast.Diagram(self._name(children[0]), span=self._span(meta), name_span=self._tspan(children[0]))

    def qname(self, meta, children):
        return ast.Name(tuple(self._name(t) for t in children), span=self._span(meta))

    # -- types

    def given_type(self, meta, c):
        return ast.GivenType(self._name(c[0]), span=self._span(meta), name_span=self._tspan(c[0]))

    def record(self, meta, c):
        return ast.Record(self._name(c[0]), tuple(c[1:]), span=self._span(meta), name_span=self._tspan(c[0]))

    def record_field(self, meta, c):
        return ast.FieldDecl(self._name(c[0]), c[1], span=self._span(meta), name_span=self._tspan(c[0]))

    def field(self, meta, c):
        return ast.Field(c[0], self._name(c[1]), span=self._span(meta), field_span=self._tspan(c[1]))

    def enumeration(self, meta, c):
        return ast.Enumeration(self._name(c[0]), tuple(c[1:]), span=self._span(meta), name_span=self._tspan(c[0]))

    def literal(self, meta, c):
        return ast.EnumLiteral(self._name(c[0]), tuple(c[1:]), span=self._span(meta), name_span=self._tspan(c[0]))

    def function_type(self, meta, c):
        return ast.FunctionType(c[0], c[1], span=self._span(meta))

    def relation_type(self, meta, c):
        return ast.RelationType(c[0], c[1], span=self._span(meta))

    def product_type(self, meta, c):
        return ast.ProductType(tuple(c), span=self._span(meta))

    def type_ref(self, meta, c):
        return ast.TypeRef(c[0], span=self._span(meta))

    def set_type(self, meta, c):
        return ast.SetType(c[0], span=self._span(meta))

    def seq_type(self, meta, c):
        return ast.SeqType(c[0], span=self._span(meta))

    def type_var(self, meta, c):
        return ast.TypeVar_(self._name(c[0]), span=self._span(meta))

    def vector_type(self, meta, c):
        return ast.VectorType(c[0], c[1], span=self._span(meta))

    def matrix_type(self, meta, c):
        return ast.MatrixType(c[0], c[1], c[2], span=self._span(meta))

    # -- declarations

    def broadcast(self, meta, c):
        return _Flag("broadcast")

    def event_decl(self, meta, c):
        broadcast = bool(c) and isinstance(c[0], _Flag)
        if broadcast:
            c = c[1:]
        return ast.EventDecl(
            self._name(c[0]), c[1] if len(c) > 1 else None, broadcast, span=self._span(meta), name_span=self._tspan(c[0])
        )

    def var_kind(self, meta, c):
        return str(c[0])

    def var_list(self, meta, c):
        return ast.VarList(c[0] == "const", tuple(c[1:]), span=self._span(meta))

    def var_decl(self, meta, c):
        return ast.VarDecl(
            self._name(c[0]), c[1], c[2] if len(c) > 2 else None, span=self._span(meta), name_span=self._tspan(c[0])
        )

    def clock_decl(self, meta, c):
        return ast.ClockDecl(self._name(c[0]), span=self._span(meta), name_span=self._tspan(c[0]))

    def op_sig(self, meta, c):
        params: tuple = ()
        terminates = False
        for x in c[1:]:
            if isinstance(x, tuple):
                params = x
            elif isinstance(x, _Flag):
                terminates = True
        return ast.OpSig(self._name(c[0]), params, terminates, span=self._span(meta), name_span=self._tspan(c[0]))

    def terminates_flag(self, meta, c):
        return _Flag("terminates")

    def params(self, meta, c):
        return tuple(c)

    def param(self, meta, c):
        return ast.Param(self._name(c[0]), c[1], span=self._span(meta), name_span=self._tspan(c[0]))

    def iface_kind(self, meta, c):
        return str(c[0])

    def iface_ref(self, meta, c):
        return ast.InterfaceRef(c[0], c[1], span=self._span(meta))

    def interface(self, meta, c):
        return ast.Interface(self._name(c[0]), tuple(c[1:]), span=self._span(meta), name_span=self._tspan(c[0]))

    def platform(self, meta, c):
        return ast.Platform(self._name(c[0]), tuple(c[1:]), span=self._span(meta), name_span=self._tspan(c[0]))

    def controller(self, meta, c):
        return ast.Controller(self._name(c[0]), tuple(c[1:]), span=self._span(meta), name_span=self._tspan(c[0]))

    def module(self, meta, c):
        return ast.Module(self._name(c[0]), tuple(c[1:]), span=self._span(meta), name_span=self._tspan(c[0]))

    def ref_kind(self, meta, c):
        return str(c[0])

    def reference(self, meta, c):
        return ast.Reference(self._name(c[1]), c[0], c[2], span=self._span(meta), name_span=self._tspan(c[1]))

    def async_flag(self, meta, c):
        return _Flag("async")

    def mult_flag(self, meta, c):
        return _Flag("mult")

    def connection(self, meta, c):
        names, flags = c[:4], {f.what for f in c[4:]}
        return ast.Connection(
            *(self._name(t) for t in names),
            asynchronous="async" in flags,
            mult="mult" in flags,
            span=self._span(meta),
            spans=tuple(self._tspan(t) for t in names),
        )

    def stm(self, meta, c):
        return ast.StateMachine(self._name(c[0]), tuple(c[1:]), span=self._span(meta), name_span=self._tspan(c[0]))

    def operation_def(self, meta, c):
        params: tuple = ()
        rest = c[1:]
        if rest and isinstance(rest[0], tuple):
            params, rest = rest[0], rest[1:]
        return ast.OperationDef(self._name(c[0]), params, tuple(rest), span=self._span(meta), name_span=self._tspan(c[0]))

    def function_def(self, meta, c):
        params: tuple = ()
        rest = c[1:]
        if rest and isinstance(rest[0], tuple):
            params, rest = rest[0], rest[1:]
        return ast.FunctionDef(
            self._name(c[0]), params, rest[0], tuple(rest[1:]), span=self._span(meta), name_span=self._tspan(c[0])
        )

    def terminates(self, meta, c):
        return ast.Terminates(span=self._span(meta))

    def precondition(self, meta, c):
        return ast.Precondition(c[0], span=self._span(meta))

    def postcondition(self, meta, c):
        return ast.Postcondition(c[0], span=self._span(meta))

    def cycle_def(self, meta, c):
        return ast.CycleDef(c[0], span=self._span(meta))

    def context_kind(self, meta, c):
        return str(c[0])

    def context(self, meta, c):
        return ast.Context(c[0], tuple(c[1:]), span=self._span(meta))

    # -- nodes and transitions

    def _node(self, cls, meta, c):
        return cls(self._name(c[0]), span=self._span(meta), name_span=self._tspan(c[0]))

    def initial(self, meta, c):
        return self._node(ast.Initial, meta, c)

    def junction(self, meta, c):
        return self._node(ast.Junction, meta, c)

    def final(self, meta, c):
        return self._node(ast.Final, meta, c)

    def probabilistic(self, meta, c):
        return self._node(ast.Probabilistic, meta, c)

    def state(self, meta, c):
        return ast.State(self._name(c[0]), tuple(c[1:]), span=self._span(meta), name_span=self._tspan(c[0]))

    def action_kind(self, meta, c):
        return str(c[0])

    def state_action(self, meta, c):
        return ast.StateAction(c[0], c[1], span=self._span(meta))

    def transition(self, meta, c):
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
            span=self._span(meta),
            name_span=self._tspan(name),
            source_span=self._tspan(source),
            target_span=self._tspan(target),
        )

    def trigger(self, meta, c):
        return _Clause("trigger", c[0])

    def exec_trigger(self, meta, c):
        return _Clause("exec", True)

    def probability(self, meta, c):
        return _Clause("probability", c[0])

    def reset(self, meta, c):
        return ast.ClockReset(self._name(c[0]), span=self._span(meta), clock_span=self._tspan(c[0]))

    def deadline(self, meta, c):
        return _Clause("deadline", c[0])

    def condition(self, meta, c):
        return _Clause("condition", c[0])

    def condition_else(self, meta, c):
        return _Clause("condition_else", True)

    def action(self, meta, c):
        return _Clause("action", c[0])

    def communication(self, meta, c):
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
        return ast.Communication(
            self._name(event), kind, var, value, filt, span=self._span(meta), event_span=self._tspan(event), var_span=var_span
        )

    def comm_input(self, meta, c):
        return ("?", c[0])

    def comm_output(self, meta, c):
        return ("!", c[0])

    def comm_sync(self, meta, c):
        return (".", c[0])

    def filter_bind(self, meta, c):
        return ast.Filter(self._name(c[0]), c[1], c[2] if len(c) > 2 else None, span=self._span(meta))

    def filter_pred(self, meta, c):
        return ast.Filter(None, None, c[0], span=self._span(meta))

    # -- statements

    def seq(self, meta, c):
        left, right = c
        items = left.stmts if isinstance(left, ast.Seq) else (left,)
        return ast.Seq(items + (right,), span=self._span(meta))

    def stmt_deadline(self, meta, c):
        return ast.StmtDeadline(c[0], c[1], span=self._span(meta))

    def skip(self, meta, c):
        return ast.Skip(span=self._span(meta))

    def exec_stmt(self, meta, c):
        return ast.Exec(span=self._span(meta))

    def wait(self, meta, c):
        return ast.Wait(c[0], span=self._span(meta))

    def clock_reset(self, meta, c):
        return ast.ClockReset(self._name(c[0]), span=self._span(meta), clock_span=self._tspan(c[0]))

    def if_stmt(self, meta, c):
        return ast.IfStmt(c[0], c[1], c[2] if len(c) > 2 else None, span=self._span(meta))

    def send(self, meta, c):
        return ast.Communicate(c[0], True, span=self._span(meta))

    def bare_stmt(self, meta, c):
        """A statement that is only a target: a call `op(args)`, a plain event `e`, or `e.v`."""
        target = c[0]
        span = self._span(meta)
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

    def assign(self, meta, c):
        return ast.Assign(c[0], c[1], span=self._span(meta))

    def _stmt_comm(self, meta, c, kind):
        target, payload = c
        span = self._span(meta)
        if not (isinstance(target, ast.Name) and not target.qualified):
            self.problems.append(error("a communication must name an event", target.span or span))
            return ast.Skip(span=span)
        if kind == "?":
            comm = ast.Communication(target.last, "?", self._name(payload), span=span, event_span=target.span, var_span=self._tspan(payload))
        else:
            comm = ast.Communication(target.last, "!", value=payload, span=span, event_span=target.span)
        return ast.Communicate(comm, False, span=span)

    def comm_input_stmt(self, meta, c):
        return self._stmt_comm(meta, c, "?")

    def comm_output_stmt(self, meta, c):
        return self._stmt_comm(meta, c, "!")

    def dollar_stmt(self, meta, c):
        return ast.DollarOutput(self._name(c[0]), "", None, span=self._span(meta), event_span=self._tspan(c[0]))

    def dollar_output(self, meta, c):
        return ast.DollarOutput(self._name(c[0]), "!", c[1], span=self._span(meta), event_span=self._tspan(c[0]))

    def dollar_sync(self, meta, c):
        return ast.DollarOutput(self._name(c[0]), ".", c[1], span=self._span(meta), event_span=self._tspan(c[0]))

    def dollar_call(self, meta, c):
        args = c[1] if len(c) > 1 else ()
        return ast.DollarCall(self._name(c[0]), args, span=self._span(meta), op_span=self._tspan(c[0]))

    def dollar_assign(self, meta, c):
        return ast.DollarAssign(self._name(c[0]), c[1], span=self._span(meta), var_span=self._tspan(c[0]))

    # -- expressions

    def binder_kind(self, meta, c):
        return str(c[0])

    def binder(self, meta, c):
        kind, decls = c[0], c[1]
        such_that = c[2].expr if len(c) == 4 else None
        return ast.Binder(kind, decls, such_that, c[-1], span=self._span(meta))

    def decls(self, meta, c):
        return tuple(c)

    def decl(self, meta, c):
        return ast.Decl(self._name(c[0]), c[1], span=self._span(meta), name_span=self._tspan(c[0]))

    def such_that(self, meta, c):
        return _SuchThat(c[0])

    def _binary(self, op, meta, c):
        return ast.Binary(op, c[0], c[-1], span=self._span(meta))

    def iff(self, meta, c):
        return self._binary("iff", meta, c)

    def implies(self, meta, c):
        return self._binary("=>", meta, c)

    def or_(self, meta, c):
        return self._binary("\\/", meta, c)

    def and_(self, meta, c):
        return self._binary("/\\", meta, c)

    def not_(self, meta, c):
        return ast.Unary("not", c[0], span=self._span(meta))

    def cmp_op(self, meta, c):
        return str(c[0])

    def compare(self, meta, c):
        return ast.Binary(c[1], c[0], c[2], span=self._span(meta))

    def member(self, meta, c):
        return self._binary("in", meta, c)

    def the(self, meta, c):
        decls = c[0]
        such_that = c[1].expr if len(c) == 3 else None
        return ast.Binder("the", decls, such_that, c[-1], span=self._span(meta))

    def let(self, meta, c):
        return ast.Let(tuple(c[:-1]), c[-1], span=self._span(meta))

    def let_def(self, meta, c):
        return ast.LetDef(self._name(c[0]), c[1], span=self._span(meta), name_span=self._tspan(c[0]))

    def if_expr(self, meta, c):
        return ast.IfExpr(c[0], c[1], c[2], span=self._span(meta))

    def cast_op(self, meta, c):
        return str(c[0])

    def cast(self, meta, c):
        return ast.Cast(c[1], c[0], c[2], span=self._span(meta))

    add_op = mul_op = cat_op = cast_op

    def arith(self, meta, c):
        return ast.Binary(c[1], c[0], c[2], span=self._span(meta))

    def neg(self, meta, c):
        return ast.Unary("-", c[0], span=self._span(meta))

    def index(self, meta, c):
        return ast.Index(c[0], c[1], span=self._span(meta))

    def call(self, meta, c):
        return ast.Call(c[0], c[1] if len(c) > 1 else (), span=self._span(meta))

    def args(self, meta, c):
        return tuple(c)

    def int_lit(self, meta, c):
        return ast.IntLit(int(c[0]), span=self._span(meta))

    def real_lit(self, meta, c):
        return ast.RealLit(str(c[0]), span=self._span(meta))

    def string_lit(self, meta, c):
        raw = str(c[0])[1:-1]
        return ast.StringLit(re.sub(r"\\(.)", r"\1", raw), span=self._span(meta))

    def true_lit(self, meta, c):
        return ast.BoolLit(True, span=self._span(meta))

    def false_lit(self, meta, c):
        return ast.BoolLit(False, span=self._span(meta))

    def name(self, meta, c):
        return c[0]  # a qname already built as ast.Name

    def result(self, meta, c):
        return ast.Keyword("result", span=self._span(meta))

    def from_atom(self, meta, c):
        return ast.Keyword("from", span=self._span(meta))

    def to_atom(self, meta, c):
        return ast.Keyword("to", span=self._span(meta))

    def cycle_atom(self, meta, c):
        return ast.Keyword("cycle", span=self._span(meta))

    def _range(self, meta, c, low_closed, high_closed):
        return ast.Range(c[0], c[1], low_closed, high_closed, span=self._span(meta))

    def range_oo(self, meta, c):
        return self._range(meta, c, False, False)

    def range_oc(self, meta, c):
        return self._range(meta, c, False, True)

    def range_cc(self, meta, c):
        return self._range(meta, c, True, True)

    def range_co(self, meta, c):
        return self._range(meta, c, True, False)

    def since(self, meta, c):
        return ast.Since(self._name(c[0]), span=self._span(meta), clock_span=self._tspan(c[0]))

    def since_entry(self, meta, c):
        return ast.SinceEntry(c[0], span=self._span(meta))

    def seq_lit(self, meta, c):
        return ast.SeqLit(c[0] if c else (), span=self._span(meta))

    def seq_items(self, meta, c):
        return tuple(c)

    def set_empty(self, meta, c):
        return ast.SetLit((), span=self._span(meta))

    def set_lit(self, meta, c):
        return ast.SetLit(tuple(c), span=self._span(meta))

    def set_range(self, meta, c):
        return ast.SetRange(c[0], c[1], span=self._span(meta))

    def set_comprehension(self, meta, c):
        decls = c[0]
        such_that = next((x.expr for x in c[1:] if isinstance(x, _SuchThat)), None)
        body = next((x.expr for x in c[1:] if isinstance(x, _Body)), None)
        return ast.SetComprehension(decls, such_that, body, span=self._span(meta))

    def set_body(self, meta, c):
        return _Body(c[0])

    def tuple_lit(self, meta, c):
        return ast.TupleLit(tuple(c), span=self._span(meta))

    def record_lit(self, meta, c):
        return ast.RecordLit(c[0], tuple(c[1:]), span=self._span(meta))

    def field_value(self, meta, c):
        return ast.FieldValue(self._name(c[0]), c[1], span=self._span(meta), name_span=self._tspan(c[0]))

    def vector_lit(self, meta, c):
        return ast.VectorLit(c[0], span=self._span(meta))

    def matrix_rows(self, meta, c):
        return tuple(c)

    def matrix_row(self, meta, c):
        return tuple(c)

    def inverse(self, meta, c):
        return ast.MatrixOp("inverse", c[0], span=self._span(meta))

    def transpose(self, meta, c):
        return ast.MatrixOp("transpose", c[0], span=self._span(meta))

    def dollar(self, meta, c):
        return ast.Dollar(self._name(c[0]), span=self._span(meta), name_span=self._tspan(c[0]))

    def dollar_input(self, meta, c):
        return ast.DollarInput(
            self._name(c[0]),
            self._name(c[1]),
            c[2] if len(c) > 2 else None,
            span=self._span(meta),
            event_span=self._tspan(c[0]),
            var_span=self._tspan(c[1]),
        )

    def dollar_value(self, meta, c):
        return ast.DollarValue(self._name(c[0]), c[1], span=self._span(meta), event_span=self._tspan(c[0]))


class _Package:
    __slots__ = ("name",)

    def __init__(self, name: ast.Name):
        self.name = name


class _Flag:
    __slots__ = ("what",)

    def __init__(self, what: str):
        self.what = what


class _Clause:
    __slots__ = ("key", "value")

    def __init__(self, key: str, value):
        self.key = key
        self.value = value


class _SuchThat:
    __slots__ = ("expr",)

    def __init__(self, expr):
        self.expr = expr


class _Body:
    __slots__ = ("expr",)

    def __init__(self, expr):
        self.expr = expr
