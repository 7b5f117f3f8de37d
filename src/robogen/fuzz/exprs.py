"""Random well-typed expressions: :meth:`Exprs.expr` writes an expression of a requested type
in a scope, and returns it with the type the checker will give it.

Numbers follow the checker's lattice: an expression asked for a ``nat`` has type ``nat``, one
asked for an ``int`` has type ``nat`` or ``int``, one asked for a ``real`` any number. Every
type has a literal, so an expression of any type can always be written (depth 0 gives a
literal or a variable). The generator avoids what would only make a run end early (division
by a value that may be zero, ``head`` of a possibly empty sequence) and what the checker warns
about (a comparison whose value the types decide, a record literal without a field).
"""

from __future__ import annotations

import random
from dataclasses import dataclass, field, replace

from robogen.fuzz.toolkit import ToolkitForms
from robogen.fuzz.typegen import NUMBERS, SCALARS, TypeEnv, is_collection, is_tagged, name, type_ast
from robogen.semantics import limits
from robogen.semantics import types as T
from robogen.syntax import ast


@dataclass(frozen=True)
class Sym:
    """Something an expression can read: a variable, constant, parameter or bound name."""

    name: str
    type: T.Type
    kind: str = "var"  # var const param binder shared

    @property
    def assignable(self) -> bool:
        return self.kind in ("var", "shared")


@dataclass(frozen=True)
class UserFn:
    """A user function: its signature, and its C and Python bodies (see robogen.fuzz.functions),
    or (switch postcondition_functions) the expression its postcondition ``result == e`` gives;
    its parameters may have the type variable ``?X`` (switch generic_functions)."""

    name: str
    params: tuple[tuple[str, T.Type], ...]
    result: T.Type
    c_body: str | None
    py: str | None
    contract: ast.Expr | None = None

    @property
    def generic(self) -> bool:
        return any("?" in t.show() for _, t in self.params)


@dataclass(frozen=True)
class Scope:
    """What an expression can see where it is written."""

    syms: tuple[Sym, ...] = ()
    robosim: bool = False
    guard: bool = False  # a transition condition: since, sinceEntry, the $ tests of inputs
    inputs: tuple[tuple[str, T.Type | None], ...] = ()  # RoboSim input events
    clocks: tuple[str, ...] = ()
    states: tuple[str, ...] = ()  # states sinceEntry may name
    functions: tuple[UserFn, ...] = ()
    dollar_vars: tuple[Sym, ...] = ()  # RoboSim: variables read as $x
    lambdas: bool = True  # lambda bodies see only their parameters

    def with_syms(self, *syms: Sym) -> "Scope":
        return replace(self, syms=self.syms + syms)

    def of_type(self, t: T.Type, assignable: bool = False) -> list[Sym]:
        return [s for s in self.syms if fits(s.type, t) and (s.assignable or not assignable)]


def fits(value: T.Type, target: T.Type) -> bool:
    """May a value of type ``value`` stand where ``target`` is asked for? Numbers only widen
    (nat -> int -> real): narrowing is legal but wraps at run time."""
    if value in NUMBERS and target in NUMBERS:
        return NUMBERS.index(value) <= NUMBERS.index(target)
    return value == target


@dataclass
class Exprs(ToolkitForms):
    rng: random.Random
    env: TypeEnv
    on: frozenset[str]
    toolkits: set[str] = field(default_factory=set)  # the toolkits the model must import
    names: int = 0
    written: set[T.Type] = field(default_factory=set)  # the types of the expressions written (see Machines)

    def fresh(self, prefix: str) -> str:
        self.names += 1
        return f"{prefix}{self.names}"

    def chance(self, p: float) -> bool:
        return self.rng.random() < p

    @staticmethod
    def sym(x: str, t: T.Type) -> Sym:
        return Sym(x, t, "binder")

    # ---------------------------------------------------------------- entry point

    def expr(self, t: T.Type, sc: Scope, depth: int = 2) -> tuple[ast.Expr, T.Type]:
        """An expression of type ``t`` (see fits) readable in ``sc``, and its type."""
        rng = self.rng
        self.written.add(t)
        if depth <= 0 or rng.random() < 0.25:
            result = self.leaf(t, sc)
        else:
            options = self._generic(t, sc) + self._specific(t, sc) + self.toolkit_forms(t, sc)
            if not options:
                result = self.leaf(t, sc)
            else:
                make = rng.choices([m for _, m in options], [w for w, _ in options])[0]
                result = make(depth - 1)
        self.written.add(result[1])  # (a tuple of literals has the literals' types: nat * nat)
        return result

    def leaf(self, t: T.Type, sc: Scope) -> tuple[ast.Expr, T.Type]:
        syms = sc.of_type(t)
        if syms and self.chance(0.6):
            s = self.rng.choice(syms)
            return ast.Name((s.name,)), s.type
        dollar = [s for s in sc.dollar_vars if fits(s.type, t)]
        if dollar and self.chance(0.5):
            s = self.rng.choice(dollar)
            return ast.Dollar(s.name), s.type
        lit = self.literal(t, sc)
        return lit, _literal_type(lit, t)

    # ---------------------------------------------------------------- literals

    def number(self, t: T.Type, positive: bool = False) -> ast.Expr:
        rng = self.rng
        if t == T.REAL:
            text = rng.choice(("0.5", "1.5", "2.0", "0.25", "3.75", "10.0", "0.0", "1.0"))
            lit: ast.Expr = ast.RealLit("1.5" if positive and text == "0.0" else text)
        else:
            value = rng.choice((0, 1, 1, 2, 3, 4, 5, 7, 10, 100))
            if rng.random() < 0.03:
                value = rng.choice((2**31, 2**40, 2**62))
            lit = ast.IntLit(max(value, 1) if positive else value)
        if t != T.NAT and not positive and rng.random() < 0.3:
            return ast.Unary("-", lit)
        return lit

    def literal(self, t: T.Type, sc: Scope) -> ast.Expr:
        rng = self.rng
        self.written.add(t)
        if t in NUMBERS:
            return self.number(t)
        if t == T.BOOLEAN:
            return ast.BoolLit(rng.random() < 0.5)
        if t == T.STRING:
            return ast.StringLit(rng.choice(("", "a", "hello", "x y", "\u00e9t\u00e9", "bye")))
        if isinstance(t, T.EnumT):
            return self.enum_literal(t, sc, 0)[0]
        if isinstance(t, T.RecordT):
            return ast.RecordLit(name(t.qname), tuple(ast.FieldValue(n, self.literal(ft, sc)) for n, ft in t.fields))
        if isinstance(t, T.ProductT):
            return ast.TupleLit(tuple(self.literal(x, sc) for x in t.items))
        if isinstance(t, (T.SetT, T.SeqT)):
            items = [(x, _literal_type(x, t.element)) for x in (self.literal(t.element, sc) for _ in range(rng.choice((0, 1, 2))))]
            return (ast.SetLit if isinstance(t, T.SetT) else ast.SeqLit)(chained(items)[0])
        if isinstance(t, T.VectorT):
            return ast.VectorLit((tuple(self.number(t.element) for _ in range(t.size)),))  # type: ignore[arg-type]
        if isinstance(t, T.MatrixT):
            return ast.VectorLit(tuple(tuple(self.number(t.element) for _ in range(t.columns))  # type: ignore[arg-type]
                                       for _ in range(t.rows)))  # type: ignore[arg-type]
        if isinstance(t, T.FunctionT):
            return self.lambda_(t, sc, 0)[0]
        raise TypeError(f"no literal of {t.show()}")  # pragma: no cover

    def foldable(self, t: T.Type, sc: Scope) -> ast.Expr:
        """The value of a constant that code generation computes when it generates the FMU (a
        parameter's start value): literals, other constants, negation and + - * of numbers."""
        rng = self.rng
        if isinstance(t, (T.VectorT, T.MatrixT)):
            rows = 1 if isinstance(t, T.VectorT) else t.rows
            width = t.size if isinstance(t, T.VectorT) else t.columns
            return ast.VectorLit(tuple(tuple(self.foldable(t.element, sc) for _ in range(width))  # type: ignore[arg-type]
                                       for _ in range(rows)))  # type: ignore[arg-type]
        if t not in NUMBERS:
            return self.leaf(t, sc)[0] if not is_tagged(t) else self.literal(t, sc)
        syms = [s for s in sc.syms if s.kind == "const" and fits(s.type, t)]
        r = rng.random()
        if syms and r < 0.3:
            return ast.Name((rng.choice(syms).name,))
        if r < 0.6:
            return self.number(t)
        a, b = self.foldable(t, sc), self.foldable(t, sc)
        op = rng.choice(("+", "*") if t == T.NAT else ("+", "-", "*"))
        return ast.Binary(op, a, b)

    def enum_literal(self, t: T.EnumT, sc: Scope, depth: int) -> tuple[ast.Expr, T.Type]:
        choices = range(len(t.literals))
        if depth <= 0:  # a literal that does not carry the enumeration itself, where one does
            choices = [i for i in choices if not any(self.env.resolve(a) == t for a in (t.literal_args[i] if t.literal_args else ()))]
        i = self.rng.choice(list(choices))
        lit = t.literals[i]
        text = f"{t.qname}::{lit}" if self.chance(0.5) else lit
        args = tuple(self.env.resolve(a) for a in (t.literal_args[i] if t.literal_args else ()))
        if not args:
            return name(text), t
        values = tuple(self.expr(a, sc, depth - 1)[0] if depth else self.literal(a, sc) for a in args)
        return ast.Call(name(text), values), t

    def lambda_(self, t: T.FunctionT, sc: Scope, depth: int) -> tuple[ast.Expr, T.Type]:
        """``lambda x: D @ body``: the body sees only x (a function stored in a variable may not
        read the machine's variables)."""
        x = self.fresh("x")
        inner = Scope(syms=(Sym(x, t.domain, "binder"),), robosim=sc.robosim)
        body, bt = self.expr(t.range, inner, depth)
        return ast.Binder("lambda", (ast.Decl(x, type_ast(t.domain)),), None, body), T.FunctionT(t.domain, bt)

    # ---------------------------------------------------------------- forms of any type

    def _generic(self, t: T.Type, sc: Scope) -> list:
        out: list = []
        syms = sc.of_type(t)
        if syms:
            out.append((3, lambda d: self.leaf(t, sc)))
        if "lets" in self.on and not isinstance(t, T.FunctionT):
            out.append((1, lambda d: self._if(t, sc, d)))
            out.append((1, lambda d: self._let(t, sc, d)))
        fields = [(r, n) for r in self.env.records for n, ft in r.fields if fits(ft, t)]
        if fields:
            out.append((2, lambda d: self._field(self.rng.choice(fields), sc, d)))
        tuples = [s for s in sc.syms if isinstance(s.type, T.ProductT) and any(fits(x, t) for x in s.type.items)]
        if tuples:
            out.append((2, lambda d: self._project(self.rng.choice(tuples), t)))
        functions = [f for f in sc.functions if fits(f.result, t) or f.generic and f.result == t]
        if functions:
            out.append((2, lambda d: self._user_call(self.rng.choice(functions), sc, d)))
        applied = [s for s in sc.syms if isinstance(s.type, T.FunctionT) and fits(s.type.range, t)]
        if applied:
            out.append((2, lambda d: self._apply(self.rng.choice(applied), sc, d)))
        if "function_values" in self.on and not isinstance(t, T.FunctionT) and sc.lambdas:
            out.append((1, lambda d: self._apply_lambda(t, sc, d)))
        return out

    def _if(self, t: T.Type, sc: Scope, d: int) -> tuple[ast.Expr, T.Type]:
        c = self.boolean(sc, d)
        a, at = self.expr(t, sc, d)
        b, bt = self.expr(t, sc, d)
        return ast.IfExpr(c, a, b), join(at, bt)

    def _let(self, t: T.Type, sc: Scope, d: int) -> tuple[ast.Expr, T.Type]:
        x = self.fresh("l")
        vt = self.env.draw("var", 1) if self.chance(0.5) else t
        if isinstance(vt, T.FunctionT):
            vt = t
        value, real_t = self.expr(vt, sc, d)
        body, bt = self.expr(t, sc.with_syms(Sym(x, real_t, "binder")), d)
        return ast.Let((ast.LetDef(x, value),), body), bt

    def _field(self, rf: tuple[T.RecordT, str], sc: Scope, d: int) -> tuple[ast.Expr, T.Type]:
        r, f = rf
        self.written.add(r)
        obj, _ = self.expr(r, sc, d)
        return ast.Field(obj, f), r.field(f)  # type: ignore[return-value]

    def _project(self, s: Sym, t: T.Type) -> tuple[ast.Expr, T.Type]:
        items = s.type.items  # type: ignore[attr-defined]
        k = self.rng.choice([i for i, x in enumerate(items) if fits(x, t)])
        return ast.Index(ast.Name((s.name,)), (ast.IntLit(k + 1),)), items[k]

    def _user_call(self, f: UserFn, sc: Scope, d: int) -> tuple[ast.Expr, T.Type]:
        """A call; of a generic function, with ?X instantiated by a type drawn for this call."""
        bindings = {"X": self.env.scalar("elem")} if f.generic else {}
        args = tuple(self._argument(T.instantiate(pt, bindings), sc, d, f.generic) for _, pt in f.params)
        return ast.Call(ast.Name((f.name,)), args), T.instantiate(f.result, bindings)

    def _argument(self, t: T.Type, sc: Scope, d: int, generic: bool) -> ast.Expr:
        """An argument of type ``t``; of a generic function, a collection is cast to its type
        (``<>`` alone does not decide ?X: a located error, as the README says)."""
        e = self.expr(t, sc, d)[0]
        return ast.Cast("as", e, type_ast(t)) if generic and isinstance(t, (T.SetT, T.SeqT)) else e

    def _apply(self, s: Sym, sc: Scope, d: int) -> tuple[ast.Expr, T.Type]:
        ft: T.FunctionT = s.type  # type: ignore[assignment]
        return ast.Call(ast.Name((s.name,)), (self.expr(ft.domain, sc, d)[0],)), ft.range

    def _apply_lambda(self, t: T.Type, sc: Scope, d: int) -> tuple[ast.Expr, T.Type]:
        """``(lambda x: D @ e)(a)``, or of two parameters ``(lambda x: D, y: E @ e)(a, b)``."""
        n = self.rng.choice((1, 1, 2))
        params = [(self.fresh("x"), self.env.scalar("param") if self.chance(0.7) else self.rng.choice(NUMBERS))
                  for _ in range(n)]
        params = [(p, pt if pt != T.STRING else T.INT) for p, pt in params]
        inner = Scope(syms=tuple(Sym(p, pt, "binder") for p, pt in params), robosim=sc.robosim)
        body, bt = self.expr(t, inner, d)
        lam = ast.Binder("lambda", tuple(ast.Decl(p, type_ast(pt)) for p, pt in params), None, body)
        return ast.Call(lam, tuple(self.expr(pt, sc, d)[0] for _, pt in params)), bt

    # ---------------------------------------------------------------- forms by type

    def _specific(self, t: T.Type, sc: Scope) -> list:
        if t == T.BOOLEAN:
            return [(6, lambda d: (self.boolean(sc, d + 1), T.BOOLEAN))]
        if t in NUMBERS:
            return [(6, lambda d: self.arith(t, sc, d))]
        if isinstance(t, T.EnumT):
            return [(3, lambda d: self.enum_literal(t, sc, d))]
        if isinstance(t, T.RecordT):
            return [(3, lambda d: (ast.RecordLit(name(t.qname), tuple(ast.FieldValue(n, self.expr(ft, sc, d)[0])
                                                                      for n, ft in t.fields)), t))]
        if isinstance(t, T.ProductT):
            return [(3, lambda d: self._tuple(t, sc, d))]
        if isinstance(t, T.SetT):
            return [(4, lambda d: self.set_expr(t, sc, d))]
        if isinstance(t, T.SeqT):
            return [(4, lambda d: self.seq_expr(t, sc, d))]
        if isinstance(t, (T.VectorT, T.MatrixT)):
            return [(4, lambda d: self.linear(t, sc, d))]
        if isinstance(t, T.FunctionT):
            return [(3, lambda d: self.lambda_(t, sc, d))]
        return []

    def _tuple(self, t: T.ProductT, sc: Scope, d: int) -> tuple[ast.Expr, T.Type]:
        items = [self.expr(x, sc, d) for x in t.items]
        return ast.TupleLit(tuple(e for e, _ in items)), T.ProductT(tuple(x for _, x in items))

    def arith(self, t: T.Type, sc: Scope, d: int) -> tuple[ast.Expr, T.Type]:
        """A number of type ``t`` (or narrower): + - * / % and unary minus."""
        rng = self.rng
        ops = ["+", "*", "/", "%"] + (["-", "neg"] if t != T.NAT else [])
        if t == T.NAT and self._sizeable(sc) and self.chance(0.3):
            return self._size(sc, d)
        op = rng.choice(ops)
        if op == "neg":
            e, et = self.expr(t, sc, d)
            return ast.Unary("-", e), T.INT if et == T.NAT else et
        a, at = self.expr(t, sc, d)
        if op in ("/", "%"):  # a divisor that is never zero: a positive literal
            b: ast.Expr = self.number(t if t != T.INT else T.NAT, positive=True)
            bt = T.REAL if isinstance(b, ast.RealLit) else T.NAT
        else:
            b, bt = self.expr(t, sc, d)
        if op == "%" and T.REAL in (at, bt) and t != T.REAL:
            op = "*"
        result = T.INT if op == "-" and at == bt == T.NAT else T.numeric_join(at, bt)
        if not fits(result, t):  # (nat - nat is an int)
            return self.expr(t, sc, 0)
        return ast.Binary(op, a, b), result

    def _sizeable(self, sc: Scope) -> list[Sym]:
        return [s for s in sc.syms if is_collection(s.type)]

    def _size(self, sc: Scope, d: int) -> tuple[ast.Expr, T.Type]:
        self.toolkits.add("sequence_toolkit")
        s = self.rng.choice(self._sizeable(sc))
        return ast.Call(name("size"), (ast.Name((s.name,)),)), T.NAT

    # ---------------------------------------------------------------- booleans

    def boolean(self, sc: Scope, d: int) -> ast.Expr:
        """A boolean expression (conditions included: the $ forms, since and sinceEntry)."""
        rng = self.rng
        if d <= 0:
            return self.leaf(T.BOOLEAN, sc)[0] if not sc.guard or not self._guard_atoms(sc) else self._guard_atom(sc, 0)
        forms = [(4, self._compare), (2, self._equal), (2, self._not), (3, self._connective)]
        if self._guard_atoms(sc):
            forms.append((5, self._guard_atom))
        if any(is_collection(s.type) for s in sc.syms):
            forms.append((2, self._member))
        forms += self.predicates(sc)
        make = rng.choices([m for _, m in forms], [w for w, _ in forms])[0]
        return make(sc, d - 1)

    def condition(self, sc: Scope, used: set[str]) -> ast.Expr:
        """A transition's condition: mostly one or two tests of the machine's variables and
        inputs (so that it can hold and can fail; a random boolean expression is often constant
        and the checker warns that a transition can never fire), sometimes any boolean. A test
        avoids the variables, inputs and clocks in ``used`` (those of the other conditions of the
        same source: conditions made to exclude each other could otherwise contradict
        themselves), and adds its own."""
        rng = self.rng
        if rng.random() < 0.05:
            return self.boolean(sc, 2)
        atoms = [self._test(sc, used) for _ in range(rng.choice((1, 1, 1, 2)))]
        e = atoms[0]
        for a in atoms[1:]:
            e = ast.Binary(rng.choice(("/\\", "\\/")), e, a)
        return e

    def _test(self, sc: Scope, used: set[str]) -> ast.Expr:
        rng = self.rng
        free = [s for s in sc.syms if s.kind in ("var", "shared") and s.name not in used]
        numbers = [s for s in free if s.type in NUMBERS]
        flags = [s for s in free if s.type == T.BOOLEAN]
        enums = [s for s in free if isinstance(s.type, T.EnumT) and not is_tagged(s.type)]
        inner = replace(sc, inputs=tuple(i for i in sc.inputs if i[0] not in used),
                        clocks=tuple(c for c in sc.clocks if c not in used),
                        states=tuple(x for x in sc.states if x not in used))
        forms = ["guard"] * 4 * self._guard_atoms(inner)
        forms += ["number"] * 3 * bool(numbers) + ["flag"] * bool(flags) + ["enum"] * bool(enums)
        if not forms:  # every test is taken: test a variable again (the conditions may then contradict)
            numbers = [s for s in sc.syms if s.kind in ("var", "shared") and s.type in NUMBERS]
            forms = ["number"] if numbers else ["any"]
        form = rng.choice(forms)
        if form == "guard":
            e = self._guard_atom(inner, 1)
            used.update(_tested(e))
            return e
        if form == "any":
            return self.boolean(replace(sc, guard=False), 1)
        v = rng.choice(numbers if form == "number" else flags if form == "flag" else enums)
        used.add(v.name)
        if form == "number":
            op = rng.choice(("<", "<=", ">", ">=", "==", "!="))
            bound = ast.IntLit(rng.randint(0, 5)) if v.type != T.REAL else self.number(T.REAL)
            return self.undecided(ast.Binary(op, ast.Name((v.name,)), bound), v.type, _literal_type(bound, v.type))
        if form == "flag":
            return ast.Name((v.name,)) if rng.random() < 0.6 else ast.Unary("not", ast.Name((v.name,)))
        return ast.Binary(rng.choice(("==", "!=")), ast.Name((v.name,)), self.literal(v.type, sc))

    def _not(self, sc: Scope, d: int) -> ast.Expr:
        return ast.Unary("not", self.boolean(sc, d))

    def _connective(self, sc: Scope, d: int) -> ast.Expr:
        op = self.rng.choice(("/\\", "\\/", "/\\", "\\/", "=>", "iff"))
        return ast.Binary(op, self.boolean(sc, d), self.boolean(sc, d))

    def _compare(self, sc: Scope, d: int) -> ast.Expr:
        op = self.rng.choice(("<", "<=", ">", ">=", "==", "!="))
        t = self.rng.choice(NUMBERS)
        a, at = self.expr(t, sc, d)
        b, bt = self.expr(t, sc, d)
        return self.undecided(ast.Binary(op, a, b), at, bt)

    def undecided(self, e: ast.Binary, at: T.Type, bt: T.Type) -> ast.Binary:
        """``e``, or, if its operands' types decide it (``k >= 0`` for a nat ``k``: the checker
        warns), ``e`` with its number literal replaced by a positive one."""
        if limits.constant_comparison(e, at, bt) is None:
            return e
        positive = ast.IntLit(self.rng.randint(1, 5))
        if _number_literal(e.right):
            return ast.Binary(e.op, e.left, positive)
        return ast.Binary(e.op, positive, e.right)

    def _equal(self, sc: Scope, d: int) -> ast.Expr:
        t = self.env.draw("var", 1)
        if isinstance(t, T.FunctionT):
            t = T.INT
        a, at = self.expr(t, sc, d)
        b, bt = self.expr(t, sc, d)
        return self.undecided(ast.Binary(self.rng.choice(("==", "!=")), a, b), at, bt)

    def _member(self, sc: Scope, d: int) -> ast.Expr:
        s = self.rng.choice([s for s in sc.syms if is_collection(s.type)])
        x, _ = self.expr(s.type.element, sc, d)  # type: ignore[attr-defined]
        return ast.Binary("in", x, ast.Name((s.name,)))

    def _guard_atoms(self, sc: Scope) -> bool:
        return sc.guard and bool(sc.inputs or sc.clocks or sc.states)

    def _guard_atom(self, sc: Scope, d: int) -> ast.Expr:
        """``$e``, ``$e?x``, ``$e?x : p``, ``$e.v`` of an input; ``since(C)``, ``sinceEntry(S)``."""
        rng = self.rng
        kinds = []
        if sc.inputs:
            kinds += ["dollar"] * 3
        if sc.clocks:
            kinds.append("since")
        if sc.states:
            kinds.append("entry")
        kind = rng.choice(kinds)
        if kind in ("since", "entry"):
            timed: ast.Expr = ast.Since(rng.choice(sc.clocks)) if kind == "since" else ast.SinceEntry(name(rng.choice(sc.states)))
            bound = ast.IntLit(rng.randint(1, 4))
            op = rng.choice(("<", "<=", ">", ">=", "==", "!="))
            return ast.Binary(op, timed, bound) if rng.random() < 0.8 else ast.Binary(op, bound, timed)
        event, et = rng.choice(sc.inputs)
        binders = [s for s in sc.syms if s.assignable and et is not None and fits_bind(et, s.type)]
        r = rng.random()
        if et is not None and binders and r < 0.5:
            var = rng.choice(binders)
            pred = None
            if rng.random() < 0.3:  # an atom or a call: parenthesised by the printer
                pred = self.boolean(sc, 0)
            return ast.DollarInput(event, var.name, pred)
        if et is not None and r < 0.7 and not isinstance(et, T.FunctionT):
            return ast.DollarValue(event, self.expr(et, replace(sc, guard=False), 0)[0])
        return ast.Dollar(event)

    # ---------------------------------------------------------------- collections

    def set_expr(self, t: T.SetT, sc: Scope, d: int) -> tuple[ast.Expr, T.Type]:
        rng = self.rng
        r = rng.random()
        if r < 0.4 or "sets" not in self.on:
            items, element = self._enumeration(t.element, sc, d, self.expr)
            return ast.SetLit(items), T.SetT(element)
        if r < 0.8:
            self.toolkits.add("set_toolkit")
            op = rng.choice(("union", "inter", "diff", "symetric_diff"))
            return ast.Call(name(op), (self.operand(t, sc, d), self.operand(t, sc, d))), t
        self.toolkits.add("relation_toolkit")  # ran of a sequence: its elements
        return ast.Call(name("ran"), (self.operand(T.SeqT(t.element), sc, d),)), t

    def seq_expr(self, t: T.SeqT, sc: Scope, d: int) -> tuple[ast.Expr, T.Type]:
        rng = self.rng
        r = rng.random()
        if r < 0.35 or "sequences" not in self.on:
            items, element = self._enumeration(t.element, sc, d, self._seq_item)
            return ast.SeqLit(items), T.SeqT(element)
        self.toolkits.add("sequence_toolkit")
        if r < 0.6:
            op = rng.choice(("^", "cat", "concat"))
            a, b = self.operand(t, sc, d), self.operand(t, sc, d)
            return (ast.Call(name("concat"), (a, b)) if op == "concat" else ast.Binary(op, a, b)), t
        if r < 0.75:
            return ast.Call(name("reverse"), (self.operand(t, sc, d),)), t
        if r < 0.9:
            return ast.Call(name("filter"), (self.operand(t, sc, d), self.operand(T.SetT(t.element), sc, d))), t
        q = self._named(t, sc) or self.operand(t, sc, 0)
        op = rng.choice(("tail", "front"))  # of a sequence that is not empty
        return ast.IfExpr(ast.Binary(">", ast.Call(name("size"), (q,)), ast.IntLit(0)), ast.Call(name(op), (q,)), q), t

    def operand(self, t: T.SetT | T.SeqT, sc: Scope, d: int) -> ast.Expr:
        """An operand of a toolkit function: never an empty enumeration (``union({}, {})`` leaves
        the element type unknown, and code generation refuses a set of unknown elements)."""
        e, _ = self.expr(t, sc, d)
        if isinstance(e, (ast.SetLit, ast.SeqLit)) and not e.items:
            return type(e)((self.literal(t.element, sc),))
        return e

    def _seq_item(self, t: T.Type, sc: Scope, d: int) -> tuple[ast.Expr, T.Type]:
        """An element of a sequence literal: an additive expression (a comparison or a binder
        there would need the parentheses the printer adds)."""
        return self.expr(t, sc, d)

    def _enumeration(self, t: T.Type, sc: Scope, d: int, item) -> tuple[tuple[ast.Expr, ...], T.Type]:
        """The elements of a set or sequence enumeration asked for elements of type ``t``, and the
        type the checker gives its elements. As RoboTool's type provider (``typeFor(SetExp)``),
        the checker takes the first element's type and, element by element, the wider of it and
        the next, and rejects an element of neither a wider nor a narrower type: ``(| 2.0, 0 |)``
        (``real * nat``) beside ``(| -1, 0.5 |)`` (``int * real``). Such an element is written again
        as a copy of the first one (found by the fuzzer: 1.281)."""
        items, element = chained([item(t, sc, d) for _ in range(self.rng.choice((0, 1, 2, 3)))])
        return items, element if items else t

    def exact_set(self, e: T.Type, sc: Scope, d: int) -> ast.Expr:
        """A set whose type is exactly ``Set(e)``, for ``x in s`` with ``x: e`` (RoboTool's type
        provider asks the member's type to fit in the set's element type, so a ``real`` member of
        a ``Set(int)`` is an error): a variable of that type, or an enumeration with one literal
        of type ``e`` (its elements' type is then ``e``; found by the fuzzer: 1.316)."""
        syms = [s for s in sc.syms if s.type == T.SetT(e)]
        if e in SCALARS and e not in NUMBERS and self.chance(0.5):  # (a set of pairs may be a relation: not for 'in')
            return self.operand(T.SetT(e), sc, d)
        if syms and self.chance(0.5):
            return ast.Name((self.rng.choice(syms).name,))
        items, element = self._enumeration(e, sc, d, self.expr)
        if T.element_join(element, e) != e:
            items = ()
        return ast.SetLit(items + (self.exact_literal(e, sc),))

    def exact_literal(self, t: T.Type, sc: Scope) -> ast.Expr:
        """A literal the checker types as exactly ``t`` (``-1`` for an int, ``0.5`` for a real)."""
        if t == T.INT:
            return ast.Unary("-", ast.IntLit(self.rng.randint(1, 3)))
        if t == T.REAL:
            return ast.RealLit(self.rng.choice(("0.5", "1.5", "2.0")))
        if isinstance(t, T.ProductT):
            return ast.TupleLit(tuple(self.exact_literal(x, sc) for x in t.items))
        if isinstance(t, (T.SetT, T.SeqT)):
            return (ast.SetLit if isinstance(t, T.SetT) else ast.SeqLit)((self.exact_literal(t.element, sc),))
        return self.literal(t, sc)

    def _named(self, t: T.Type, sc: Scope) -> ast.Expr | None:
        syms = sc.of_type(t)
        return ast.Name((self.rng.choice(syms).name,)) if syms else None

    # ---------------------------------------------------------------- vectors and matrices

    def linear(self, t: T.VectorT | T.MatrixT, sc: Scope, d: int) -> tuple[ast.Expr, T.Type]:
        """A vector or matrix: a literal, a sum or difference, a negation, a number times one, a
        matrix product, a transpose (switch matrix_ops); with the type the checker gives it (the
        widest of its parts' numbers)."""
        rng = self.rng
        r = rng.random()
        if r < 0.3:
            if d <= 0:
                lit = self.literal(t, sc)
                return lit, _literal_type(lit, t)
            return self._linear_lit(t, sc, d)
        if r < 0.55:
            (a, at), (b, bt) = self.expr(t, sc, d), self.expr(t, sc, d)
            return ast.Binary(rng.choice(("+", "-")), a, b), _shaped(t, at, bt)
        if r < 0.7 and t.element != T.NAT:
            a, at = self.expr(t, sc, d)
            return ast.Unary("-", a), _shaped(t, at, T.INT)
        if r < 0.85:
            (k, kt), (a, at) = self.expr(t.element, sc, d), self.expr(t, sc, d)
            return ast.Binary("*", k, a), _shaped(t, at, kt)
        if isinstance(t, T.VectorT):
            if t.size < 2:  # (a matrix has two rows or more)
                return self.literal(t, sc), t
            inner = rng.randint(2, 3)
            (m, mt), (v, vt) = self.expr(T.MatrixT(t.element, t.size, inner), sc, d), self.expr(T.VectorT(t.element, inner), sc, d)
            return ast.Binary("*", m, v), _shaped(t, mt, vt)
        if "matrix_ops" in self.on and rng.random() < 0.5:
            m, mt = self.expr(T.MatrixT(t.element, t.columns, t.rows), sc, d)
            return ast.MatrixOp("transpose", m), _shaped(t, mt)
        inner = rng.randint(2, 3)
        (a, at), (b, bt) = self.expr(T.MatrixT(t.element, t.rows, inner), sc, d), self.expr(T.MatrixT(t.element, inner, t.columns), sc, d)
        return ast.Binary("*", a, b), _shaped(t, at, bt)

    def _linear_lit(self, t: T.VectorT | T.MatrixT, sc: Scope, d: int) -> tuple[ast.Expr, T.Type]:
        """A vector or matrix literal of expressions, and its type."""
        rows, width = (1, t.size) if isinstance(t, T.VectorT) else (t.rows, t.columns)
        items = [[self.expr(t.element, sc, d - 1) for _ in range(width)] for _ in range(rows)]  # type: ignore[arg-type]
        return ast.VectorLit(tuple(tuple(x for x, _ in row) for row in items)), _shaped(t, *(xt for row in items for _, xt in row))


def _shaped(t: T.VectorT | T.MatrixT, *parts: T.Type) -> T.Type:
    """``t`` with the widest number of ``parts`` (numbers, vectors, matrices) as its element."""
    numbers = [p.element if isinstance(p, (T.VectorT, T.MatrixT)) else p for p in parts]
    element = join(*[n for n in numbers if n in NUMBERS]) if any(n in NUMBERS for n in numbers) else t.element
    return T.VectorT(element, t.size) if isinstance(t, T.VectorT) else T.MatrixT(element, t.rows, t.columns)


def _tested(e: ast.Expr) -> set[str]:
    """The input, clock or state a test of a condition is about."""
    while isinstance(e, ast.Binary):
        e = e.left if isinstance(e.left, (ast.Since, ast.SinceEntry)) else e.right
    if isinstance(e, ast.Since):
        return {e.clock}
    if isinstance(e, ast.SinceEntry):
        return {e.state.last}
    if isinstance(e, ast.Dollar):
        return {e.name}
    if isinstance(e, (ast.DollarInput, ast.DollarValue)):
        return {e.event}
    return set()


def _literal_type(e: ast.Expr, t: T.Type) -> T.Type:
    """The checker's type of a literal written for type ``t``: an integer literal is a nat, its
    negation an int; a tuple, vector or matrix of them has the types of its parts (``(| 1, 2 |)``
    is a ``nat * nat``, ``[| 1, -2 |]`` a ``vector(int, 2)``)."""
    if t in NUMBERS:
        if isinstance(e, ast.RealLit) or isinstance(e, ast.Unary) and isinstance(e.operand, ast.RealLit):
            return T.REAL
        return T.INT if isinstance(e, ast.Unary) else T.NAT if isinstance(e, ast.IntLit) else t
    if isinstance(t, T.ProductT) and isinstance(e, ast.TupleLit) and len(e.items) == len(t.items):
        return T.ProductT(tuple(_literal_type(x, xt) for x, xt in zip(e.items, t.items)))
    if isinstance(t, (T.VectorT, T.MatrixT)) and isinstance(e, ast.VectorLit) and t.element in NUMBERS:
        items = [_literal_type(x, t.element) for row in e.rows for x in row]
        element = join(*items) if items else t.element
        return T.VectorT(element, t.size) if isinstance(t, T.VectorT) else T.MatrixT(element, t.rows, t.columns)
    return t


def _number_literal(e: ast.Expr) -> bool:
    while isinstance(e, ast.Unary) and e.op == "-":
        e = e.operand
    return isinstance(e, (ast.IntLit, ast.RealLit))


def fits_bind(event: T.Type, var: T.Type) -> bool:
    """May an input of type ``event`` be bound to a variable of type ``var``?"""
    return fits(event, var) and not isinstance(event, T.FunctionT)


def chained(items: list[tuple[ast.Expr, T.Type]]) -> tuple[tuple[ast.Expr, ...], T.Type | None]:
    """The elements of an enumeration (each with its type) that the checker accepts together, and
    their type (None: no element): an element whose type is neither wider nor narrower than the
    others' so far (``(| 2.0, 0 |)`` beside ``(| -1, 0.5 |)``) is replaced by a copy of the first."""
    out: list[ast.Expr] = []
    element: T.Type | None = None
    for e, et in items:
        if element is None:
            element = et
        else:
            wider = T.element_join(element, et)
            if wider is None:
                e, wider = out[0], element
            element = wider
        out.append(e)
    return tuple(out), element


def join(a: T.Type, *others: T.Type) -> T.Type:
    """The type of ``if c then a else b end`` (of the elements of a literal)."""
    for b in others:
        if a in NUMBERS and b in NUMBERS:
            a = NUMBERS[max(NUMBERS.index(a), NUMBERS.index(b))]
    return a


__all__ = ["Exprs", "Scope", "Sym", "UserFn", "chained", "fits", "fits_bind", "join", "is_tagged"]
