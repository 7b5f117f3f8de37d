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


def draw(rng: random.Random, env: TypeEnv, x) -> tuple[UserFn, ...]:
    """Zero to two user functions."""
    out = []
    for _ in range(rng.choice((0, 0, 1, 2))):
        params, result, c_body, py = rng.choice(CATALOGUE)
        out.append(UserFn(x.fresh("fn"), tuple(zip(PARAM_NAMES, params)), result, c_body, py))
    return tuple(out)


def declarations(functions: tuple[UserFn, ...]) -> list[ast.FunctionDef]:
    return [ast.FunctionDef(f.name, tuple(ast.Param(n, type_ast(t)) for n, t in f.params), type_ast(f.result))
            for f in functions]


def c_file(functions: tuple[UserFn, ...]) -> str:
    lines = ["/* User functions of a generated model (robogen.fuzz). */"]
    for f in functions:
        params = ", ".join(f"{C_TYPES[t]} {n}" for n, t in f.params)
        lines.append(f"static {C_TYPES[f.result]} rg_user_{f.name}({params}) {{ {f.c_body} }}")
    return "\n".join(lines) + "\n"


def python(functions: tuple[UserFn, ...]) -> dict:
    """The Python implementations, for the reference interpreter."""
    out = {}
    for f in functions:
        args = ", ".join(n for n, _ in f.params)
        out[f.name] = eval(f"lambda {args}: {f.py}", {})  # the catalogue's own text
    return out


__all__ = ["draw", "declarations", "c_file", "python", "CATALOGUE"]
