"""User functions of generated models: declared in the model by their signature (a contract
with no body), implemented in C (the file given to the code generator with ``--functions``)
and in Python (for the reference interpreter), from a catalogue of bodies that mean the same
in both languages on every input: comparisons and selections only, no arithmetic that could
overflow (C's signed overflow is undefined), no division.
"""

from __future__ import annotations

import random

from robogen.fuzz.exprs import UserFn
from robogen.fuzz.typegen import TypeEnv, type_ast
from robogen.semantics import types as T
from robogen.syntax import ast

C_TYPES = {T.NAT: "uint64_t", T.INT: "int64_t", T.REAL: "double", T.BOOLEAN: "bool"}

# (parameter types, result type, C body, Python body); a and b are the parameters
CATALOGUE: tuple[tuple[tuple[T.Type, ...], T.Type, str, str], ...] = (
    ((T.INT, T.INT), T.INT, "return a > b ? a : b;", "a if a > b else b"),
    ((T.INT, T.INT), T.INT, "return a < b ? a : b;", "a if a < b else b"),
    ((T.NAT, T.NAT), T.NAT, "return a >= b ? a : b;", "a if a >= b else b"),
    ((T.NAT,), T.BOOLEAN, "return a % 2u == 0u;", "a % 2 == 0"),
    ((T.INT,), T.BOOLEAN, "return a > 0;", "a > 0"),
    ((T.REAL, T.REAL), T.REAL, "return a > b ? b : a;", "b if a > b else a"),
    ((T.REAL,), T.BOOLEAN, "return a >= 0.5;", "a >= 0.5"),
    ((T.BOOLEAN, T.INT), T.INT, "return a ? b : 0;", "b if a else 0"),
    ((T.BOOLEAN,), T.BOOLEAN, "return !a;", "not a"),
    ((T.INT,), T.NAT, "return a < 0 ? 0u : (uint64_t)a;", "0 if a < 0 else a"),
    ((T.REAL,), T.REAL, "return a < 0.0 ? -a : a;", "-a if a < 0.0 else a"),
)

PARAM_NAMES = ("a", "b")


X = T.TypeVarT("X")
A, B = ast.Name(("a",)), ast.Name(("b",))

# functions defined by `postcondition result == e` (switch postcondition_functions; with ?X,
# switch generic_functions): (parameter types, result type, e, the toolkit e needs)
CONTRACTS: tuple[tuple[tuple[T.Type, ...], T.Type, ast.Expr, str | None], ...] = (
    ((T.INT, T.INT), T.INT, ast.Binary("+", A, B), None),
    ((T.REAL,), T.REAL, ast.Binary("*", A, ast.RealLit("2.0")), None),
    ((T.NAT,), T.BOOLEAN, ast.Binary("==", ast.Binary("%", A, ast.IntLit(2)), ast.IntLit(0)), None),
    ((T.BOOLEAN, T.INT), T.INT, ast.IfExpr(A, B, ast.IntLit(0)), None),
)
GENERIC: tuple[tuple[tuple[T.Type, ...], T.Type, ast.Expr, str | None], ...] = (
    ((T.SetT(X), X), T.BOOLEAN, ast.Binary("in", B, A), None),
    ((T.SeqT(X),), T.NAT, ast.Call(ast.Name(("size",)), (A,)), "sequence_toolkit"),
    ((X, X), T.BOOLEAN, ast.Binary("==", A, B), None),
)


def draw(rng: random.Random, env: TypeEnv, x) -> tuple[UserFn, ...]:
    """Zero to two user functions implemented in C, and, with their switches, functions defined
    by their postcondition, generic or not."""
    out = []
    for _ in range(rng.choice((0, 0, 1, 2))):
        params, result, c_body, py = rng.choice(CATALOGUE)
        out.append(UserFn(x.fresh("fn"), tuple(zip(PARAM_NAMES, params)), result, c_body, py))
    generic = tuple(g for g in GENERIC if all(_switched_on(t, env.on) for t in g[0]))
    pool = CONTRACTS * ("postcondition_functions" in env.on) + generic * ("generic_functions" in env.on)
    for _ in range(rng.choice((0, 1, 2)) if pool else 0):
        params, result, body, toolkit = rng.choice(pool)
        if toolkit is not None:
            x.toolkits.add(toolkit)
        out.append(UserFn(x.fresh("fn"), tuple(zip(PARAM_NAMES, params)), result, None, None, body))
    return tuple(out)


def _switched_on(t: T.Type, on) -> bool:
    """Is a parameter of type ``t`` allowed by the switches (a set needs sets, a sequence sequences)?"""
    return not (isinstance(t, T.SetT) and "sets" not in on or isinstance(t, T.SeqT) and "sequences" not in on)


def declarations(functions: tuple[UserFn, ...]) -> list[ast.FunctionDef]:
    def members(f: UserFn) -> tuple[ast.Node, ...]:
        if f.contract is None:
            return ()
        return (ast.Postcondition(ast.Binary("==", ast.Keyword("result"), f.contract)),)

    return [ast.FunctionDef(f.name, tuple(ast.Param(n, _syntax(t)) for n, t in f.params), _syntax(f.result), members(f))
            for f in functions]


def _syntax(t: T.Type) -> ast.TypeExpr:
    if isinstance(t, T.TypeVarT):
        return ast.TypeVar_(t.name)
    if isinstance(t, T.SetT):
        return ast.SetType(_syntax(t.element))
    if isinstance(t, T.SeqT):
        return ast.SeqType(_syntax(t.element))
    return type_ast(t)


def c_file(functions: tuple[UserFn, ...]) -> str | None:
    """The C file of the functions implemented in C (None when there is none)."""
    if all(f.c_body is None for f in functions):
        return None
    lines = ["/* User functions of a generated model (robogen.fuzz). */"]
    for f in functions:
        if f.c_body is None:
            continue
        params = ", ".join(f"{C_TYPES[t]} {n}" for n, t in f.params)
        lines.append(f"static {C_TYPES[f.result]} rg_user_{f.name}({params}) {{ {f.c_body} }}")
    return "\n".join(lines) + "\n"


def python(functions: tuple[UserFn, ...]) -> dict:
    """The Python implementations, for the reference interpreter."""
    out = {}
    for f in functions:
        if f.py is None:
            continue
        args = ", ".join(n for n, _ in f.params)
        out[f.name] = eval(f"lambda {args}: {f.py}", {})  # the catalogue's own text
    return out


__all__ = ["draw", "declarations", "c_file", "python", "CATALOGUE", "CONTRACTS", "GENERIC"]
