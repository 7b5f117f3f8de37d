"""Guards evaluated over small sample domains, for the analyses of robogen.semantics.machine_analysis.

A guard's *leaves* are the sub-expressions the evaluator does not look into: each input event
``$e`` (occurred or not), each boolean, enumeration or given-type value, each number. A boolean
leaf ranges over true and false, an enumeration leaf over its literals, a given-type leaf over
three distinct tokens, a numeric leaf over the number literals of the guards and their
neighbours (and, for reals, the midpoints between those). Constants declared with a literal
value and the RoboSim period ``cycle`` are their values, not leaves.

The sampling finds real examples (a witness is an assignment under which the guards hold, so
a warning built on one is never speculative), and it is exhaustive only in the case
:meth:`Guards.unsatisfiable` admits. Anything the evaluator cannot follow (a division, a
function of a leaf, a value bound by ``$e?x`` and read before) makes it decline to judge.

Each distinct leaf of a machine gets a small integer; a guard is compiled once into a closure
over an environment that maps those integers to values (evaluation is the analyses' hot spot).
A guard may be a flat chain of thousands of operands (``a /\\ b /\\ ...``): chains are walked,
compiled and evaluated in loops (:func:`robogen.syntax.ast.chain`), and sub-expressions are
told apart by :func:`_key`, never by hashing a deep node.
"""

from __future__ import annotations

import itertools
from fractions import Fraction
from typing import Callable, Iterator

from robogen.semantics import types as T
from robogen.semantics.model import EnumLitSym, EventSym, Tables, VarSym
from robogen.syntax import ast
from robogen.syntax.printer import expr as _printed

Number = int | Fraction
_NUMBERS = (int, Fraction)  # compared with type(x) in ..., so that booleans are not numbers

MAX_ASSIGNMENTS = 4096  # a witness search gives up beyond this many assignments
EXACT_LIMIT = 512  # unsatisfiable() evaluates at most this many

_LOGIC = ("/\\", "\\/", "=>", "iff")
_ORDER = ("<", "<=", ">", ">=")
_VISITED = _LOGIC + ("==", "!=") + _ORDER + ("+", "-", "*")


class Unknown(Exception):
    """The evaluator cannot decide a guard (it declines rather than guess)."""


def number(x: Fraction) -> Number:
    return x.numerator if x.denominator == 1 else x


def real_value(text: str) -> Number:
    return number(Fraction(text))


def const_value(e: ast.Name, tables: Tables) -> Number | bool | str | None:
    """The value of a constant declared with a literal value (a number, boolean or enumeration
    literal), or None: such a constant is not an unknown of a guard."""
    ref = tables.ref(e)
    if not isinstance(ref, VarSym) or ref.kind != "const" or ref.init is None:
        return None
    init = ref.init
    negate = isinstance(init, ast.Unary) and init.op == "-"
    if negate:
        init = init.operand  # type: ignore[union-attr]
    if isinstance(init, ast.IntLit):
        value: Number = init.value
    elif isinstance(init, ast.RealLit):
        value = real_value(init.text)
    elif isinstance(init, ast.BoolLit) and not negate:
        return init.value
    elif isinstance(init, ast.Name) and isinstance(tables.ref(init), EnumLitSym) and not negate:
        return tables.ref(init).literal  # type: ignore[union-attr]
    else:
        return None
    return -value if negate else value


# Sub-expressions whose node is its own key (hashing them is cheap and follows no operand).
_SHALLOW = (ast.Name, ast.IntLit, ast.RealLit, ast.BoolLit, ast.StringLit, ast.Keyword, ast.Dollar, ast.Since, ast.SinceEntry)


def _key(e: ast.Expr) -> object:
    """A key equal for equal sub-expressions: a name, a literal or a field of one is its own key;
    an operator expression is keyed by its operators and shallow operands in prefix order, built
    in a loop (hashing a node follows its operands recursively, and a flat chain of operators may
    be thousands deep); any other sub-expression by its text."""
    return e if _shallow(e) else _shape(e)


def _shallow(e: ast.Expr) -> bool:
    while isinstance(e, ast.Field):
        e = e.obj
    return isinstance(e, _SHALLOW)


# Operands keyed in _shape by their class and their one compared field (hashed in C, where a
# node's own hash and equality are Python functions).
_ATOM_FIELD = {ast.Name: "parts", ast.IntLit: "value", ast.RealLit: "text", ast.BoolLit: "value",
               ast.StringLit: "value", ast.Keyword: "word", ast.Since: "clock"}  # fmt: skip


def _shape(e: ast.Expr) -> tuple:
    """The prefix (Polish) form of the unary and binary operators and the inputs of ``e``, with
    every other operand as its _key: each operator's arity is fixed (an input says whether a
    predicate follows), so equal forms are equal expressions."""
    out: list[object] = []
    todo = [e]
    while todo:
        x = todo.pop()
        kind = type(x)
        if kind is ast.Binary:
            out.append(("binary", x.op))  # type: ignore[attr-defined]
            todo.append(x.right)  # type: ignore[attr-defined]
            todo.append(x.left)  # type: ignore[attr-defined]
        elif kind is ast.Unary:
            out.append(("unary", x.op))  # type: ignore[attr-defined]
            todo.append(x.operand)  # type: ignore[attr-defined]
        elif kind is ast.DollarInput:  # `$e?x` or `$e?x | predicate`: the predicate follows if there is one
            out.append(("input", x.event, x.var, x.qualifier, x.var_qualifier, x.predicate is not None))  # type: ignore[attr-defined]
            if x.predicate is not None:  # type: ignore[attr-defined]
                todo.append(x.predicate)  # type: ignore[attr-defined]
        elif kind in _ATOM_FIELD:
            out.append((kind, getattr(x, _ATOM_FIELD[kind])))
        else:
            out.append(x if _shallow(x) else ("text", _printed(x)))
    return tuple(out)


class _Leaf:
    __slots__ = ("kind", "expr", "finite", "numeric")

    def __init__(self, kind: str, expr: object, finite: list | None, numeric: T.Type | None):
        self.kind = kind  # "ev" (an event; expr is its name), "opaque" or "leaf": how a witness is described
        self.expr = expr
        self.finite = finite  # the domain of a non-numeric leaf
        self.numeric = numeric  # the type of a numeric leaf, whose domain depends on the literals


class Guards:
    """The guards of one machine: their leaves, compiled evaluators, witnesses."""

    def __init__(self, tables: Tables, period: Number | None = None):
        self.tables = tables
        self.period = period
        self._ids: dict[tuple, int] = {}
        self._leaves: list[_Leaf] = []
        # by the guard's key (equal guards have the same leaves, see key()):
        self._facts: dict[object, tuple[tuple[int, ...], frozenset]] = {}  # -> (leaf ids in order, literals)
        self._compiled: dict[object, Callable[[dict], object]] = {}  # -> evaluator
        self._keep: list[ast.Expr] = []  # the guards cached by id stay alive
        self._keys: dict[int, object] = {}  # id(guard) -> _key(guard)
        self._answers: dict[tuple, object] = {}  # (question, guard keys) -> answer

    # ------------------------------------------------------------------ leaves

    def _leaf(self, kind: str, expr: object, finite: list | None = None, numeric: T.Type | None = None) -> int:
        key = (kind, expr if kind == "ev" else _key(expr))  # type: ignore[arg-type]
        n = self._ids.get(key)
        if n is None:
            n = self._ids[key] = len(self._leaves)
            self._leaves.append(_Leaf(kind, expr, finite, numeric))
        return n

    def _leaf_id(self, kind: str, expr: object) -> int | None:
        """The number of a leaf already registered, if it is one."""
        return self._ids.get((kind, expr if kind == "ev" else _key(expr)))  # type: ignore[arg-type]

    def facts(self, g: ast.Expr) -> tuple[tuple[int, ...], frozenset]:
        """The leaves of ``g`` in the order first met, and the number literals it mentions."""
        key = self.key(g)
        cached = self._facts.get(key)
        if cached is not None:
            return cached
        order: dict[int, None] = {}
        literals: set[Number] = set()
        self._visit(g, order, literals)
        result = self._facts[key] = (tuple(order), frozenset(literals))
        return result

    def _visit(self, e: ast.Expr, order: dict[int, None], literals: set[Number]) -> None:
        """Record the leaves of ``e`` in ``order`` and its number literals in ``literals`` (a
        method, not a closure of facts(): a recursive closure is a reference cycle, and it would
        keep the whole machine's guards alive until the cyclic collector runs)."""
        tables = self.tables
        if isinstance(e, ast.IntLit):
            literals.add(e.value)
        elif isinstance(e, ast.RealLit):
            literals.add(real_value(e.text))
        elif isinstance(e, (ast.BoolLit, ast.StringLit)):
            pass
        elif isinstance(e, ast.Unary) and e.op == "-":  # `-10.0`: the samples must reach below -10
            inner: set[Number] = set()
            self._visit(e.operand, order, inner)
            literals.update(inner, (-v for v in inner))
        elif isinstance(e, ast.Unary) and e.op == "not":
            self._visit(e.operand, order, literals)
        elif isinstance(e, ast.Binary) and e.op in _VISITED:
            first, links = ast.chain(e, _VISITED)
            self._visit(first, order, literals)
            for link in links:
                self._visit(link.right, order, literals)
        elif isinstance(e, ast.DollarInput):
            order[self._leaf("ev", e.event, [False, True])] = None
            if e.predicate is not None:
                order[self._leaf("opaque", e.predicate, [False, True])] = None
        elif isinstance(e, ast.Name) and isinstance(tables.ref(e), EnumLitSym):
            pass
        elif isinstance(e, ast.Name) and const_value(e, tables) is not None:
            value = const_value(e, tables)
            if type(value) in _NUMBERS:
                literals.add(value)  # type: ignore[arg-type]
        elif isinstance(e, ast.Keyword) and e.word == "cycle":
            if self.period is not None:
                literals.add(self.period)
        elif isinstance(e, ast.Dollar) and isinstance(tables.ref(e), EventSym):
            order[self._leaf("ev", e.name, [False, True])] = None
        else:
            t = tables.type_of(e)
            if t == T.BOOLEAN:
                n = self._leaf("leaf", e, [False, True])
            elif isinstance(t, T.EnumT):
                n = self._leaf("leaf", e, list(t.literals))
            elif isinstance(t, T.Given):
                n = self._leaf("leaf", e, [f"{t.simple}#1", f"{t.simple}#2", f"{t.simple}#3"])
            elif t in T.NUMERIC:
                n = self._leaf("leaf", e, numeric=t)
            else:
                n = self._leaf("leaf", e, [False, True])  # opaque
            order[n] = None

    def _domains(self, ids: tuple[int, ...], literals: frozenset) -> list[list]:
        domains: list[list] = []
        candidates: list[Number] | None = None
        mids: list[Number] | None = None
        for n in ids:
            leaf = self._leaves[n]
            if leaf.numeric is None:
                domains.append(leaf.finite)  # type: ignore[arg-type]
                continue
            if candidates is None:
                points = sorted(literals | {0, 1, 2})
                candidates = sorted({p + d for p in points for d in (-1, 0, 1)})
            if leaf.numeric == T.REAL:
                if mids is None:
                    mids = [number(Fraction(a + b) / 2) for a, b in zip(candidates, candidates[1:])]
                domains.append(sorted(set(candidates + mids)))
            else:
                signed = leaf.numeric == T.INT
                domains.append([c for c in candidates if c.denominator == 1 and (signed or c >= 0)])
        return domains

    def _assignments(self, guards: list[ast.Expr], limit: int) -> Iterator[dict[int, object]]:
        """Every assignment of the leaves of ``guards`` (raises Unknown beyond ``limit``)."""
        order, domains = self._space(guards, limit)
        for values in itertools.product(*domains):
            yield dict(zip(order, values))

    def _space(self, guards: list[ast.Expr], limit: int) -> tuple[tuple[int, ...], list[list]]:
        """The leaves of ``guards`` (those of the first guard first, in its order) and their
        domains; raises Unknown when they have more than ``limit`` assignments."""
        ids: dict[int, None] = {}
        literals: frozenset = frozenset()
        for g in guards:
            leaf_ids, lits = self.facts(g)
            ids.update(dict.fromkeys(leaf_ids))
            literals |= lits
        order = tuple(ids)
        domains = self._domains(order, literals)
        total = 1
        for d in domains:
            total *= max(1, len(d))
            if total > limit:
                raise Unknown
        return order, domains

    # ------------------------------------------------------------------ evaluation

    def evaluator(self, g: ast.Expr) -> Callable[[dict], object]:
        key = self.key(g)
        f = self._compiled.get(key)
        if f is None:
            self.facts(g)  # registers the leaves the closures look up
            f = self._compiled[key] = self._compile(g)
        return f

    def _compile(self, e: ast.Expr) -> Callable[[dict], object]:
        tables = self.tables
        if isinstance(e, ast.BoolLit):
            return _constant(e.value)
        if isinstance(e, ast.IntLit):
            return _constant(e.value)
        if isinstance(e, ast.RealLit):
            return _constant(real_value(e.text))
        if isinstance(e, ast.Name):
            ref = tables.ref(e)
            if isinstance(ref, EnumLitSym):
                return _constant(ref.literal)
            value = const_value(e, tables)
            if value is not None:
                return _constant(value)
        if isinstance(e, ast.Keyword) and e.word == "cycle":
            return _constant(self.period) if self.period is not None else _unknown
        if isinstance(e, ast.Dollar) and ("ev", e.name) in self._ids:
            n = self._ids[("ev", e.name)]
            return lambda env: env[n]
        if isinstance(e, ast.DollarInput):
            occurred = self._ids[("ev", e.event)]
            if e.predicate is None:
                return lambda env: env[occurred]
            holds = self._leaf_id("opaque", e.predicate)
            return lambda env: env[occurred] and env[holds]
        if isinstance(e, ast.Unary):
            operand = self._compile(e.operand)
            if e.op == "not":
                return lambda env: not operand(env)
            return lambda env: _negate(operand(env))
        if isinstance(e, ast.Binary):
            return self._chain(e)
        n = self._leaf_id("leaf", e)
        if n is None:
            return _unknown
        return lambda env: env[n]

    def _chain(self, e: ast.Binary) -> Callable[[dict], object]:
        """A chain of binary operators (ast.chain): one operator is one closure; a longer chain
        is evaluated in a loop over its links, each combining the value so far with its right
        operand (evaluated only when the operator needs it, as `and` and `or` do)."""
        first, links = ast.chain(e)
        if any(link.op not in _STEPS for link in links):  # division, modulus, membership, concatenation
            return _unknown  # not followed: the chain's value needs that operator's
        if len(links) == 1:
            step, left, right = _STEPS[e.op], self._compile(e.left), self._compile(e.right)
            return lambda env: step(left(env), right, env)
        start = self._compile(first)
        steps = [(_STEPS[link.op], self._compile(link.right)) for link in links]

        def evaluate(env: dict) -> object:
            value = start(env)
            for step, right in steps:
                value = step(value, right, env)
            return value

        return evaluate

    # ------------------------------------------------------------------ questions

    # The answers are remembered by the guards' keys (_key): within one machine, equal guards have the
    # same leaves (leaves are told apart by _key too) and so the same answers; a machine's states
    # often repeat a guard (`not $e`, `x > k`), and this is where the analyses spend their time.

    def key(self, g: ast.Expr | None) -> object:
        """The key (_key) of a guard, computed once per guard."""
        if g is None:
            return None
        k = self._keys.get(id(g), _MISSING)
        if k is _MISSING:
            k = self._keys[id(g)] = _key(g)
            self._keep.append(g)
        return k

    def never_true(self, g: ast.Expr) -> bool:
        """Is ``g`` false whatever its leaves are? Claimed only when its propositional abstraction
        is unsatisfiable (see abstractly_satisfiable) or when unsatisfiable() says so."""
        question = ("never", self.key(g))
        answer = self._answers.get(question)
        if answer is None:
            answer = self._answers[question] = not abstractly_satisfiable(g) or self.unsatisfiable(g)
        return answer  # type: ignore[return-value]

    def common_witness(self, g1: ast.Expr | None, g2: ast.Expr | None) -> dict[int, object] | None:
        """witness(), remembered: the first assignment in which both guards hold, or None."""
        question = ("witness", self.key(g1), self.key(g2))
        answer = self._answers.get(question, _MISSING)
        if answer is _MISSING:
            answer = self._answers[question] = self.witness(g1, g2)
        return answer  # type: ignore[return-value]

    def witness(self, g1: ast.Expr | None, g2: ast.Expr | None) -> dict[int, object] | None:
        """An assignment under which both guards hold, or None (also when undecided)."""
        guards = [g for g in (g1, g2) if g is not None]
        evaluators = [self.evaluator(g) for g in guards]
        first, second = (evaluators + [_true, _true])[:2]
        try:
            order, domains = self._space(guards, MAX_ASSIGNMENTS)
            # The assignments in product order, the first guard's leaves first: its value is
            # known from them alone, so when it does not hold, the assignments that differ only
            # in the other leaves are skipped (the first witness found is the same).
            split = len(self.facts(guards[0])[0]) if guards else 0
            own, rest = order[:split], order[split:]
            for head in itertools.product(*domains[:split]):
                if first(dict(zip(own, head))) is not True:
                    continue
                for tail in itertools.product(*domains[split:]):
                    env = dict(zip(own, head))
                    env.update(zip(rest, tail))
                    if second(env) is True:
                        return env
        except Unknown:
            return None
        return None

    def unsatisfiable(self, g: ast.Expr) -> bool:
        """Is ``g`` false for every value of its leaves? Decided by evaluating it over the
        sample domains, which is exhaustive only when each comparison of numbers sets a leaf
        against a number constant (the samples then meet every interval the constants delimit);
        any other guard is declined."""
        if not self._exact(g) or rebinds(g):
            return False
        f = self.evaluator(g)
        try:
            for env in self._assignments([g], EXACT_LIMIT):
                if f(env) is True:
                    return False
            return True
        except Unknown:
            return False

    def _exact(self, e: ast.Expr) -> bool:
        tables = self.tables
        if isinstance(e, ast.BoolLit):
            return True
        if isinstance(e, ast.Unary) and e.op == "not":
            return self._exact(e.operand)
        if isinstance(e, ast.Binary) and e.op in _LOGIC:
            first, links = ast.chain(e, _LOGIC)
            return self._exact(first) and all(self._exact(link.right) for link in links)
        if isinstance(e, ast.Binary) and (e.op in _ORDER or (e.op in ("==", "!=") and tables.type_of(e.left) in T.NUMERIC)):
            return any(self._numeric_constant(a) and _plain_leaf(b) for a, b in ((e.left, e.right), (e.right, e.left)))
        if isinstance(e, ast.Binary) and e.op in ("==", "!="):
            return _plain_leaf(e.left) and _plain_leaf(e.right) and not isinstance(tables.type_of(e.left), T.Given)
        return _plain_leaf(e)

    def _numeric_constant(self, e: ast.Expr) -> bool:
        if isinstance(e, ast.Unary) and e.op == "-":
            return self._numeric_constant(e.operand)
        if isinstance(e, ast.Name):
            return type(const_value(e, self.tables)) in _NUMBERS
        if isinstance(e, ast.Keyword) and e.word == "cycle":
            return self.period is not None
        return isinstance(e, (ast.IntLit, ast.RealLit))

    def describe(self, env: dict[int, object]) -> str:
        """A witness in words: `$e occurs, x = 4, m = off`."""
        parts = []
        for n, value in env.items():
            leaf = self._leaves[n]
            if leaf.kind == "ev" and value:
                parts.append(f"${leaf.expr} occurs")
            elif leaf.kind == "leaf":
                text = _text(leaf.expr)  # type: ignore[arg-type]
                if text is None:
                    continue
                if isinstance(value, bool):
                    parts.append(f"{text} is {'true' if value else 'false'}")
                elif isinstance(value, Fraction):
                    parts.append(f"{text} = {float(value)}")
                else:
                    parts.append(f"{text} = {value}")
        return ", ".join(parts) if parts else "always"


def _numeric(operation: Callable[[Number, Number], object]) -> Callable[[object, Callable, dict], object]:
    """The step of an arithmetic operator or comparison: both operands must be numbers."""

    def step(x: object, right: Callable, env: dict) -> object:
        y = right(env)
        if type(x) not in _NUMBERS or type(y) not in _NUMBERS:
            raise Unknown
        return operation(x, y)  # type: ignore[arg-type]

    return step


# How each operator the evaluator follows combines the value of its left operand with its right
# operand (a closure, evaluated only if needed).
_STEPS: dict[str, Callable[[object, Callable, dict], object]] = {
    "/\\": lambda x, right, env: x and right(env),
    "\\/": lambda x, right, env: x or right(env),
    "=>": lambda x, right, env: (not x) or right(env),
    "iff": lambda x, right, env: x == right(env),
    "==": lambda x, right, env: x == right(env),
    "!=": lambda x, right, env: x != right(env),
    "<": _numeric(lambda x, y: x < y),
    "<=": _numeric(lambda x, y: x <= y),
    ">": _numeric(lambda x, y: x > y),
    ">=": _numeric(lambda x, y: x >= y),
    "+": _numeric(lambda x, y: x + y),
    "-": _numeric(lambda x, y: x - y),
    "*": _numeric(lambda x, y: x * y),
}


_MISSING = object()


def _true(env: dict) -> object:
    return True


def _constant(value: object) -> Callable[[dict], object]:
    return lambda env: value


def _unknown(env: dict) -> object:
    raise Unknown


def _negate(x: object) -> object:
    if type(x) not in _NUMBERS:
        raise Unknown
    return -x  # type: ignore[operator]


def _plain_leaf(e: ast.Expr) -> bool:
    """A sub-expression the evaluator takes as one unknown value (or a literal)."""
    return not isinstance(e, (ast.Binary, ast.Unary, ast.IfExpr, ast.Let, ast.Binder))


def _text(e: ast.Expr) -> str | None:
    if isinstance(e, ast.Name):
        return e.text
    if isinstance(e, ast.Dollar):
        return f"${e.name}"
    if isinstance(e, ast.Since):
        return f"since({e.clock})"
    if isinstance(e, ast.Field):
        inner = _text(e.obj)
        return f"{inner}.{e.field}" if inner else None
    return None


# ---------------------------------------------------------------------------- propositional view


def rebinds(g: ast.Expr) -> bool:
    """Does ``g`` bind a variable with `$e?x` that it also reads? Then `x` has one value before
    the binding and another after it (guards bind as they are evaluated, left to right), and
    analyses that give each leaf one value do not apply."""
    bound: set[str] = set()
    names: list[str] = []
    _bindings(g, bound, names)
    return bool(bound) and any(n in bound for n in names)


def _bindings(e: ast.Expr, bound: set[str], names: list[str]) -> None:
    """The variables ``e`` binds with `$e?x` into ``bound``, the names it reads into ``names``."""
    if isinstance(e, ast.DollarInput):
        bound.add(e.var)
        if e.predicate is not None:
            _bindings(e.predicate, bound, names)
    elif isinstance(e, ast.Name):
        names.append(e.last)
    elif isinstance(e, ast.Unary):
        _bindings(e.operand, bound, names)
    elif isinstance(e, ast.Binary):
        first, links = ast.chain(e)
        _bindings(first, bound, names)
        for link in links:
            _bindings(link.right, bound, names)


def abstractly_satisfiable(g: ast.Expr) -> bool:
    """Is ``g`` satisfiable when every comparison or other atom is a free proposition? (An
    over-approximation: a 'no' is sound.)"""
    atoms: dict[object, None] = {}
    _atoms(g, atoms)
    keys = list(atoms)
    if len(keys) > 12 or rebinds(g):
        return True
    normed: dict[int, tuple] = {}  # id(atom) -> _norm(atom), computed once per atom
    return any(_holds(g, dict(zip(keys, values)), normed) for values in itertools.product((False, True), repeat=len(keys)))


def _norm(e: ast.Expr) -> tuple[tuple, bool]:
    """A key for an atom and whether it is negated: a > b is not (a <= b)."""
    if isinstance(e, ast.Binary) and e.op in (">", ">="):
        return ("cmp", "<=" if e.op == ">" else "<", _key(e.left), _key(e.right)), True
    if isinstance(e, ast.Binary) and e.op == "!=":
        return ("cmp", "==", _key(e.left), _key(e.right)), True
    if isinstance(e, ast.Binary) and e.op in ("<", "<=", "=="):
        return ("cmp", e.op, _key(e.left), _key(e.right)), False
    if isinstance(e, ast.DollarInput):
        return ("ev", e.event, None if e.predicate is None else _key(e.predicate)), False
    return ("atom", _key(e)), False


def _atoms(e: ast.Expr, atoms: dict[object, None]) -> None:
    """The atoms of ``e`` (by their _norm keys) into ``atoms``, in the order first met."""
    if isinstance(e, ast.BoolLit):
        return
    if isinstance(e, ast.Unary) and e.op == "not":
        _atoms(e.operand, atoms)
    elif isinstance(e, ast.Binary) and e.op in _LOGIC:
        first, links = ast.chain(e, _LOGIC)
        _atoms(first, atoms)
        for link in links:
            _atoms(link.right, atoms)
    else:
        atoms[_norm(e)[0]] = None


def _holds(e: ast.Expr, env: dict, normed: dict[int, tuple]) -> bool:
    """The value of ``e`` when each atom has the value ``env`` gives its key."""
    if isinstance(e, ast.BoolLit):
        return e.value
    if isinstance(e, ast.Unary) and e.op == "not":
        return not _holds(e.operand, env, normed)
    if isinstance(e, ast.Binary) and e.op in _LOGIC:
        first, links = ast.chain(e, _LOGIC)
        a = _holds(first, env, normed)
        for link in links:
            b = _holds(link.right, env, normed)
            op = link.op
            a = (a and b) if op == "/\\" else (a or b) if op == "\\/" else ((not a) or b) if op == "=>" else a == b
        return a
    known = normed.get(id(e))
    if known is None:
        known = normed[id(e)] = _norm(e)
    key, negated = known
    return env[key] != negated


__all__ = ["Guards", "Unknown", "abstractly_satisfiable", "const_value", "number", "rebinds"]
