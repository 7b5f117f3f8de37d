"""Rules of the file structure, types and declarations: packages and imports, data types and
enumerations, events, variables, clocks, operation signatures, interfaces, platforms,
controllers, modules and state machines (as containers), references and connections, operation
and function definitions."""

from __future__ import annotations

from lark import Token

from robogen.syntax import ast
from robogen.syntax.transform_base import Flag, Package, first_child, make_span, pos, span_pos
from robogen.syntax.transform_obsolete import Dropped

_Name = ast.Name


class Declarations:
    """Callbacks of the declarations rules (a part of :class:`~robogen.syntax.transform.ToAst`)."""

    def start(self, c):
        package = None
        imports, items = [], []
        for x in c:
            if isinstance(x, Package):
                package = x.name
            elif isinstance(x, ast.Import):
                imports.append(x)
            else:
                items.append(x)
        return ast.File(self.path, self.language, package, tuple(imports), tuple(items), span=self._span(c),
                        notices=tuple(self.notices))

    def package(self, c):
        package = Package(c[0])
        package.pos = span_pos(self._span(c, left=("package",)))
        return package

    def import_(self, c):
        return ast.Import(c[0], len(c) > 1, span=self._span(c, left=("import",)))

    def diagram(self, c):
        return ast.Diagram(self._name(c[0]), span=self._span(c, left=("diagram",)), name_span=self._tspan(c[0]))

    def qname(self, c):
        if len(c) == 1:  # most names: one token, its span (_name and _tspan inline)
            token = c[0]
            text = token.value
            if type(token) is Token and text[:1] != "^" and text not in (self._keywords or self.keywords) and token.end_column:
                return _Name((text,), span=make_span(self.path, token.line, token.column, token.end_line, token.end_column,
                                                     token.start_pos, token.end_pos))  # fmt: skip
            return ast.Name((self._name(token),), span=self._tspan(token))
        return ast.Name(tuple(self._name(t) for t in c), span=self._span(c))

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

    def broadcast(self, c):
        return Flag("broadcast", pos(c[0]))

    def event_decl(self, c):
        broadcast = bool(c) and isinstance(c[0], Flag)
        rest = c[1:] if broadcast else c
        return ast.EventDecl(
            self._name(rest[0]),
            rest[1] if len(rest) > 1 else None,
            broadcast,
            span=self._span(c, left=() if broadcast else ("event",)),
            name_span=self._tspan(rest[0]),
        )

    @first_child
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
            elif isinstance(x, Flag):
                terminates = True
        return ast.OpSig(
            self._name(c[0]), params, terminates, span=self._span(c, right=() if terminates else (")",)) if params or terminates else self._span(c, right=("(", ")")),
            name_span=self._tspan(c[0]),
        )

    def terminates_flag(self, c):
        return Flag("terminates", span_pos(self._span(c, left=("[",), right=("]",))))

    def params(self, c):
        return tuple(c)

    def param(self, c):
        return ast.Param(self._name(c[0]), c[1], span=self._span(c), name_span=self._tspan(c[0]))

    @first_child
    def iface_kind(self, c):
        return c[0]

    def iface_ref(self, c):
        return ast.InterfaceRef(str(c[0]), c[1], span=self._span(c))

    def _container(self, cls, c, keyword: tuple[str, ...]):
        right = ("}",) if len(c) > 1 else ("{", "}")
        members = tuple(m for m in c[1:] if type(m) is not Dropped)
        return cls(self._name(c[0]), members, span=self._span(c, left=keyword, right=right), name_span=self._tspan(c[0]))

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

    @first_child
    def ref_kind(self, c):
        return c[0]

    def reference(self, c):
        return ast.Reference(self._name(c[1]), str(c[0]), c[2], span=self._span(c), name_span=self._tspan(c[1]))

    def async_flag(self, c):
        return Flag("async", span_pos(self._span(c, left=("(",), right=(")",))))

    def bidirectional_flag(self, c):
        return Flag("bidirectional", span_pos(self._span(c, left=("[",), right=("]",))))

    def connection(self, c):
        names, flags = c[:4], {f.what for f in c[4:]}
        return ast.Connection(
            *(self._name(t) for t in names),
            asynchronous="async" in flags,
            bidirectional="bidirectional" in flags,
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
