"""Type checking of function calls and of functions used as values (a part of
:class:`~robogen.semantics.exprs.ExprChecker`).

What a call ``f(args)`` calls, as RoboTool resolves it (``RoboChartScopeProvider``,
``RoboCalcTypeProvider.typeFor(CallExp)``):

- a name: an enumeration literal of the file (a constructor, ``EM3(1)``), else a variable or
  parameter (a function value), else a function visible from the file: the model's own, a
  toolkit function, or one of robogen's extensions (:mod:`robogen.semantics.toolkit`);
- any other expression whose type is a function: a lambda, a parenthesised expression, a cast
  (``(override(f, g) as nat -> nat)(0)``), RoboSim's ``$f`` of a function-typed variable. A
  function whose domain is a product takes one argument per component; another takes one
  argument. ``$op(args)`` of an operation is a statement, not an expression.

Generic functions are typed by unifying their type variables with the arguments' types.
A named function used as a value has a product domain even for one parameter (RoboTool's
rule); a function without parameters stands for its result.
"""

from __future__ import annotations

from robogen.diagnostics import Note
from robogen.semantics import types as T
from robogen.semantics.model import EnumLitSym, FuncSym
from robogen.semantics.toolkit import EXTENSIONS, Builtin, Extension, extension_warning
from robogen.syntax import ast


class Calls:
    """The call rules of :class:`~robogen.semantics.exprs.ExprChecker` (a mixin)."""

    def _e_Call(self, e: ast.Call) -> T.Type:
        arg_types = [self.expr(a) for a in e.args]
        f = e.func
        if isinstance(f, ast.Name):
            t = self._call_named(e, f, arg_types)
            if t is not None:
                return t
        if isinstance(f, ast.Dollar) and f.name in self.scope.ops and self._dollar_variable(f.name) is None:
            return self._operation_in_expression(f.name, f)
        return self._call_value(e, self.expr(f), arg_types)

    def _operation_in_expression(self, name: str, f: ast.Expr) -> T.Type:
        return self._err(f"'{name}' is an operation; operations are called as statements, not in expressions", f)

    def _call_named(self, e: ast.Call, f: ast.Name, arg_types: list[T.Type]) -> T.Type | None:
        """The type of a call of a name; None when the name is a variable (a function value)."""
        lit = self.literal_named(f)
        if lit is not None:
            self.tables.refs[id(f)] = lit
            params = tuple((f"{i + 1}", t) for i, t in enumerate(literal_args(lit)))
            self._check_args(f"enumeration literal '{f.text}'", params, e.args, arg_types, e)
            return lit.enum
        if not f.qualified:
            if f.last in self.scope.ops:
                return self._operation_in_expression(f.last, f)
            if self.lookup_var(f.last) is not None:
                return None
        decl = self.lookup_global(f, self.scope.file, (ast.FunctionDef,), "function", False)
        extension = EXTENSIONS.get(f.last) if not f.qualified else None
        if extension is not None and len(arg_types) == extension.arity and (decl is None or not _takes(decl, len(arg_types))):
            return self._extension_call(extension, e, f, arg_types)
        decl = self.lookup_global(f, self.scope.file, (ast.FunctionDef,), "function", True)
        if decl is None:
            return T.UNKNOWN
        if decl.builtin is not None:
            return self._builtin_call(decl.builtin, e, f, arg_types)
        fdef: ast.FunctionDef = decl.node  # type: ignore[assignment]
        params, result = self.function_signature(fdef, decl.file or self.scope.file)
        self.tables.refs[id(f)] = FuncSym(f.last, params, result, fdef, None, decl.qname)
        bindings: dict[str, T.Type] = {}
        self._check_args(f"function '{f.last}'", params, e.args, arg_types, e, bindings)
        return T.instantiate(result, bindings)

    def function_signature(self, fdef: ast.FunctionDef, file: ast.File) -> tuple[tuple[tuple[str, T.Type], ...], T.Type]:
        params = tuple((p.name, self.resolve_type(p.type, file)) for p in fdef.params)
        return params, self.resolve_type(fdef.result, file)

    def _call_value(self, e: ast.Call, callee: T.Type, arg_types: list[T.Type]) -> T.Type:
        """A call of a function value: a variable, a lambda, a cast, a parenthesised expression."""
        if isinstance(callee, (T.UnknownT, T.TypeVarT)):
            return T.UNKNOWN
        if not isinstance(callee, T.FunctionT) or callee.relation:
            return self._err(f"only a function can be called, and this is {callee.show()}", e.func)
        domain = T.single(callee.domain)
        items = domain.items if isinstance(domain, T.ProductT) else (domain,)
        params = tuple((f"{i + 1}", t) for i, t in enumerate(items))
        bindings: dict[str, T.Type] = {}
        self._check_args(f"this function of type {callee.show()}", params, e.args, arg_types, e, bindings)
        return T.instantiate(callee.range, bindings)

    def _check_args(self, what: str, params, args, arg_types, node, bindings: dict[str, T.Type] | None = None) -> None:
        if len(args) != len(params):
            self._err(f"{what} takes {plural(len(params), 'argument')}, but {len(args)} {'were' if len(args) != 1 else 'was'} given", node)
            return
        bindings = {} if bindings is None else bindings
        for (pname, ptype), a, at in zip(params, args, arg_types):
            if not T.unify(ptype, at, bindings):
                which = f"argument {pname}" if pname.isdigit() else f"argument '{pname}'"
                self._err(f"{which} of {what} must be {T.instantiate(ptype, bindings).show()}, but this is {at.show()}", a)

    def _builtin_call(self, b: Builtin, e: ast.Call, f: ast.Name, arg_types: list[T.Type]) -> T.Type:
        """A call of a toolkit function: its type variables bound by the arguments."""
        self.tables.refs[id(f)] = FuncSym(f.last, b.params, b.result, None, b, f"{b.package}::{b.name}")
        if len(arg_types) != len(b.params):
            return self._err(f"'{b.name}' takes {len(b.params)} argument(s), not {len(arg_types)}", e, Note(b.doc))
        bindings: dict[str, T.Type] = {}
        for (pname, ptype), at in zip(b.params, arg_types):
            if not T.unify(ptype, at, bindings):
                wanted = T.instantiate(ptype, bindings)
                if T.same_form(wanted, at):
                    message = f"argument '{pname}' of '{b.name}' must be {wanted.show()}, but this is {at.show()}"
                else:
                    message = f"'{b.name}' expects {_forms(b, wanted)}, not {at.show()}"
                return self._err(message, e, Note(b.doc))
        return T.instantiate(b.result, bindings)

    def _extension_call(self, ext: Extension, e: ast.Call, f: ast.Name, arg_types: list[T.Type]) -> T.Type:
        """A call of a robogen extension (abs, min and max of numbers): allowed, with a warning."""
        self.sink.warning(extension_warning(ext), f.span, Note(ext.doc))
        self.tables.refs[id(f)] = FuncSym(f.last, (), T.UNKNOWN, None, ext, f"robogen::{ext.name}")
        result = ext.rule(arg_types)
        if isinstance(result, str):
            return self._err(result, e, Note(ext.doc))
        return result

    def function_value(self, e: ast.Name) -> T.Type | None:
        """The type of a name that denotes a function, used as a value; None if it does not."""
        decl = self.lookup_global(e, self.scope.file, (ast.FunctionDef,), "function", False)
        if decl is None:
            return None
        decl = self.lookup_global(e, self.scope.file, (ast.FunctionDef,), "function", True)  # its warnings, if any
        if decl.builtin is not None:
            b = decl.builtin
            self.tables.refs[id(e)] = FuncSym(e.last, b.params, b.result, None, b, decl.qname)
            return b.value_type
        fdef: ast.FunctionDef = decl.node  # type: ignore[assignment]
        params, result = self.function_signature(fdef, decl.file or self.scope.file)
        self.tables.refs[id(e)] = FuncSym(e.last, params, result, fdef, None, decl.qname)
        return T.FunctionT(T.ProductT(tuple(t for _, t in params)), result) if params else result


def _takes(decl, n: int) -> bool:
    """Does a function declaration take ``n`` arguments?"""
    if decl.builtin is not None:
        return len(decl.builtin.params) == n
    return len(decl.node.params) == n


def _forms(b: Builtin, wanted: T.Type) -> str:
    """How a message names what a toolkit function expects: "sets" when every parameter is a
    set, else the form of the parameter that did not fit."""
    forms = {type(T.single(t)) for _, t in b.params}
    if len(b.params) > 1 and len(forms) == 1:
        return T.form(wanted, plural=True)
    return T.form(wanted)


def literal_args(lit: EnumLitSym) -> tuple[T.Type, ...]:
    enum = lit.enum
    if not isinstance(enum, T.EnumT) or not enum.literal_args:
        return ()
    return enum.literal_args[enum.literals.index(lit.literal)]


def plural(n: int, word: str) -> str:
    return f"{n} {word}{'' if n == 1 else 's'}"


__all__ = ["Calls", "literal_args", "plural"]
