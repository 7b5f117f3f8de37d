"""Resolution and well-formedness checks of a whole workspace: the RoboChart and RoboSim
reference manuals' well-formedness conditions, as RoboTool's validators implement them.

:func:`check` takes a :class:`~robogen.semantics.workspace.Workspace` and returns the frozen
:class:`~robogen.semantics.model.SemanticModel`: every diagnostic found (all of them: problems
are collected, not raised one by one), the scope of every state machine and operation, the
containers with their parts, and the tables with the type of every expression and the symbol of
every name. The :class:`Checker` and its working records stay behind.

The checks run in three passes: every declaration (scopes are built as machines are met); then
the containers are assembled, which needs every machine's scope (periods, events); then the
connections of the assembled containers.
"""

from __future__ import annotations

import dataclasses
from fractions import Fraction
from typing import Iterable

from robogen.diagnostics import Note, Span, did_you_mean, working_on
from robogen.semantics import connections
from robogen.semantics import types as T
from robogen.semantics.assemble import ControllerParts, ModuleParts, assemble_controller, assemble_module
from robogen.semantics.exprs import Where
from robogen.semantics.machine_analysis import analyse_machine
from robogen.semantics.model import Controller, EnumLitSym, MachineScope, Module, Region, SemanticModel, Tables, VarSym
from robogen.semantics.periods import cycle_period, frac
from robogen.semantics.scope import ScopeBuilder
from robogen.semantics.stmts import StmtChecker
from robogen.semantics.workspace import TYPE_DECLS, Decl, Workspace
from robogen.syntax import ast
from robogen.syntax.parser import without_gc


def check(workspace: Workspace) -> SemanticModel:
    """Check ``workspace`` and return what it means (see the module documentation)."""
    checker = Checker(workspace)
    with without_gc():
        checker.run()
        controllers, modules = checker.assemble()
        # the connection checks read the model as later stages do (which operation a call runs)
        model = SemanticModel(
            files=tuple(workspace.files),
            root=workspace.root,
            diagnostics=(),
            scopes=tuple(checker.scopes.values()),
            controllers=tuple(controllers),
            modules=tuple(modules),
            tables=checker.tables,
        )
        for c in controllers:
            connections.check_controller(c, model, workspace.sink)
        for m in modules:
            connections.check_module(m, workspace.sink)
    return dataclasses.replace(model, diagnostics=tuple(workspace.sink.sorted()))


class Checker:
    def __init__(self, ws: Workspace):
        self.ws = ws
        self.sink = ws.sink
        self.tables = Tables()
        self.scopes: dict[int, MachineScope] = {}  # id(node) -> scope of a machine or operation
        self.modules: dict[int, ModuleParts] = {}
        self.controllers: dict[int, ControllerParts] = {}
        # Caches keyed by id(node) also hold the node, so that its id cannot be reused by another
        # node while the entry exists (the checkers build temporary names and type references).
        # The resolved type expressions are the model's table (SemanticModel.type_of).
        self._type_cache = self.tables.type_exprs
        self._decl_types: dict[int, T.Type] = {}
        self.records: dict[str, T.RecordT] = {}  # qname -> record type with its fields
        self._lookups: dict[tuple[int, tuple[type, ...]], tuple[Decl | None, bool, ast.Name]] = {}
        self._file_literals: dict[int, dict[str, EnumLitSym]] = {}  # id(file) -> its enumerations' literals
        self.builder = ScopeBuilder(self.sink, self.resolve_type, self.resolve_interface, self.resolve_operation)

    # ------------------------------------------------------------------ types and names

    def lookup(self, name: ast.Name, file: ast.File, kinds: tuple[type, ...], what: str, report: bool = True) -> Decl | None:
        """Global lookup, memoised per name occurrence so that each problem is reported once."""
        key = (id(name), kinds)
        entry = self._lookups.get(key)
        if entry is not None:
            found, reported, _ = entry
            if reported or not report:
                return found
        found = self.ws.lookup(name, file, kinds, what, report)
        self._lookups[key] = (found, report, name)
        return found

    def resolve_type(self, t: ast.TypeExpr | None, file: ast.File) -> T.Type:
        if t is None:
            return T.UNKNOWN
        cached = self._type_cache.get(id(t))
        if cached is not None:
            return cached[1]
        result = self._resolve_type(t, file)
        self._type_cache[id(t)] = (t, result)
        return result

    def _resolve_type(self, t: ast.TypeExpr, file: ast.File) -> T.Type:
        if isinstance(t, ast.TypeRef):
            decl = self.lookup(t.name, file, TYPE_DECLS, "type")
            if decl is None:
                return T.UNKNOWN
            return self.decl_type(decl)
        if isinstance(t, ast.SetType):
            return T.SetT(self.resolve_type(t.element, file))
        if isinstance(t, ast.SeqType):
            return T.SeqT(self.resolve_type(t.element, file))
        if isinstance(t, ast.ProductType):
            return T.ProductT(tuple(self.resolve_type(x, file) for x in t.items))
        if isinstance(t, ast.FunctionType):
            return T.FunctionT(self.resolve_type(t.domain, file), self.resolve_type(t.range, file))
        if isinstance(t, ast.RelationType):
            return T.FunctionT(self.resolve_type(t.domain, file), self.resolve_type(t.range, file), relation=True)
        if isinstance(t, ast.TypeVar_):
            return T.TypeVarT(t.name)
        if isinstance(t, ast.VectorType):
            return T.VectorT(self.resolve_type(t.element, file), self._size(t.size, file))
        if isinstance(t, ast.MatrixType):
            return T.MatrixT(self.resolve_type(t.element, file), self._size(t.rows, file), self._size(t.columns, file))
        return T.UNKNOWN  # pragma: no cover

    def _size(self, e: ast.Expr, file: ast.File) -> int | None:
        if isinstance(e, ast.IntLit):
            if e.value <= 0:
                self.sink.error("a vector or matrix size must be positive", e.span)
            return e.value
        # a constant name: its value is a model parameter, unknown here
        return None

    def decl_type(self, decl: Decl) -> T.Type:
        if decl.primitive is not None:
            return T.PRIMITIVES[decl.primitive]
        node = decl.node
        cached = self._decl_types.get(id(node))
        if cached is not None:
            return cached
        if isinstance(node, ast.GivenType):
            result: T.Type = T.Given(decl.qname)
        elif isinstance(node, ast.Enumeration):
            literals = tuple(lit.name for lit in node.literals)
            self._decl_types[id(node)] = T.EnumT(decl.qname, literals)  # breaks recursion: E { a(E) }
            result = T.EnumT(
                decl.qname,
                literals,
                tuple(tuple(self.resolve_type(a, decl.file) for a in lit.args) for lit in node.literals),  # type: ignore[arg-type]
            )
        elif isinstance(node, ast.Record):
            self._decl_types[id(node)] = T.RecordT(decl.qname, ())  # breaks recursion (see ExprChecker._record)
            result = T.RecordT(decl.qname, tuple((f.name, self.resolve_type(f.type, decl.file)) for f in node.fields))  # type: ignore[arg-type]
            self.records[decl.qname] = result
        else:  # pragma: no cover
            result = T.UNKNOWN
        self._decl_types[id(node)] = result
        if isinstance(result, (T.EnumT, T.RecordT)):
            self.tables.declared[decl.qname] = result
        return result

    def file_literals(self, f: ast.File) -> dict[str, EnumLitSym]:
        """The literals of the enumerations a file declares, by simple name: RoboTool's
        innermost scope for names in expressions (``VA``, ``EM3(1)`` without ``E::``)."""
        found = self._file_literals.get(id(f))
        if found is None:
            found = {}
            package = f.package.text if f.package else None
            for item in f.items:
                if isinstance(item, ast.Enumeration):
                    enum = self.decl_type(Decl(item.name, package, item, f))
                    for lit in item.literals:
                        found.setdefault(lit.name, EnumLitSym(enum, lit.name))
            self._file_literals[id(f)] = found
        return found

    def resolve_interface(self, name: ast.Name, file: ast.File) -> tuple[ast.Interface, ast.File] | None:
        decl = self.lookup(name, file, (ast.Interface,), "interface")
        if decl is None or decl.file is None:
            return None
        return decl.node, decl.file  # type: ignore[return-value]

    def resolve_operation(self, name: str, file: ast.File) -> ast.OperationDef | None:
        """The software operation definition ``name`` denotes where ``file`` can see it, without
        reporting anything (an operation without one belongs to the robotic platform)."""
        decl = self.ws.lookup(ast.Name((name,)), file, (ast.OperationDef,), "operation", report=False)
        return decl.node if decl is not None else None  # type: ignore[return-value]

    # ------------------------------------------------------------------ driver

    def run(self) -> None:
        for f in self.ws.files:
            if not f.items and not f.imports and f.package is None:
                self.sink.warning("the file is empty: it declares nothing", Span.point(f.path))
            for item in f.items:
                with working_on(getattr(item, "span", None)):
                    self.item(item, f)

    def assemble(self) -> tuple[list[Controller], list[Module]]:
        """The frozen controllers and modules (after run: they need every machine's scope)."""
        controllers: dict[int, Controller] = {}
        for key, parts in self.controllers.items():
            with working_on(parts.node.span):
                controllers[key] = assemble_controller(parts, self.scopes, self.builder)
        modules = []
        for parts in self.modules.values():
            with working_on(parts.node.span):
                modules.append(assemble_module(parts, controllers, self.builder))
        return list(controllers.values()), modules

    def qname(self, f: ast.File, name: str) -> str:
        return f"{f.package.text}::{name}" if f.package else name

    def item(self, item: ast.Node, f: ast.File) -> None:
        if isinstance(item, ast.Interface):
            self.interface(item, f)
        elif isinstance(item, ast.Platform):
            self.platform(item, f)
        elif isinstance(item, ast.Record):
            self.record(item, f)
        elif isinstance(item, ast.Enumeration):
            self.enumeration(item, f)
        elif isinstance(item, ast.Controller):
            self.controller(item, f)
        elif isinstance(item, (ast.StateMachine, ast.OperationDef)):
            self.machine(item, f)
        elif isinstance(item, ast.FunctionDef):
            self.function(item, f)
        elif isinstance(item, ast.Module):
            self.module(item, f)

    # ------------------------------------------------------------------ simple declarations

    def record(self, r: ast.Record, f: ast.File) -> None:
        if not r.fields:
            self.sink.error(f"datatype '{r.name}' has no fields", r.name_span, Note("a datatype declares at least one field, e.g. 'x: real'"))
        seen: dict[str, ast.FieldDecl] = {}
        qname = self.qname(f, r.name)
        for fd in r.fields:
            if fd.name in seen:
                self.sink.error(f"field '{fd.name}' is declared twice in datatype '{r.name}'", fd.name_span, Note("first declared here", seen[fd.name].name_span))
            seen[fd.name] = fd
            if self._contains(self.resolve_type(fd.type, f), qname, set()):
                self.sink.error(
                    f"datatype '{r.name}' contains itself through field '{fd.name}': its values would be infinite",
                    fd.name_span,
                    Note("a datatype may refer to itself inside a set or a sequence, e.g. 'kids: Seq(R)'"),
                )

    def _contains(self, t: T.Type, qname: str, seen: set[str]) -> bool:
        """Does every value of type ``t`` hold a value of record ``qname`` (outside sets,
        sequences, functions and enumerations, which can be empty or finite)?"""
        if isinstance(t, T.RecordT):
            if t.qname == qname:
                return True
            if t.qname in seen:
                return False
            seen.add(t.qname)
            full = self.records.get(t.qname, t)
            return any(self._contains(ft, qname, seen) for _, ft in full.fields)
        if isinstance(t, T.ProductT):
            return any(self._contains(x, qname, seen) for x in t.items)
        if isinstance(t, (T.VectorT, T.MatrixT)):
            return self._contains(t.element, qname, seen)
        return False

    def enumeration(self, e: ast.Enumeration, f: ast.File) -> None:
        seen: dict[str, ast.EnumLiteral] = {}
        for lit in e.literals:
            if lit.name in seen:
                self.sink.error(f"literal '{lit.name}' is declared twice in enumeration '{e.name}'", lit.name_span, Note("first declared here", seen[lit.name].name_span))
            seen[lit.name] = lit
            for a in lit.args:
                self.resolve_type(a, f)

    def function(self, fn: ast.FunctionDef, f: ast.File) -> None:
        self._params(fn.params, f, f"function '{fn.name}'")
        result = self.resolve_type(fn.result, f)
        params = {p.name: VarSym(p.name, self.resolve_type(p.type, f), "param", p, f"function '{fn.name}'") for p in fn.params}
        scope = MachineScope(fn, f, self.qname(f, fn.name), vars=params)
        checker = self._expr_checker(scope)
        for m in fn.members:
            if isinstance(m, (ast.Precondition, ast.Postcondition)):
                checker.result_type = result if isinstance(m, ast.Postcondition) else None
                t = checker.value(m.expr, Where(pre=True))
                if not T.is_boolean(t):
                    self.sink.error(f"a {'pre' if isinstance(m, ast.Precondition) else 'post'}condition must be boolean, not {t.show()}", m.expr.span)

    def _params(self, params: Iterable[ast.Param], f: ast.File, owner: str) -> None:
        seen: dict[str, ast.Param] = {}
        for p in params:
            if p.name in seen:
                self.sink.error(f"parameter '{p.name}' is declared twice in {owner}", p.name_span, Note("first declared here", seen[p.name].name_span))
            seen[p.name] = p
            self.resolve_type(p.type, f)

    def interface(self, i: ast.Interface, f: ast.File) -> None:
        names: dict[str, ast.Node] = {}
        has_events = has_ops = False
        scope = MachineScope(i, f, self.qname(f, i.name))  # type: ignore[arg-type]
        checker = self._expr_checker(scope)
        for m in i.members:
            for name, span in _member_names(m):
                if name in names:
                    self.sink.error(f"'{name}' is declared twice in interface '{i.name}'", span, Note("first declared here", _first_span(names[name], name)))
                else:
                    names[name] = m
            if isinstance(m, ast.EventDecl):
                has_events = True
                self.resolve_type(m.type, f)
                if m.broadcast and f.language == "robosim":
                    self.sink.error("RoboSim has no broadcast events", m.span)
            elif isinstance(m, ast.OpSig):
                has_ops = True
                self._params(m.params, f, f"operation '{m.name}'")
            elif isinstance(m, ast.VarList):
                self._var_list(m, f, checker)
        if has_events and has_ops:
            self.sink.error(
                f"interface '{i.name}' declares both events and operations",
                i.name_span,
                Note("an interface holds variables plus either events or operations (rule I2)"),
            )

    def _var_list(self, vl: ast.VarList, f: ast.File, checker: StmtChecker) -> None:
        for v in vl.vars:
            t = self.resolve_type(v.type, f)
            if v.init is not None:
                vt = checker.value(v.init, Where(init=True))
                if not T.assignable(vt, t):
                    self.sink.error(f"the initial value of '{v.name}' must be {t.show()}, but this is {vt.show()}", v.init.span)

    def platform(self, p: ast.Platform, f: ast.File) -> None:
        names: dict[str, ast.Node] = {}
        scope = MachineScope(p, f, self.qname(f, p.name))  # type: ignore[arg-type]
        checker = self._expr_checker(scope)
        for m in p.members:
            for name, span in _member_names(m):
                if name in names:
                    self.sink.error(f"'{name}' is declared twice in robotic platform '{p.name}'", span, Note("first declared here", _first_span(names[name], name)))
                else:
                    names[name] = m
            if isinstance(m, ast.InterfaceRef):
                if m.kind == "requires":
                    self.sink.error("a robotic platform requires no interface", m.span, Note("platforms 'provide' operations and variables and 'use' events"))
                self.resolve_interface(m.name, f)
            elif isinstance(m, ast.ClockDecl):
                self.sink.error("a robotic platform declares no clocks", m.span)
            elif isinstance(m, ast.EventDecl):
                self.resolve_type(m.type, f)
            elif isinstance(m, ast.OpSig):
                self._params(m.params, f, f"operation '{m.name}'")
            elif isinstance(m, ast.VarList):
                self._var_list(m, f, checker)

    # ------------------------------------------------------------------ controllers and modules

    def controller(self, c: ast.Controller, f: ast.File) -> None:
        info = ControllerParts(c, f, self.qname(f, c.name))
        self.controllers[id(c)] = info
        names: dict[str, ast.Node] = {}
        for m in c.members:
            if isinstance(m, ast.InterfaceRef):
                self.resolve_interface(m.name, f)
            elif isinstance(m, ast.Reference):
                if m.name in names:
                    self.sink.error(f"'{m.name}' is declared twice in controller '{c.name}'", m.name_span, Note("first declared here", _first_span(names[m.name], m.name)))
                names[m.name] = m
                if m.kind == "sref":
                    d = self.lookup(m.target, f, (ast.StateMachine,), "state machine")
                    if d is not None:
                        info.machines.append((m.name, d.node))  # type: ignore[arg-type]
                elif m.kind == "opref":
                    d = self.lookup(m.target, f, (ast.OperationDef,), "operation")
                    if d is not None:
                        info.operations.append((m.name, d.node))  # type: ignore[arg-type]
                else:
                    self.sink.error(f"'{m.kind}' is not allowed in a controller", m.span, Note("a controller references state machines (sref) and operations (opref)"))
            elif isinstance(m, ast.StateMachine):
                if m.name in names:
                    self.sink.error(f"'{m.name}' is declared twice in controller '{c.name}'", m.name_span)
                names[m.name] = m
                self.machine(m, f)
                info.machines.append((m.name, m))
            elif isinstance(m, ast.OperationDef):
                self.machine(m, f)
                info.operations.append((m.name, m))
            elif isinstance(m, ast.OpSig):
                self.sink.error(
                    f"a controller declares no operation signatures: '{m.name}' belongs in an interface the controller requires or provides",
                    m.name_span,
                )
            elif isinstance(m, ast.ClockDecl):
                self.sink.error("a controller declares no clocks", m.span)
            elif isinstance(m, ast.EventDecl):
                self.resolve_type(m.type, f)
                if m.broadcast and f.language == "robosim":
                    self.sink.error("RoboSim has no broadcast events", m.span)
            elif isinstance(m, ast.VarList):
                self._var_list(m, f, self._expr_checker(MachineScope(c, f, info.qname)))  # type: ignore[arg-type]
            elif isinstance(m, ast.CycleDef):
                info.period = cycle_period(m, info.period, f"controller '{c.name}'", self.sink)
        if not any(isinstance(m, ast.StateMachine) or (isinstance(m, ast.Reference) and m.kind == "sref") for m in c.members):
            self.sink.error(f"controller '{c.name}' has no state machine", c.name_span)

    def module(self, mod: ast.Module, f: ast.File) -> None:
        info = ModuleParts(mod, f, self.qname(f, mod.name))
        self.modules[id(mod)] = info
        platforms: list[ast.Node] = []
        for m in mod.members:
            if isinstance(m, ast.Platform):
                platforms.append(m)
                self.platform(m, f)
                info.platform = (m.name, m, f)
            elif isinstance(m, ast.Reference):
                if m.kind == "rref":
                    platforms.append(m)
                    d = self.lookup(m.target, f, (ast.Platform,), "robotic platform")
                    if d is not None:
                        info.platform = (m.name, d.node, d.file)  # type: ignore[assignment]
                elif m.kind == "cref":
                    d = self.lookup(m.target, f, (ast.Controller,), "controller")
                    if d is not None:
                        info.controllers.append((m.name, d.node))  # type: ignore[arg-type]
                else:
                    self.sink.error(f"'{m.kind}' is not allowed in a module", m.span, Note("a module references a robotic platform (rref) and controllers (cref)"))
            elif isinstance(m, ast.Controller):
                self.controller(m, f)
                info.controllers.append((m.name, m))
            elif isinstance(m, ast.StateMachine):
                self.sink.error(f"state machine '{m.name}' must be inside a controller, not directly in module '{mod.name}'", m.name_span)
            elif isinstance(m, ast.CycleDef):
                info.period = cycle_period(m, info.period, f"module '{mod.name}'", self.sink)
        if not platforms:
            self.sink.error(f"module '{mod.name}' has no robotic platform", mod.name_span)
        for extra in platforms[1:]:
            self.sink.error(f"module '{mod.name}' has more than one robotic platform", getattr(extra, "name_span", None) or extra.span)
        if not any(isinstance(m, ast.Controller) or (isinstance(m, ast.Reference) and m.kind == "cref") for m in mod.members):
            self.sink.error(f"module '{mod.name}' has no controller", mod.name_span)

    # ------------------------------------------------------------------ state machines and operations

    def _expr_checker(self, scope: MachineScope) -> StmtChecker:
        return StmtChecker(scope, self.sink, self.tables, self.resolve_type, self.lookup, self.records, self.file_literals)

    def machine(self, node: ast.StateMachine | ast.OperationDef, f: ast.File) -> MachineScope:
        if id(node) in self.scopes:
            return self.scopes[id(node)]
        scope = self.builder.build(node, f, self.qname(f, node.name))
        self.scopes[id(node)] = scope
        if isinstance(node, ast.OperationDef):
            self._params(node.params, f, f"operation '{node.name}'")
        rs = scope.robosim
        checker = self._expr_checker(scope)
        for m in node.members:
            if isinstance(m, ast.OpSig):
                self.sink.error(
                    f"a {scope.kind} declares no operation signatures: '{m.name}' belongs in an interface it requires (rule STM6)",
                    m.name_span,
                )
            elif isinstance(m, ast.InterfaceRef) and rs and m.kind == "provides":
                self.sink.error("a RoboSim state machine provides no interface", m.span)
            elif isinstance(m, ast.EventDecl) and rs:
                self.sink.error(
                    f"a RoboSim {scope.kind} declares no events directly: declare '{m.name}' in its input or output context",
                    m.span,
                )
            elif isinstance(m, ast.EventDecl) and m.broadcast and rs:
                self.sink.error("RoboSim has no broadcast events", m.span)
            elif isinstance(m, ast.VarList):
                self._var_list(m, f, checker)
            elif isinstance(m, ast.CycleDef):
                if not rs:  # pragma: no cover - the RoboChart grammar has no cycleDef
                    self.sink.error("'cycleDef' is RoboSim syntax", m.span)
            elif isinstance(m, ast.Context):
                self._context(m, scope)
        assert scope.region is not None
        for region in scope.region.walk():
            self.region(region, scope, checker)
        analyse_machine(scope, self.tables, self.sink)
        return scope

    def _context(self, ctx: ast.Context, scope: MachineScope) -> None:
        for m in ctx.members:
            if isinstance(m, ast.InterfaceRef):
                found = self.resolve_interface(m.name, scope.file)
                if found is None:
                    continue
                iface, _ = found
                if ctx.kind == "input" and m.kind == "uses" and any(isinstance(x, ast.OpSig) for x in iface.members):
                    self.sink.error(
                        f"interface '{iface.name}' declares operations, but an input context uses only events",
                        m.span,
                        Note("operations the machine calls belong in its output context ('requires')"),
                    )
            elif isinstance(m, ast.EventDecl) and m.broadcast:
                self.sink.error("RoboSim has no broadcast events", m.span)

    def region(self, region: Region, scope: MachineScope, checker: StmtChecker) -> None:
        owner = region.owner
        if region.nodes or isinstance(owner, ast.StateMachine):
            self._initial_nodes(region)
        if isinstance(owner, ast.State) and not any(isinstance(n, (ast.State, ast.Final)) for n in region.nodes.values()):
            self.sink.error(f"composite state '{owner.name}' has no state or final node", owner.name_span)
        incoming: dict[str, list[ast.Transition]] = {n: [] for n in region.nodes}
        outgoing: dict[str, list[ast.Transition]] = {n: [] for n in region.nodes}
        for t in region.transitions:
            with working_on(t.span):
                self.transition(t, region, scope, checker, incoming, outgoing)
        for name, node in region.nodes.items():
            outs, ins = outgoing[name], incoming[name]
            if isinstance(node, ast.Initial):
                if len(outs) != 1:
                    self.sink.error(
                        f"initial node '{name}' must have exactly one outgoing transition, not {len(outs)}",
                        node.name_span,
                    )
                for t in ins:
                    self.sink.error(f"transition '{t.name}' enters initial node '{name}'", t.target_span or t.span)
            elif isinstance(node, ast.Final):
                for t in outs:
                    self.sink.error(f"transition '{t.name}' leaves final node '{name}'", t.source_span or t.span)
            elif isinstance(node, ast.Junction):
                if not ins:
                    self.sink.warning(f"junction '{name}' has no incoming transition", node.name_span)
                if not outs:
                    self.sink.error(f"junction '{name}' has no outgoing transition", node.name_span)
            elif isinstance(node, ast.Probabilistic):
                self._probabilistic(node, outs)
            if isinstance(node, ast.State):
                self.state(node, scope, checker)

    def _initial_nodes(self, region: Region) -> None:
        """A state machine has exactly one initial node (an error, rule STM3). An operation or a
        composite state with nodes should have one (a warning, as in RoboTool); an operation
        without nodes is abstract, defined by its contract only."""
        where = region.description
        initials = region.initials()
        report = self.sink.error if isinstance(region.owner, ast.StateMachine) else self.sink.warning
        if not initials:
            report(f"{where} has no initial node", getattr(region.owner, "name_span", None), Note("add 'initial i' and a transition from it"))
        for extra in initials[1:]:
            report(f"{where} has more than one initial node", extra.name_span, Note("first initial node", initials[0].name_span))

    def state(self, s: ast.State, scope: MachineScope, checker: StmtChecker) -> None:
        seen: dict[str, ast.StateAction] = {}
        for m in s.members:
            if isinstance(m, ast.StateAction):
                if m.kind in seen:
                    self.sink.error(f"state '{s.name}' has two {m.kind} actions", m.span, Note("first one here", seen[m.kind].span))
                seen[m.kind] = m
                checker.stmt(m.stmt)

    def _probabilistic(self, node: ast.Probabilistic, outs: list[ast.Transition]) -> None:
        total = Fraction(0)
        exact = True
        for t in outs:
            if t.probability is None:
                self.sink.error(f"transition '{t.name}' from probabilistic junction '{node.name}' needs a probability", t.name_span)
                exact = False
            else:
                p = t.probability
                if isinstance(p, ast.RealLit):
                    total += Fraction(p.text)
                elif isinstance(p, ast.IntLit):
                    total += p.value
                else:
                    exact = False
            if t.condition is not None or t.condition_else:
                self.sink.error(f"transition '{t.name}' from a probabilistic junction cannot have a condition", t.name_span)
        if exact and outs and total != 1:
            self.sink.error(f"the probabilities of the transitions from '{node.name}' sum to {frac(total)}, not 1", node.name_span)

    def transition(self, t: ast.Transition, region: Region, scope: MachineScope, checker: StmtChecker, incoming, outgoing) -> None:
        rs = scope.robosim
        src = self._node_ref(t.source, t.source_span or t.span, region, scope, t, "source")
        dst = self._node_ref(t.target, t.target_span or t.span, region, scope, t, "target")
        if src is not None:
            outgoing[t.source].append(t)
        if dst is not None:
            incoming[t.target].append(t)
        if t.trigger is not None:
            if rs:
                self.sink.error(
                    "RoboSim transitions have no trigger: test inputs in the condition ($e) and use 'exec' to wait for the next cycle",
                    t.trigger.span,
                )
            else:
                if t.trigger.kind in ("!", "."):
                    self.sink.error(
                        f"a trigger is a plain event or an input (e or e?x), not {'an output' if t.trigger.kind == '!' else 'a synchronisation'} (rule T2)",
                        t.trigger.span,
                    )
                checker.communication(t.trigger, trigger=True)
                if isinstance(src, (ast.Junction, ast.Probabilistic)):
                    self.sink.error(f"a transition from junction '{t.source}' cannot have a trigger (rule J3)", t.trigger.span)
        if isinstance(src, ast.Initial) and t.trigger is not None:  # J3; a condition and an action are allowed
            self.sink.error(f"the transition from initial node '{t.source}' can have no trigger (rule J3)", t.name_span)
        if t.exec and isinstance(src, (ast.Junction, ast.Initial)):  # J3: RoboSim's exec is a trigger
            self.sink.error(f"an exec transition leaves a state, not {type(src).__name__.lower()} '{t.source}'", t.name_span)
        for r in t.resets:
            if r.clock not in scope.clocks:
                self.sink.error(f"unknown clock '{r.clock}'" + did_you_mean(r.clock, scope.clocks), r.clock_span or r.span)
            else:
                self.tables.refs[id(r)] = scope.clocks[r.clock]
        if t.deadline is not None:
            if rs:
                self.sink.error("RoboSim has no deadlines", t.deadline.span)
            else:
                if t.trigger is None:
                    self.sink.error("a deadline '<{ d }' needs a trigger (rule TT1)", t.deadline.span)
                dt = checker.value(t.deadline, Where())
                if not T.is_numeric(dt):
                    self.sink.error(f"a deadline is a number of time units, not {dt.show()}", t.deadline.span)
        if t.probability is not None:
            if not isinstance(src, ast.Probabilistic):
                self.sink.error("only transitions from a probabilistic junction have a probability", t.probability.span)
            pt = checker.value(t.probability, Where())
            if not T.is_numeric(pt):
                self.sink.error(f"a probability is a number, not {pt.show()}", t.probability.span)
        if t.condition is not None:
            checker.condition(t.condition)
        if t.condition_else and src is not None and not isinstance(src, (ast.Junction, ast.Probabilistic)):
            self.sink.error("'condition else' is the default branch of a junction; here it leaves a state", t.name_span)
        if t.action is not None:
            checker.stmt(t.action)

    def _node_ref(self, name: str, span: Span | None, region: Region, scope: MachineScope, t: ast.Transition, role: str):
        node = region.nodes.get(name)
        if node is not None:
            return node
        elsewhere = [path for path, n in scope.all_states() if path[-1] == name]
        notes = []
        if elsewhere:
            where = "::".join(elsewhere[0][:-1]) or scope.name
            notes.append(Note(f"'{name}' is a node of '{where}'; a transition joins nodes of one container (rule T1)"))
        self.sink.error(
            f"transition '{t.name}': unknown {role} '{name}' in {region.description}" + did_you_mean(name, region.nodes),
            span,
            *notes,
        )
        return None


def _member_names(m: ast.Node):
    if isinstance(m, ast.VarList):
        return [(v.name, v.name_span) for v in m.vars]
    if isinstance(m, (ast.EventDecl, ast.OpSig, ast.ClockDecl)):
        return [(m.name, m.name_span)]
    return []


def _first_span(node: ast.Node, name: str) -> Span | None:
    for n, span in _member_names(node):
        if n == name:
            return span
    return getattr(node, "name_span", None)


__all__ = ["check", "Checker"]
