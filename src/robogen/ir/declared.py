"""Lowering of calls of the functions a model declares (``function f(..): R { precondition ..
postcondition .. }``; RoboChart gives them no body).

- **Defined by its contract.** Where a postcondition pins the result (``result == e``,
  ``e == result``, ``result iff e``, alone or as a conjunct ``... /\\ result == e``, ``e`` not
  reading ``result``), a call is ``e`` with each parameter standing for its argument, inlined at
  the call as a lambda's body is (:mod:`robogen.ir.functions`): the C and the reference
  interpreter compute it, no ``--functions`` file is needed. A function whose result no
  postcondition pins is the user's: the code generator takes its C body from ``--functions``
  (``rg_user_<name>``), the interpreter a Python implementation.
- **Preconditions.** A call of a function with preconditions evaluates them on the arguments
  first; where one does not hold, the call is the located run-time error "function 'f' called
  outside its precondition ..." (fmi3Error) instead of a value. A precondition code generation
  cannot evaluate is not checked, with a warning.
- **Generic functions** (type variables ``?X``) are instantiated per call from the types of its
  arguments, as C++ instantiates templates (monomorphisation): the body of a defined one is
  lowered with ``?X`` standing for its type; a user one gets a C function per instantiation,
  ``rg_user_<name>__<type of ?X>__<type of ?Y>...`` (:func:`type_word`), each named in the
  error that asks for its definition. A call whose type variables its arguments do not decide
  (an empty ``{}``, a variable only in the result) is a located error.
- **Recursion** (a defined function that calls itself, directly or through others) would inline
  without end: a located not-supported error.
"""

from __future__ import annotations

from robogen.diagnostics import RobogenError
from robogen.ir import model as ir
from robogen.ir.region_tree import Graph
from robogen.ir.supported import TupleT, check_codegen_type, holds_function, holds_string, is_scalar, not_supported
from robogen.semantics import types as T
from robogen.semantics.model import FuncSym
from robogen.syntax import ast
from robogen.syntax.printer import expr as expr_text


def pinned_result(fdef: ast.FunctionDef) -> ast.Expr | None:
    """The expression a postcondition of ``fdef`` pins the result to (None: none does)."""
    for m in fdef.members:
        if not isinstance(m, ast.Postcondition):
            continue
        first, links = ast.chain(m.expr, ("/\\",))
        for c in [first] + [link.right for link in links]:
            if isinstance(c, ast.Binary) and c.op in ("==", "iff"):
                if _is_result(c.left) and not _reads_result(c.right):
                    return c.right
                if _is_result(c.right) and not _reads_result(c.left):
                    return c.left
    return None


def _is_result(e: ast.Expr) -> bool:
    return isinstance(e, ast.Keyword) and e.word == "result"


def _reads_result(node) -> bool:
    if _is_result(node):
        return True
    for name in getattr(node, "__dataclass_fields__", {}):
        child = getattr(node, name)
        for c in child if isinstance(child, tuple) else (child,):
            if isinstance(c, ast.Node) and _reads_result(c):
                return True
    return False


def type_word(t: T.Type) -> str:
    """A C identifier part naming type ``t`` (normalised), a prefix code: ``nat``, ``Set_int``,
    ``tup2_nat_real`` (a product of two), ``pkg_Rec`` (a record or enumeration by its qualified
    name), ``vec_real_3``, ``fun_nat_int``."""
    if isinstance(t, TupleT):
        return f"tup{len(t.fields)}_" + "_".join(type_word(ft) for _, ft in t.fields)
    if isinstance(t, T.Prim):
        return t.name
    if isinstance(t, (T.RecordT, T.EnumT)):
        return "".join(ch if ch.isalnum() or ch == "_" else "_" for ch in t.qname.replace("::", "_"))
    if isinstance(t, (T.SetT, T.SeqT)):
        return f"{'Set' if isinstance(t, T.SetT) else 'Seq'}_{type_word(t.element)}"
    if isinstance(t, T.VectorT):
        return f"vec_{type_word(t.element)}_{t.size}"
    if isinstance(t, T.MatrixT):
        return f"mat_{type_word(t.element)}_{t.rows}_{t.columns}"
    if isinstance(t, T.FunctionT):
        return f"fun_{type_word(t.domain)}_{type_word(t.range)}"
    return "unknown"


def type_variables(types) -> list[str]:
    """The names of the type variables in ``types``, in order of first appearance."""
    found: list[str] = []

    def walk(t: T.Type) -> None:
        if isinstance(t, T.TypeVarT):
            if t.name not in found:
                found.append(t.name)
        for inner in (getattr(t, "element", None), getattr(t, "domain", None), getattr(t, "range", None)):
            if isinstance(inner, T.Type):
                walk(inner)
        for item in getattr(t, "items", ()):
            walk(item)

    for t in types:
        walk(t)
    return found


class DeclaredFunctions:
    """The steps of :class:`~robogen.ir.machines.MachineLowering` for calls of the model's
    functions (a mixin; see the module documentation)."""

    # -- entry

    def declared_call(self, sym: FuncSym, args: list[ir.Expr], e: ast.Expr, graph: Graph, arg_nodes=None) -> ir.Expr:
        """The call of the model's function ``sym`` on the lowered ``args`` (``arg_nodes``: the
        arguments as the model writes them, whose checked types decide the type variables)."""
        fdef = sym.decl
        assert fdef is not None
        bindings = self._instance(sym, args, e, arg_nodes)
        outer, self.tvars = self.tvars, bindings
        try:
            params = tuple((n, self._norm(t)) for n, t in sym.params)
            result = self._norm(sym.result)
            args = [self.conv(a, pt, e.span) for a, (_, pt) in zip(args, params)]
            body = pinned_result(fdef)
            if body is None:
                value = self._user_value(sym, args, params, result, e, bindings)
            else:
                value = self._inlined(fdef, sym.name, body, args, result, e, graph)
            return self._checked(fdef, sym.name, args, value, e, graph)
        finally:
            self.tvars = outer

    def _instance(self, sym: FuncSym, args: list[ir.Expr], e: ast.Expr, arg_nodes) -> dict[str, T.Type]:
        """The types of the type variables of ``sym`` at this call, from its arguments' types."""
        names = type_variables([t for _, t in sym.params] + [sym.result])
        if not names:
            return {}
        bindings: dict[str, T.Type] = {}
        nodes = arg_nodes if arg_nodes is not None else [None] * len(args)
        for (_, pt), a, node in zip(sym.params, args, nodes):
            at = T.instantiate(self.model.type_of(node), self.tvars) if node is not None else a.type
            T.unify(pt, at, bindings)
        for name in names:
            bound = bindings.get(name)
            if bound is None or _undecided(bound):
                raise RobogenError.at(
                    f"the type ?{name} of function '{sym.name}' cannot be inferred at this call: its arguments do not "
                    f"decide it (give an empty collection its type, e.g. '{{}} as Set(nat)')", e.span)
            bindings[name] = self._norm(bound)
        return bindings

    # -- the two kinds of body

    def _inlined(self, fdef: ast.FunctionDef, name: str, body: ast.Expr, args: list[ir.Expr], result: T.Type,
                 e: ast.Expr, graph: Graph) -> ir.Expr:
        """The pinned result ``body`` with the parameters standing for ``args``."""
        if any(d is fdef for d, _ in self.inlining):
            path = " -> ".join([n for _, n in self.inlining] + [name])
            raise not_supported(f"recursion between functions defined by their postcondition ({path})", e.span)
        self.inlining.append((fdef, name))
        try:
            return self.conv(self._in_body(fdef, args, lambda: self.expr(body, graph)), result, e.span)
        finally:
            self.inlining.pop()

    def _in_body(self, fdef: ast.FunctionDef, args: list[ir.Expr], lower):
        """``lower()`` with the parameters of ``fdef`` standing for ``args`` (and no other name)."""
        saved = self.bound
        self.bound = {id(p): a for p, a in zip(fdef.params, args)}
        try:
            return lower()
        finally:
            self.bound = saved

    def _user_value(self, sym: FuncSym, args: list[ir.Expr], params, result: T.Type, e: ast.Expr,
                    bindings: dict[str, T.Type]) -> ir.Expr:
        """The call of the user's C function of this instantiation. Its parameters and result
        are numbers, booleans, enumerations, strings (parameters only), records, tuples, sets or
        sequences (the C file receives and returns the C types of config.h)."""
        if holds_string(result):  # RoboChart builds no string: every string is one the FMU knows
            raise not_supported(f"function '{sym.name}': a result of type {result.show()} (the FMU holds the model's "
                                "strings and those the importer sets, not a text a C function makes)", e.span)
        for k, (n, t) in enumerate(params + (("result", result),)):
            what = f"parameter {n}" if k < len(params) else "result"
            if not is_scalar(t) and t != T.STRING:
                if holds_function(t):
                    raise not_supported(f"function '{sym.name}': {what} of type {t.show()} (a function value's default "
                                        "is robogen's numbering of the model's lambdas, which the user's C cannot apply)", e.span)
                check_codegen_type(t, e.span, f"function '{sym.name}': {what}")
        names = type_variables([t for _, t in sym.params] + [sym.result])
        instance = "__".join([sym.name] + [type_word(bindings[n]) for n in names])
        shown = ", ".join(f"?{n} = {bindings[n].show()}" for n in names)
        self.user_function(sym, e, params, result, instance, shown)
        return ir.CallU(result, sym.name, tuple(args), instance if names else "")

    def _checked(self, fdef: ast.FunctionDef, name: str, args: list[ir.Expr], value: ir.Expr, e: ast.Expr,
                 graph: Graph) -> ir.Expr:
        """``value`` where the preconditions of ``fdef`` hold of ``args``, else a located run-time
        error (a precondition code generation cannot evaluate is not checked: a warning)."""
        pres = [m.expr for m in fdef.members if isinstance(m, ast.Precondition)]
        if not pres:
            return value
        tests = []
        for p in pres:
            try:
                tests.append(self._in_body(fdef, args, lambda p=p: self.expr(p, graph)))
            except RobogenError as why:
                self.ctx.sink.warning(f"the precondition {expr_text(p)} of function '{name}' is not checked at run time: "
                                      f"{why.diagnostics[0].message}", p.span)
        if not tests:
            return value
        test = tests[0]
        for t in tests[1:]:
            test = ir.Bin(T.BOOLEAN, "and", test, t)
        text = " /\\ ".join(expr_text(p) for p in pres)
        fault = ir.Coll(value.type, "undefined", (), f"function '{name}' called outside its precondition {text}", e.span)
        return ir.Cond(value.type, test, value, fault)


def _undecided(t: T.Type) -> bool:
    """Does ``t`` hold a part that no argument decided (a type variable, or an empty collection's
    unknown element)?"""
    if isinstance(t, (T.UnknownT, T.TypeVarT)):
        return True
    inner = [getattr(t, a, None) for a in ("element", "domain", "range")] + list(getattr(t, "items", ()))
    inner += [ft for _, ft in getattr(t, "fields", ())] if isinstance(t, TupleT) else []
    return any(isinstance(x, T.Type) and _undecided(x) for x in inner)


__all__ = ["DeclaredFunctions", "pinned_result", "type_word", "type_variables"]
