"""Type checking of expressions inside one state machine or operation (statements are checked
by :mod:`robogen.semantics.stmts`, which builds on this).

The checker infers a :class:`~robogen.semantics.types.Type` for every expression and records
it, with the symbol every name resolves to, in the shared :class:`Tables`, which the IR
lowering reads back. Problems go to the sink; an expression that fails gets ``UNKNOWN`` so that
one mistake produces one message.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Mapping

from robogen.diagnostics import DiagnosticSink, Note, did_you_mean
from robogen.semantics import limits
from robogen.semantics import types as T
from robogen.semantics.algebra import linear, negation
from robogen.semantics.calls import Calls, literal_args, plural
from robogen.semantics.dollar import DollarForms
from robogen.semantics.model import EnumLitSym, MachineScope, Tables, VarSym
from robogen.syntax import ast
from robogen.syntax.printer import expr as expr_text


@dataclass
class Where:
    """Where an expression appears: decides which forms are allowed."""

    guard: bool = False  # a transition condition (since, $e?x allowed)
    action: bool = False
    init: bool = False  # a variable initialiser or constant
    pre: bool = False  # pre/postcondition (result allowed)


def _untyped_empty(t: T.Type) -> bool:
    """Is ``t`` the type of ``{}`` or ``<>``, a set or sequence whose elements nothing typed?"""
    t = T.single(t)
    return isinstance(t, (T.SetT, T.SeqT)) and isinstance(T.single(t.element), T.UnknownT)


class ExprChecker(Calls, DollarForms):
    def __init__(
        self,
        scope: MachineScope,
        sink: DiagnosticSink,
        tables: Tables,
        resolve_type: Callable[[ast.TypeExpr, ast.File], T.Type],
        lookup_global: Callable[..., object],
        records: dict[str, T.RecordT] | None = None,
        file_literals: Callable[[ast.File], Mapping[str, EnumLitSym]] | None = None,
    ):
        self.scope = scope
        self.sink = sink
        self.tables = tables
        self.resolve_type = resolve_type
        self.lookup_global = lookup_global  # (name, file, kinds, what, report) -> Decl | None
        self.records = records if records is not None else {}  # qname -> complete record type
        # the enumeration literals a file declares, by simple name (RoboTool's innermost scope)
        self.file_literals = file_literals or (lambda file: {})
        self.locals: list[dict[str, VarSym]] = []
        self.where = Where()
        self.result_type: T.Type | None = None
        self.robosim = scope.robosim
        # events used as outputs / inputs, and operations called, for later checks
        self.outputs_used: list[tuple[str, ast.Node]] = []
        self._expr_rules: dict[type, Callable | None] = {}  # node class -> _e_<class>, see rule()
        self._stmt_rules: dict[type, Callable | None] = {}  # node class -> _s_<class>
        # (id(file), parts) -> the literal a qualified name denotes, found without reporting anything
        self._qualified_literals: dict[tuple[int, tuple[str, ...]], EnumLitSym | None] = {}

    # ------------------------------------------------------------------ helpers

    def _set(self, e: ast.Expr, t: T.Type) -> T.Type:
        self.tables.types[id(e)] = t
        return t

    def _err(self, message: str, node: ast.Node | None, *notes: Note) -> T.Type:
        self.sink.error(message, getattr(node, "span", None), *notes)
        return T.UNKNOWN

    def lookup_var(self, name: str) -> VarSym | None:
        for frame in reversed(self.locals):
            if name in frame:
                return frame[name]
        return self.scope.vars.get(name)

    def _visible_value_names(self) -> list[str]:
        names = list(self.scope.vars)
        for frame in self.locals:
            names += list(frame)
        return names

    def expect(self, e: ast.Expr, expected: T.Type, what: str) -> T.Type:
        t = self.expr(e)
        if not T.assignable(t, expected):
            self._err(f"{what} must be {expected.show()}, but this is {t.show()}", e)
        return t

    def condition(self, e: ast.Expr) -> None:
        saved = self.where
        self.where = Where(guard=True)
        try:
            t = self.expr(e)
            if not T.is_boolean(t):
                self._err(f"a condition must be boolean, but this is {t.show()}", e)
        finally:
            self.where = saved

    def value(self, e: ast.Expr, where: Where) -> T.Type:
        saved = self.where
        self.where = where
        try:
            return self.expr(e)
        finally:
            self.where = saved

    # ------------------------------------------------------------------ expressions

    def expr(self, e: ast.Expr) -> T.Type:
        rule = self._expr_rules.get(type(e)) or self.rule(self._expr_rules, "_e_", type(e))
        if rule is None:  # pragma: no cover - every node class has a method
            return self._err(f"internal: no type rule for {type(e).__name__}", e)
        t = self.tables.types[id(e)] = rule(self, e)
        return t

    def rule(self, rules: dict[type, Callable | None], prefix: str, node: type) -> Callable | None:
        """The method ``<prefix><node class>`` of this checker's class, as a function, remembered
        in ``rules`` (functions, not bound methods: those would make a reference cycle)."""
        found = rules[node] = getattr(type(self), prefix + node.__name__, None)
        return found

    def _e_IntLit(self, e: ast.IntLit) -> T.Type:
        return T.NAT

    def _e_RealLit(self, e: ast.RealLit) -> T.Type:
        return T.REAL

    def _e_BoolLit(self, e: ast.BoolLit) -> T.Type:
        return T.BOOLEAN

    def _e_StringLit(self, e: ast.StringLit) -> T.Type:
        return T.STRING

    def _e_Keyword(self, e: ast.Keyword) -> T.Type:
        if e.word == "result":
            if self.result_type is None:
                return self._err("'result' is only meaningful in a postcondition", e)
            return self.result_type
        if e.word == "cycle":
            return T.REAL
        return T.UNKNOWN  # from / to in filters

    def _e_Name(self, e: ast.Name) -> T.Type:
        """A name as a value, resolved as RoboTool does: an enumeration literal of the file
        (``VA``) or a qualified one (``E::VA``), then a variable, then a function."""
        lit = self.literal_named(e)
        if lit is not None:
            return self._literal_value(e, lit)
        if not e.qualified:
            v = self.lookup_var(e.last)
            if v is not None:
                self.tables.refs[id(e)] = v
                return v.type
        function = self.function_value(e)
        if function is not None:
            return function
        if e.qualified:
            self.enum_literal(e, report=True)  # says what is wrong with Pkg::E::lit
            return T.UNKNOWN
        if e.last in self.scope.events:
            return self._err(
                f"'{e.last}' is an event; events are not values"
                + (f" (write ${e.last} to test whether it occurred)" if self.robosim else ""),
                e,
            )
        if e.last in self.scope.clocks:
            return self._err(f"'{e.last}' is a clock; write since({e.last}) for the time since its reset", e)
        return self._err(f"unknown name '{e.last}'" + did_you_mean(e.last, self._visible_value_names()), e)

    def literal_named(self, e: ast.Name) -> EnumLitSym | None:
        """The enumeration literal a name denotes: ``E::lit`` (with its package, if given), or a
        literal of an enumeration declared in the same file."""
        if e.qualified:
            return self.enum_literal(e, report=False)
        return self.file_literals(self.scope.file).get(e.last)

    def _literal_value(self, e: ast.Name, lit: EnumLitSym) -> T.Type:
        self.tables.refs[id(e)] = lit
        carried = literal_args(lit)
        if carried:
            return self._err(
                f"enumeration literal '{e.text}' carries {plural(len(carried), 'value')}: write {e.text}("
                + ", ".join(t.show() for t in carried) + ")",
                e,
            )
        return lit.enum

    def enum_literal(self, e: ast.Name, report: bool) -> EnumLitSym | None:
        """The literal ``E::lit`` (or ``Pkg::E::lit``) denotes. Without ``report``, remembered per
        file and text when finding it reported nothing (a warning, such as an enumeration used
        without its import, is given at each occurrence, so such a name is looked up each time)."""
        if report:
            return self._enum_literal(e, report)
        key = (id(self.scope.file), e.parts)
        if key in self._qualified_literals:
            return self._qualified_literals[key]
        before = len(self.sink.items)
        found = self._enum_literal(e, report)
        if len(self.sink.items) == before:
            self._qualified_literals[key] = found
        return found

    def _enum_literal(self, e: ast.Name, report: bool) -> EnumLitSym | None:
        enum_name = ast.Name(e.parts[:-1], span=e.span)
        decl = self.lookup_global(enum_name, self.scope.file, (ast.Enumeration,), "enumeration", report)
        if decl is None:
            return None
        enum_t = self.resolve_type(ast.TypeRef(enum_name, span=e.span), self.scope.file)
        if not isinstance(enum_t, T.EnumT):
            return None
        if e.last not in enum_t.literals:
            if report:
                self._err(f"enumeration '{enum_t.qname}' has no literal '{e.last}'" + did_you_mean(e.last, enum_t.literals), e)
            return None
        return EnumLitSym(enum_t, e.last)

    def _e_Unary(self, e: ast.Unary) -> T.Type:
        t = self.expr(e.operand)
        if e.op == "not":
            if not T.is_boolean(t):
                return self._err(f"'not' needs a boolean operand, not {t.show()}", e.operand)
            return T.BOOLEAN
        if isinstance(t, (T.VectorT, T.MatrixT)):
            shaped = negation(t)
            return self._err(shaped, e.operand) if isinstance(shaped, str) else shaped
        if not T.is_numeric(t):
            return self._err(f"unary '-' needs a number, not {t.show()}", e.operand)
        return T.INT if t == T.NAT else t

    def _e_Binary(self, e: ast.Binary) -> T.Type:
        """A chain of binary operators (ast.chain), typed from its leftmost operand out in a loop:
        a flat expression may have thousands of operands."""
        first, links = ast.chain(e)
        a = self.expr(first)
        for link in links:
            a = self._set(link, self._binary(link, a, self.expr(link.right)))
        return a

    def _binary(self, e: ast.Binary, a: T.Type, b: T.Type) -> T.Type:
        """The type of ``e`` from those of its operands, ``a`` on the left and ``b`` on the right."""
        op = e.op
        if op in ("iff", "=>", "\\/", "/\\"):
            for side, t in ((e.left, a), (e.right, b)):
                if not T.is_boolean(t):
                    self._err(f"'{op}' needs boolean operands, not {t.show()}", side)
            return T.BOOLEAN
        if op in ("==", "!="):
            if not T.comparable(a, b):
                self._err(f"cannot compare {a.show()} with {b.show()}", e)
            self._since_rule(e)
            self._type_limits(e, a, b)
            return T.BOOLEAN
        if op in ("<", "<=", ">", ">="):
            for side, t in ((e.left, a), (e.right, b)):
                if not T.is_numeric(t):
                    self._err(f"'{op}' needs numbers, not {t.show()}", side)
            self._since_rule(e)
            self._type_limits(e, a, b)
            return T.BOOLEAN
        if op == "in":
            if not isinstance(b, (T.SetT, T.SeqT, T.UnknownT)):
                self._err(f"the right of 'in' must be a set or a sequence, not {b.show()}", e.right)
            elif not isinstance(b, T.UnknownT) and not T.assignable(a, b.element):
                self._err(f"{a.show()} cannot be a member of {b.show()}", e.left)
            return T.BOOLEAN
        if op in ("cat", "^"):
            if a == T.STRING and b == T.STRING:  # RoboCalcTypeProvider, Cat: two strings give a string
                return T.STRING
            for side, t in ((e.left, a), (e.right, b)):
                if not isinstance(t, (T.SeqT, T.UnknownT, T.TypeVarT)):
                    self._err(f"'{op}' concatenates sequences or strings, not {t.show()}", side)
            return a if isinstance(a, T.SeqT) else b
        # + - * / %
        if isinstance(a, T.SetT) or isinstance(b, T.SetT):
            return self._err(f"'{op}' is not defined on sets; use union, inter or diff", e)
        if isinstance(a, (T.VectorT, T.MatrixT)) or isinstance(b, (T.VectorT, T.MatrixT)):
            shaped = linear(op, a, b)
            return self._err(shaped, e) if isinstance(shaped, str) else shaped
        bad = False
        for side, t in ((e.left, a), (e.right, b)):
            if not T.is_numeric(t):
                self._err(f"'{op}' needs numbers, not {t.show()}", side)
                bad = True
        if bad:
            return T.UNKNOWN
        if op == "-" and a == T.NAT and b == T.NAT:
            return T.INT
        return T.numeric_join(a, b)

    def _since_rule(self, e: ast.Binary) -> None:
        """RoboChart TE4 (warning): since/sinceEntry are compared with constants."""
        for timed, other in ((e.left, e.right), (e.right, e.left)):
            if isinstance(timed, (ast.Since, ast.SinceEntry)) and not self.robosim and not self._constant(other):
                self.sink.warning(
                    f"'{'since' if isinstance(timed, ast.Since) else 'sinceEntry'}' should be compared with a constant",
                    other.span,
                )

    def _type_limits(self, e: ast.Binary, a: T.Type, b: T.Type) -> None:
        """A comparison the operands' types decide (``k >= 0`` for a nat ``k``): a warning, and
        its value in the tables for code generation (:mod:`robogen.semantics.limits`)."""
        value = limits.constant_comparison(e, a, b)
        if value is not None:
            self.tables.comparisons[id(e)] = value
            self.sink.warning(limits.message(e, value, expr_text), e.span)

    def _constant(self, e: ast.Expr) -> bool:
        if isinstance(e, (ast.IntLit, ast.RealLit, ast.BoolLit)):
            return True
        if isinstance(e, ast.Name):
            v = self.tables.refs.get(id(e))
            return isinstance(v, EnumLitSym) or (isinstance(v, VarSym) and v.kind == "const")
        if isinstance(e, ast.Unary):
            return self._constant(e.operand)
        if isinstance(e, ast.Binary):
            first, links = ast.chain(e)
            return self._constant(first) and all(self._constant(link.right) for link in links)
        return False

    def _record(self, t: T.Type) -> T.Type:
        """A record type with its fields: a recursive datatype refers to itself through a
        placeholder without fields while it is being resolved (R { kids: Seq(R) })."""
        if isinstance(t, T.RecordT) and not t.fields:
            return self.records.get(t.qname, t)
        return t

    def _e_Field(self, e: ast.Field) -> T.Type:
        t = self._record(self.expr(e.obj))
        if isinstance(t, T.UnknownT):
            return t
        if not isinstance(t, T.RecordT):
            return self._err(f"'.{e.field}' selects a field, but this is {t.show()}, not a record", e.obj)
        ft = t.field(e.field)
        if ft is None:
            self.sink.error(
                f"datatype '{t.qname}' has no field '{e.field}'" + did_you_mean(e.field, [n for n, _ in t.fields]),
                e.field_span or e.span,
            )
            return T.UNKNOWN
        return ft

    def _e_Index(self, e: ast.Index) -> T.Type:
        t = self.expr(e.obj)
        its = [self.expr(i) for i in e.indices]
        if isinstance(t, T.UnknownT):
            return t
        if isinstance(t, T.ProductT):
            if len(e.indices) != 1 or not isinstance(e.indices[0], ast.IntLit):
                return self._err("a tuple component is selected by one integer literal, e.g. p[1]", e)
            k = e.indices[0].value
            if not 1 <= k <= len(t.items):
                return self._err(f"tuple of {len(t.items)} components has no component {k}", e.indices[0])
            return t.items[k - 1]
        for it, ie in zip(its, e.indices):
            if not T.is_integral(it):
                self._err(f"an index must be an integer, not {it.show()}", ie)
        if isinstance(t, (T.VectorT, T.SeqT)):
            if len(e.indices) != 1:
                return self._err(f"{t.show()} takes one index", e)
            return t.element
        if isinstance(t, T.MatrixT):
            if len(e.indices) != 2:
                return self._err("a matrix takes two indices, m[i, j]", e)
            return t.element
        if isinstance(t, T.FunctionT) and len(e.indices) == 1:
            return t.range
        return self._err(f"{t.show()} cannot be indexed", e.obj)

    def _e_IfExpr(self, e: ast.IfExpr) -> T.Type:
        c = self.expr(e.cond)
        if not T.is_boolean(c):
            self._err(f"the condition of 'if' must be boolean, not {c.show()}", e.cond)
        a, b = self.expr(e.then), self.expr(e.otherwise)
        if _untyped_empty(a) and T.assignable(a, b):  # if c then {} else {(| 2, 0 |)} end: the other branch's type
            return b
        joined = T.element_join(a, b)  # (as an enumeration's two elements: {x: real | ... @ <>} beside a Set(Seq(string)))
        if joined is not None:
            return joined
        return self._err(f"the branches of 'if' have different types: {a.show()} and {b.show()}", e)

    def _e_Cast(self, e: ast.Cast) -> T.Type:
        """``e as T`` has type T, if a value of e's type can be one of T: numbers convert, other
        values must be compatible one way or the other. ``e is T`` is a boolean."""
        value = self.expr(e.expr)
        t = self.resolve_type(e.type, self.scope.file)
        if e.op == "is":
            return T.BOOLEAN
        numbers = T.is_numeric(value) and T.is_numeric(t)
        if not (numbers or T.assignable(value, t) or T.assignable(t, value)):
            self.sink.error(f"a value of type {value.show()} cannot be cast as {t.show()}", e.type.span)
        return t

    def _bind(self, decls: tuple[ast.Decl, ...]) -> dict[str, VarSym]:
        frame = {}
        for d in decls:
            frame[d.name] = VarSym(d.name, self.resolve_type(d.type, self.scope.file), "binder", d, "binder")
        return frame

    def _e_Binder(self, e: ast.Binder) -> T.Type:
        frame = self._bind(e.decls)
        self.locals.append(frame)
        try:
            if e.such_that is not None:
                st = self.expr(e.such_that)
                if not T.is_boolean(st):
                    self._err(f"the predicate after '|' must be boolean, not {st.show()}", e.such_that)
            body = self.expr(e.body)
        finally:
            self.locals.pop()
        if e.kind in ("forall", "exists", "exists1"):
            if not T.is_boolean(body):
                self._err(f"the body of '{e.kind}' must be boolean, not {body.show()}", e.body)
            return T.BOOLEAN
        if e.kind == "lambda":
            dom = frame[e.decls[0].name].type if len(e.decls) == 1 else T.ProductT(tuple(v.type for v in frame.values()))
            return T.FunctionT(dom, body)
        # the x: T | p @ e: the value of e for the unique x that satisfies p (Z's mu-expression)
        return body

    def _e_Let(self, e: ast.Let) -> T.Type:
        frame: dict[str, VarSym] = {}
        self.locals.append(frame)
        try:
            for d in e.defs:
                frame[d.name] = VarSym(d.name, self.expr(d.value), "let", d, "let")
            return self.expr(e.body)
        finally:
            self.locals.pop()

    def _e_RecordLit(self, e: ast.RecordLit) -> T.Type:
        t = self.resolve_type(ast.TypeRef(e.type, span=e.type.span), self.scope.file)
        for fv in e.fields:
            self.expr(fv.value)
        if isinstance(t, T.UnknownT):
            return t
        if not isinstance(t, T.RecordT):
            return self._err(f"'{e.type.text}' is not a datatype", e.type)
        given = {fv.name: fv for fv in e.fields}
        for name, ft in t.fields:
            fv = given.pop(name, None)
            if fv is None:  # RoboTool checks only the fields given
                self.sink.warning(f"field '{name}' of '{t.qname}' is not given a value", e.span)
            elif not T.assignable(self.tables.type_of(fv.value), ft):
                self._err(f"field '{name}' must be {ft.show()}, but this is {self.tables.type_of(fv.value).show()}", fv.value)
        for name, fv in given.items():
            self.sink.error(f"datatype '{t.qname}' has no field '{name}'", fv.name_span)
        return t

    def _e_TupleLit(self, e: ast.TupleLit) -> T.Type:
        return T.ProductT(tuple(self.expr(i) for i in e.items))

    def _element(self, items, what: str) -> T.Type:
        ts = [self.expr(i) for i in items]
        if not ts:
            return T.UNKNOWN
        t = ts[0]
        for i, it in zip(items[1:], ts[1:]):
            t = self._wider(t, it, i, what)
        return t

    def _wider(self, t: T.Type, it: T.Type, at: ast.Node, what: str) -> T.Type:
        """The type of the elements of an enumeration whose elements so far are of type ``t``,
        and the next of type ``it``: numbers widen (<0, -1> is a Seq(int), not a Seq(nat) that
        would wrap -1), other types must fit one in the other: as RoboTool's type provider
        (``typeFor(SetExp)``), the next element's type where the type so far widens to it
        (``{ {1}, {-1} }`` is a Set(Set(int))), else the type so far where the next fits in it."""
        if _untyped_empty(t) and T.assignable(t, it):  # { {}, {1} }: the elements' type is the typed one's
            return it
        joined = T.element_join(t, it)
        if joined is not None:
            return joined
        self._err(f"the elements of a {what} must have one type: {t.show()} and {it.show()}", at)
        return t

    def _e_SeqLit(self, e: ast.SeqLit) -> T.Type:
        return T.SeqT(self._element(e.items, "sequence"))

    def _e_SetLit(self, e: ast.SetLit) -> T.Type:
        return T.SetT(self._element(e.items, "set"))

    def _e_SetRange(self, e: ast.SetRange) -> T.Type:
        """``{a .. b}``: RoboCalcTypeProvider (SetRange) types it by its bounds, integers or reals."""
        bounds = [self.expr(x) for x in (e.low, e.high)]
        for x, t in zip((e.low, e.high), bounds):
            if not T.is_numeric(t):
                self._err(f"a set range needs numeric bounds, not {t.show()}", x)
                return T.SetT(T.INT)
        return T.SetT(T.REAL if T.REAL in bounds else T.INT)

    def _e_Range(self, e: ast.Range) -> T.Type:
        for x in (e.low, e.high):
            t = self.expr(x)
            if not T.is_numeric(t):
                self._err(f"a range needs numeric bounds, not {t.show()}", x)
        return T.SetT(T.INT)

    def _e_SetComprehension(self, e: ast.SetComprehension) -> T.Type:
        frame = self._bind(e.decls)
        self.locals.append(frame)
        try:
            if e.such_that is not None:
                self.expr(e.such_that)
            if e.body is not None:
                body = self.expr(e.body)
            else:  # RoboCalcTypeProvider (SetComp): the variable's type, the product of several
                types = tuple(v.type for v in frame.values())
                body = types[0] if len(types) == 1 else T.ProductT(types)
        finally:
            self.locals.pop()
        return T.SetT(body)

    def _e_VectorLit(self, e: ast.VectorLit) -> T.Type:
        elements = [self._element(row, "vector") for row in e.rows]
        if len(e.rows) == 1:
            return T.VectorT(elements[0], len(e.rows[0]))
        widths = {len(r) for r in e.rows}
        if len(widths) != 1:
            return self._err("the rows of a matrix literal must have the same length", e)
        element = elements[0]
        for row, t in zip(e.rows[1:], elements[1:]):  # the elements of every row, not the first row's alone
            element = self._wider(element, t, row[0], "matrix")
        return T.MatrixT(element, len(e.rows), widths.pop())

    def _e_Since(self, e: ast.Since) -> T.Type:
        self._timed_allowed(e, "since")
        clock = self.scope.clocks.get(e.clock)
        if clock is None:
            self.sink.error(
                f"unknown clock '{e.clock}'" + did_you_mean(e.clock, self.scope.clocks),
                e.clock_span or e.span,
                Note(f"clocks are declared with 'clock {e.clock}' in the {self.scope.kind}"),
            )
            return T.NAT
        self.tables.refs[id(e)] = clock
        return T.NAT

    def _e_SinceEntry(self, e: ast.SinceEntry) -> T.Type:
        self._timed_allowed(e, "sinceEntry")
        found = [(path, n) for path, n in self.scope.all_states() if path[-1] == e.state.last and (not e.state.qualified or path == e.state.parts[-len(path):])]
        if not found:
            self._err(f"no state '{e.state.text}' in {self.scope.kind} '{self.scope.name}'", e.state)
        elif isinstance(found[0][1], ast.Final):
            self._err("'sinceEntry' of a final state", e.state)
        elif not isinstance(found[0][1], ast.State):
            self._err(f"'{e.state.text}' is not a state", e.state)
        else:
            self.tables.refs[id(e)] = found[0]
        return T.NAT

    def _timed_allowed(self, e: ast.Expr, word: str) -> None:
        if not self.where.guard:
            self._err(f"'{word}' may only appear in a transition condition", e)

    def _e_MatrixOp(self, e: ast.MatrixOp) -> T.Type:
        t = self.expr(e.operand)
        if e.op == "transpose" and isinstance(t, T.VectorT):  # RoboCalcTypeProvider (TransposeExp): a matrix of one row
            return T.MatrixT(t.element, 1, t.size)
        if not isinstance(t, (T.MatrixT, T.UnknownT)):
            return self._err(f"'{e.op}' needs a matrix, not {t.show()}", e.operand)
        if e.op == "transpose" and isinstance(t, T.MatrixT):
            return T.MatrixT(t.element, t.columns, t.rows)
        return t

__all__ = ["ExprChecker", "Where"]
