"""The function library of RoboChart: RoboTool's four toolkits, and robogen's three extensions.

RoboTool ships its toolkits as RoboChart packages of functions defined by contracts only
(``set_toolkit``, ``relation_toolkit``, ``function_toolkit``, ``sequence_toolkit``). robogen
knows each function by its signature, written below in RoboChart's own syntax and parsed once,
and by what it computes. As in RoboTool, only ``core`` (the primitive types) is imported
implicitly: a model names a toolkit function through ``import <toolkit>::*``,
``import <toolkit>::f`` or a qualified name (``relation_toolkit::dom(r)``). Calls are typed by
unifying the signature's type variables with the arguments (:func:`robogen.semantics.types.unify`).

robogen extensions, which RoboTool lacks: ``abs(x)``, ``min(x, y)`` and ``max(x, y)`` of numbers.
They stay because robogen's own code-generation models use them (``tests/codegen/models``) and
the generated C implements them; every use is warned about, as RoboTool rejects a model that
uses them. They are visible everywhere without an import, and ``min``/``max`` of two numbers
coexist with ``sequence_toolkit``'s ``min``/``max`` of a set of integers (the number of
arguments tells them apart). robogen's former ``card`` and ``elems`` are gone: RoboTool's
``size`` counts a set, and ``ran(s)`` is the set of a sequence's elements.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Callable, Mapping, Sequence

from robogen.semantics.types import (INT, NAT, PRIMITIVES, FunctionT, ProductT, SeqT, SetT, Type, TypeVarT,
                                     is_numeric, numeric_join)
from robogen.syntax import ast

# Each line: a signature in RoboChart syntax | what the function computes.
_LIBRARY = {
    "set_toolkit": """
        notin(m: ?X, s: Set(?X)): boolean | whether m is not a member of s
        subseteq(ss: Set(?X), s: Set(?X)): boolean | whether every member of ss is in s
        subset(ss: Set(?X), s: Set(?X)): boolean | whether ss is in s and differs from it
        union(s1: Set(?X), s2: Set(?X)): Set(?X) | the members of s1 or of s2
        inter(s1: Set(?X), s2: Set(?X)): Set(?X) | the members of both s1 and s2
        diff(s1: Set(?X), s2: Set(?X)): Set(?X) | the members of s1 that are not in s2
        symetric_diff(s1: Set(?X), s2: Set(?X)): Set(?X) | the members of exactly one of s1 and s2
        Union(A: Set(Set(?X))): Set(?X) | the members of some set in A
        Inter(A: Set(Set(?X))): Set(?X) | the members of every set in A
    """,
    "relation_toolkit": """
        first(p: ?X * ?Y): ?X | the first component of the pair p
        second(p: ?X * ?Y): ?Y | the second component of the pair p
        maplet(x: ?X, y: ?Y): ?X * ?Y | the pair of x and y
        dom(r: ?X <-> ?Y): Set(?X) | the first components of the pairs of r
        ran(r: ?X <-> ?Y): Set(?Y) | the second components of the pairs of r
        id(): ?X <-> ?X | the relation of every value to itself
        relcomp(r: ?X <-> ?Y, s: ?Y <-> ?Z): ?X <-> ?Z | r followed by s
        funcomp(s: ?Y -> ?Z, r: ?X -> ?Y): ?X <-> ?Z | s after r (r followed by s)
        dres(a: Set(?X), r: ?X <-> ?Y): ?X <-> ?Y | the pairs of r whose first component is in a
        rres(r: ?X <-> ?Y, b: Set(?Y)): ?X <-> ?Y | the pairs of r whose second component is in b
        dsub(a: Set(?X), r: ?X <-> ?Y): ?X <-> ?Y | the pairs of r whose first component is not in a
        rsub(r: ?X <-> ?Y, b: Set(?Y)): ?X <-> ?Y | the pairs of r whose second component is not in b
        rinv(r: ?X <-> ?Y): ?Y <-> ?X | r with each pair reversed
        rimage(r: ?X <-> ?Y, a: Set(?X)): Set(?Y) | what r relates the members of a to
        override(r: ?X <-> ?Y, s: ?X <-> ?Y): ?X <-> ?Y | s, with the pairs of r whose first component s does not relate
        tr_closure(r: ?X <-> ?X): ?X <-> ?X | r composed with itself one or more times
        refl_tr_closure(r: ?X <-> ?X): ?X <-> ?X | r composed with itself zero or more times
    """,
    "function_toolkit": """
        isTotal(f: ?X -> ?Y): boolean | whether f maps every value of its domain type
        isInjection(f: ?X -> ?Y): boolean | whether f maps different values to different values
        isTotalInjection(f: ?X -> ?Y): boolean | whether f is total and an injection
        isSurjection(f: ?X -> ?Y): boolean | whether every value of the range type is mapped to
        isTotalSurjection(f: ?X -> ?Y): boolean | whether f is total and a surjection
        isBijection(f: ?X -> ?Y): boolean | whether f is a total injection and a total surjection
        isFinite(s: Set(?X)): boolean | whether s has finitely many members
        isFiniteFunction(f: ?X -> ?Y): boolean | whether f has finitely many pairs
        isFiniteInjection(f: ?X -> ?Y): boolean | whether f is finite and an injection
        disjoint(f: ?L <-> Set(?X)): boolean | whether the sets f relates to different labels share no member
        partitions(f: ?L <-> Set(?X), a: Set(?X)): boolean | whether those sets are disjoint and together make a
    """,
    "sequence_toolkit": """
        range(x: int, y: int): Seq(int) | the integers from x to y, in order
        iter(n: int, r: ?X <-> ?X): ?X <-> ?X | r composed with itself n times (its inverse for n < 0)
        size(a: Set(?X)): nat | the number of members of a (of elements, for a sequence)
        hasMin(a: Set(int)): boolean | whether a has a least member
        hasMax(a: Set(int)): boolean | whether a has a greatest member
        min(a: Set(int)): int | the least member of a
        max(a: Set(int)): int | the greatest member of a
        isNonEmpty(s: Seq(?X)): boolean | whether s has an element
        isInjectiveSequence(s: Seq(?X)): boolean | whether no element of s repeats
        concat(s: Seq(?X), t: Seq(?X)): Seq(?X) | s followed by t
        reverse(s: Seq(?X)): Seq(?X) | s from its last element to its first
        head(s: Seq(?X)): ?X | the first element of s
        last(s: Seq(?X)): ?X | the last element of s
        tail(s: Seq(?X)): Seq(?X) | s without its first element
        front(s: Seq(?X)): Seq(?X) | s without its last element
        squash(f: int -> ?X): Seq(?X) | the values of f in the order of their indices, as a sequence
        extract(a: Set(int), s: Seq(?X)): Seq(?X) | the elements of s at the indices in a, in order
        filter(s: Seq(?X), a: Set(?X)): Seq(?X) | the elements of s that are in a, in order
        prefix(s: Seq(?X), t: Seq(?X)): boolean | whether t starts with s
        suffix(s: Seq(?X), t: Seq(?X)): boolean | whether t ends with s
        infix(s: Seq(?X), t: Seq(?X)): boolean | whether s occurs in t
        dconcat(s: Seq(Seq(?X))): Seq(?X) | the sequences of s one after another
    """,
}


@dataclass(frozen=True)
class Builtin:
    """A toolkit function: its package, signature and meaning."""

    package: str
    name: str
    params: tuple[tuple[str, Type], ...]
    result: Type
    meaning: str
    signature: str  # as written in the library, for notes

    @property
    def doc(self) -> str:
        return f"{self.package}::{self.signature}: {self.meaning}"

    @property
    def value_type(self) -> Type:
        """Its type as a value (RoboTool: a product domain even for one parameter; a function
        without parameters stands for its result)."""
        if not self.params:
            return self.result
        return FunctionT(ProductT(tuple(t for _, t in self.params)), self.result)


@dataclass(frozen=True)
class Extension:
    """A robogen extension: a function RoboTool lacks, typed by a rule (numbers of any kind)."""

    name: str
    arity: int
    rule: Callable[[Sequence[Type]], Type | str]  # the result type, or an error message
    doc: str


def _numbers(name: str):
    def rule(args: Sequence[Type]) -> Type | str:
        if not all(is_numeric(a) for a in args):
            return f"'{name}' expects numbers, not " + " and ".join(a.show() for a in args)
        if len(args) == 1:  # abs: an integer's absolute value is a nat
            return NAT if args[0] in (NAT, INT) else args[0]
        a, b = args
        return numeric_join(a, b)

    return rule


EXTENSIONS: Mapping[str, Extension] = {
    "abs": Extension("abs", 1, _numbers("abs"), "abs(x): the absolute value of a number"),
    "min": Extension("min", 2, _numbers("min"), "min(x, y): the smaller of two numbers"),
    "max": Extension("max", 2, _numbers("max"), "max(x, y): the larger of two numbers"),
}


def extension_warning(ext: Extension) -> str:
    return (f"'{ext.name}' of {ext.arity} argument{'s' if ext.arity > 1 else ''} is a robogen extension, "
            "not a RoboTool toolkit function: RoboTool rejects this model")


@functools.lru_cache(maxsize=None)
def library() -> Mapping[str, Mapping[str, Builtin]]:
    """Package name -> function name -> the toolkit function, parsed from :data:`_LIBRARY`."""
    from robogen.syntax.parser import parse_text

    packages: dict[str, dict[str, Builtin]] = {}
    for package, text in _LIBRARY.items():
        lines = [line.strip() for line in text.strip().splitlines()]
        entries = [line.split(" | ", 1) for line in lines]
        source = "\n".join(f"function {signature} {{ }}" for signature, _ in entries)
        functions = parse_text(source, f"<{package}>").items
        packages[package] = {
            f.name: Builtin(package, f.name, tuple((p.name, _type(p.type)) for p in f.params), _type(f.result), meaning, signature)
            for f, (signature, meaning) in zip(functions, entries)  # type: ignore[attr-defined]
        }
    return packages


def _type(t: ast.TypeExpr) -> Type:
    """A type of a library signature (primitive types, type variables and their compounds)."""
    if isinstance(t, ast.TypeRef):
        return PRIMITIVES[t.name.text]
    if isinstance(t, ast.TypeVar_):
        return TypeVarT(t.name)
    if isinstance(t, ast.SetType):
        return SetT(_type(t.element))
    if isinstance(t, ast.SeqType):
        return SeqT(_type(t.element))
    if isinstance(t, ast.ProductType):
        return ProductT(tuple(_type(x) for x in t.items))
    if isinstance(t, (ast.FunctionType, ast.RelationType)):
        return FunctionT(_type(t.domain), _type(t.range), isinstance(t, ast.RelationType))
    raise AssertionError(f"no library type {type(t).__name__}")  # pragma: no cover - the library is fixed




__all__ = ["Builtin", "Extension", "EXTENSIONS", "extension_warning", "library"]
