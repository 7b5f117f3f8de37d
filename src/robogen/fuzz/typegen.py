"""The types of generated models: the datatypes and enumerations a model declares, random types
for each place a type appears, and their syntax.

Types are the checker's own values (:mod:`robogen.semantics.types`), so the generator tracks
the type of every expression it writes with the checker's vocabulary. A record or enumeration
is named by its simple name (one file, no package prefix). Where a type may appear is a
*purpose*:

- ``var``: a machine variable or constant (anything code generation stores);
- ``port``: the payload of an event at the FMU boundary (FMI variables: no functions, no
  collections of enumerations with arguments, no collections of records with vector fields);
- ``elem``: the element of a set or sequence; ``field``: a field of a record;
- ``param``: a parameter of an operation or of a user function (what the C file receives).
"""

from __future__ import annotations

import random
from dataclasses import dataclass, field

from robogen.semantics import types as T
from robogen.syntax import ast

NUMBERS = (T.NAT, T.INT, T.REAL)
SCALARS = (T.NAT, T.INT, T.REAL, T.BOOLEAN)


def name(text: str) -> ast.Name:
    return ast.Name(tuple(text.split("::")))


def ref(text: str) -> ast.TypeRef:
    return ast.TypeRef(name(text))


def type_ast(t: T.Type) -> ast.TypeExpr:
    """The syntax of type ``t``."""
    if isinstance(t, T.Prim):
        return ref(t.name)
    if isinstance(t, (T.RecordT, T.EnumT)):
        return ref(t.qname)
    if isinstance(t, T.SetT):
        return ast.SetType(type_ast(t.element))
    if isinstance(t, T.SeqT):
        return ast.SeqType(type_ast(t.element))
    if isinstance(t, T.ProductT):
        return ast.ProductType(tuple(type_ast(x) for x in t.items))
    if isinstance(t, T.FunctionT):
        return ast.FunctionType(type_ast(t.domain), type_ast(t.range))
    if isinstance(t, T.VectorT):
        return ast.VectorType(type_ast(t.element), ast.IntLit(t.size))  # type: ignore[arg-type]
    if isinstance(t, T.MatrixT):
        return ast.MatrixType(type_ast(t.element), ast.IntLit(t.rows), ast.IntLit(t.columns))  # type: ignore[arg-type]
    raise TypeError(f"no syntax for {t.show()}")  # pragma: no cover


def is_tagged(t: T.Type) -> bool:
    return isinstance(t, T.EnumT) and any(t.literal_args)


def holds(t: T.Type, pred) -> bool:
    """Does ``t`` or a type inside it satisfy ``pred``?"""
    if pred(t):
        return True
    if isinstance(t, T.RecordT):
        return any(holds(ft, pred) for _, ft in t.fields)
    if isinstance(t, T.EnumT):
        return any(holds(a, pred) for args in t.literal_args for a in args)
    if isinstance(t, T.ProductT):
        return any(holds(x, pred) for x in t.items)
    if isinstance(t, (T.SetT, T.SeqT, T.VectorT, T.MatrixT)):
        return holds(t.element, pred)
    if isinstance(t, T.FunctionT):
        return holds(t.domain, pred) or holds(t.range, pred)
    return False


def parts(t: T.Type):
    """``t`` and every type inside it."""
    yield t
    inner: tuple = ()
    if isinstance(t, T.RecordT):
        inner = tuple(ft for _, ft in t.fields)
    elif isinstance(t, T.EnumT):
        inner = tuple(a for args in t.literal_args for a in args)
    elif isinstance(t, T.ProductT):
        inner = t.items
    elif isinstance(t, (T.SetT, T.SeqT, T.VectorT, T.MatrixT)):
        inner = (t.element,)
    elif isinstance(t, T.FunctionT):
        inner = (t.domain, t.range)
    for x in inner:
        yield from parts(x)


def is_struct(t: T.Type) -> bool:
    """Is ``t`` a C struct of generated code (a record, a tuple, an enumeration with arguments,
    a vector, a matrix)?"""
    return isinstance(t, (T.RecordT, T.ProductT, T.VectorT, T.MatrixT)) or is_tagged(t)


def is_collection(t: T.Type) -> bool:
    return isinstance(t, (T.SetT, T.SeqT))


@dataclass
class TypeEnv:
    """The datatypes and enumerations of one model, in declaration order, and the random
    choices of types over them."""

    rng: random.Random
    on: frozenset[str]
    records: list[T.RecordT] = field(default_factory=list)
    enums: list[T.EnumT] = field(default_factory=list)
    decls: list[ast.Node] = field(default_factory=list)
    _count: int = 0

    def fresh(self, prefix: str) -> str:
        self._count += 1
        return f"{prefix}{self._count}"

    # ---------------------------------------------------------------- declarations

    def declare(self) -> None:
        """Draw the model's enumerations and datatypes."""
        rng = self.rng
        for _ in range(rng.choice((0, 1, 1, 2))):
            self._enumeration(tagged=False)
        if "enum_args" in self.on and rng.random() < 0.5:
            self._enumeration(tagged=True)
        if "recursive_enums" in self.on and rng.random() < 0.5:
            self._recursive_enumeration()
        if "records" in self.on:
            for _ in range(rng.choice((0, 1, 1, 2, 3))):
                self._record()

    def _enumeration(self, tagged: bool) -> T.EnumT:
        n = self.rng.randint(1, 4)
        base = self.fresh("E")
        literals = tuple(f"{base.lower()}_{chr(97 + i)}" for i in range(n))
        args: list[tuple[T.Type, ...]] = []
        for _ in literals:
            if tagged and self.rng.random() < 0.6:
                args.append(tuple(self.rng.choice(SCALARS + tuple(self.enums)) for _ in range(self.rng.randint(1, 2))))
            else:
                args.append(())
        if tagged and not any(args):
            args[-1] = (T.INT,)
        t = T.EnumT(base, literals, tuple(args) if any(args) else ())
        self.enums.append(t)
        self.decls.append(ast.Enumeration(base, tuple(ast.EnumLiteral(lit, tuple(type_ast(a) for a in la))
                                                      for lit, la in zip(literals, args))))
        return t

    def _recursive_enumeration(self) -> T.EnumT:
        """``enumeration E { e_leaf e_node(E, nat) }``: a literal that carries the enumeration (the
        argument is the placeholder ``EnumT(E, ())``, see :meth:`resolve`)."""
        base = self.fresh("E")
        lower = base.lower()
        literals = (f"{lower}_leaf", f"{lower}_node")
        args = ((), (T.EnumT(base, ()), self.rng.choice(SCALARS)))
        t = T.EnumT(base, literals, args)
        self.enums.append(t)
        self.decls.append(ast.Enumeration(base, tuple(ast.EnumLiteral(lit, tuple(type_ast(a) for a in la))
                                                      for lit, la in zip(literals, args))))
        return t

    def resolve(self, t: T.Type) -> T.Type:
        """A recursive enumeration's placeholder as the enumeration it stands for."""
        if isinstance(t, T.EnumT) and not t.literals:
            return next((e for e in self.enums if e.qname == t.qname), t)
        return t

    def _record(self) -> T.RecordT:
        base = self.fresh("R")
        fields = []
        for i in range(self.rng.randint(1, 3)):
            fields.append((f"f{i + 1}", self.draw("field", 1)))
        t = T.RecordT(base, tuple(fields))
        self.records.append(t)
        self.decls.append(ast.Record(base, tuple(ast.FieldDecl(n, type_ast(ft)) for n, ft in fields)))
        return t

    # ---------------------------------------------------------------- random types

    def scalar(self, purpose: str = "var") -> T.Type:
        options: list[T.Type] = list(SCALARS) * 2
        options += [e for e in self.enums if not is_tagged(e) or purpose not in ("elem",)]
        if "strings" in self.on and purpose in ("var", "port", "field") or purpose == "elem" and "strings_in_collections" in self.on:
            options.append(T.STRING)
        return self.rng.choice(options)

    def draw(self, purpose: str, depth: int = 2) -> T.Type:
        """A random type for ``purpose`` (see the module docstring), at most ``depth`` levels of
        structure deep."""
        rng, on = self.rng, self.on
        if depth <= 0 or rng.random() < 0.55:
            return self.scalar(purpose)
        forms = []
        if self.records and purpose != "elem" or purpose == "elem" and self._elem_records():
            forms.append("record")
        if "tuples" in on:
            forms.append("tuple")
        if purpose not in ("elem",) or "nested_collections" in on:
            if "sets" in on:
                forms.append("set")
            if "sequences" in on:
                forms.append("seq")
        if purpose not in ("elem", "param") or "nested_collections" in on:
            if "vectors" in on:
                forms.append("vector")
            if "matrices" in on:
                forms.append("matrix")
        if purpose == "var" and "function_values" in on:
            forms.append("function")
        if not forms:
            return self.scalar(purpose)
        form = rng.choice(forms)
        return self._form(form, purpose, depth)

    def _elem_records(self) -> list[T.RecordT]:
        return [r for r in self.records if "nested_collections" in self.on or not holds(r, lambda x: is_collection(x)
                or isinstance(x, (T.VectorT, T.MatrixT, T.FunctionT)) or x == T.STRING or is_tagged(x))]

    def _form(self, form: str, purpose: str, depth: int) -> T.Type:
        rng = self.rng
        if form == "record":
            pool = self._elem_records() if purpose == "elem" else self.records
            return rng.choice(pool)
        if form == "tuple":
            inner = "elem" if purpose == "elem" else "field"
            return T.ProductT(tuple(self.draw(inner, depth - 1) if purpose != "elem" else self.scalar("elem")
                                    for _ in range(rng.randint(2, 3))))
        if form in ("set", "seq"):
            element = self.draw("elem", depth - 1)
            return T.SetT(element) if form == "set" else T.SeqT(element)
        element = rng.choice(NUMBERS)
        if form == "vector":
            return T.VectorT(element, rng.randint(1, 3))
        if form == "matrix":  # (a matrix literal has two rows or more: one row is a vector)
            return T.MatrixT(element, rng.randint(2, 3), rng.randint(2, 3))
        return T.FunctionT(rng.choice(SCALARS), rng.choice(SCALARS))


def port_safe(t: T.Type) -> bool:
    """Can values of ``t`` cross the FMU boundary (an event's payload, a platform operation's
    argument)?"""
    if isinstance(t, T.FunctionT):
        return False
    if is_collection(t):
        e = t.element  # type: ignore[attr-defined]
        return not is_tagged(e) and not holds(e, lambda x: is_collection(x) or isinstance(x, (T.VectorT, T.MatrixT))
                                                 or x == T.STRING or is_tagged(x)) and port_safe(e)
    if isinstance(t, T.RecordT):
        return all(port_safe(ft) for _, ft in t.fields)
    if isinstance(t, T.ProductT):
        return all(port_safe(x) for x in t.items)
    return True


__all__ = ["TypeEnv", "type_ast", "port_safe", "is_tagged", "holds", "is_collection", "parts", "is_struct", "name", "ref", "NUMBERS", "SCALARS"]
