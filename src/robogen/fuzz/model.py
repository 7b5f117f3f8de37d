"""Random whole models: :func:`generate` turns a seed into one RoboChart or RoboSim file (an AST
printed by :func:`robogen.syntax.printer.file`), with what compiling and driving it needs.

A model is a lone state machine, or a module: a robotic platform, one or two controllers, and
one to three machines. Each machine receives some events from the platform and sends others
to it (asynchronous connections through its controller and the module), may send events to a
later machine of its controller (a synchronous, asynchronous or bidirectional connection; never
to an earlier one, so that no exchange between machines loops within an instant), calls
platform operations (output clocks) and software operations, and reads and writes variables its
controller provides. Everything is named by a counter (``e3``, ``S7``, ``t12``), so no name
clashes with another or with a keyword.
"""

from __future__ import annotations

import random
from dataclasses import dataclass, field

from robogen.fuzz import functions as userfns
from robogen.fuzz.exprs import Exprs, Sym, UserFn
from robogen.fuzz.machines import Machines, MachineSpec
from robogen.fuzz.stmts import OpInfo, Stmts
from robogen.fuzz.typegen import TypeEnv, name, port_safe, type_ast
from robogen.semantics import types as T
from robogen.syntax import ast, printer


@dataclass
class Generated:
    """One generated model and what compiling and driving it needs."""

    seed: str
    language: str  # robochart | robosim
    file: ast.File
    functions: tuple[UserFn, ...] = ()
    capacity: int = 8
    features: frozenset[str] = frozenset()

    @property
    def path(self) -> str:
        return self.file.path

    @property
    def c_functions(self) -> str | None:
        return userfns.c_file(self.functions)

    def py_functions(self) -> dict:
        return userfns.python(self.functions)

    def text(self) -> str:
        """The model's text: its AST printed; with the switch ``old_syntax``, in RoboTool's syntax
        before 2020-10 where it differs (a bare ``trigger`` for the empty trigger of a RoboChart
        transition), which parses to the same AST."""
        text = printer.file(self.file)
        if "old_syntax" not in self.features or self.language != "robochart":
            return text
        out, block = [], []
        for line in text.splitlines(keepends=True):
            block.append(line)
            if line.strip() == "}" and block and block[0].lstrip().startswith("transition "):
                out += _bare_trigger(block)
                block = []
            elif not line.lstrip().startswith(("transition ", "from ", "to ", "trigger", "probability", "#", "<{",
                                               "condition", "action", "exec")):
                out += block
                block = []
        return "".join(out + block)


@dataclass
class _Machine:
    spec: MachineSpec
    instance: str  # its name in the controller (sref) or its own name (inline)
    inline: bool
    node: ast.StateMachine | None = None


@dataclass
class _Controller:
    name: str
    instance: str
    inline: bool
    machines: list[_Machine] = field(default_factory=list)
    members: list[ast.Node] = field(default_factory=list)
    connections: list[ast.Connection] = field(default_factory=list)
    events: list[ast.EventDecl] = field(default_factory=list)


def _bare_trigger(block: list[str]) -> list[str]:
    """A transition's lines with ``trigger`` alone after its target, if it has no trigger."""
    if any(x.lstrip().startswith(("trigger", "probability", "exec")) for x in block):
        return block
    at = next(i for i, x in enumerate(block) if x.lstrip().startswith("to "))
    indent = block[at][: len(block[at]) - len(block[at].lstrip())]
    return block[: at + 1] + [f"{indent}trigger\n"] + block[at + 1:]


def model_seed(seed: int | str, index: int) -> str:
    """The seed of model ``index`` of a run from ``seed``."""
    return f"{seed}.{index}"


class Builder:
    def __init__(self, seed: str, on: frozenset[str]):
        self.seed = seed
        self.on = on
        self.rng = random.Random(seed)
        self.env = TypeEnv(self.rng, on)
        self.x = Exprs(self.rng, self.env, on)
        self.s = Stmts(self.x)
        self.items: list[ast.Node] = []
        self.interfaces: list[ast.Interface] = []
        self.platform_members: list[ast.Node] = []
        self.module_connections: list[ast.Connection] = []
        self.ops_iface: ast.Interface | None = None
        self.shared_iface: ast.Interface | None = None

    # ---------------------------------------------------------------- the model

    def build(self) -> Generated:
        rng, on = self.rng, self.on
        languages = [lang for lang in ("robochart", "robosim") if lang in on]
        self.language = rng.choice(languages)
        self.robosim = self.language == "robosim"
        self.period = rng.choice(("1", "1", "2", "0.5")) if self.robosim else None
        self.env.declare()
        self.functions = userfns.draw(self.rng, self.env, self.x) if "user_functions" in on else ()
        modular = "modules" in on and rng.random() < 0.75
        self.machines_ = Machines(self.x, self.s, self.functions)
        if modular:
            self._module()
        else:
            self._lone()
        imports = tuple(ast.Import(name(t), True) for t in sorted(self.x.toolkits))
        items = tuple(self.env.decls) + tuple(userfns.declarations(self.functions)) + tuple(self.interfaces) + tuple(self.items)
        ext = ".rst" if self.robosim else ".rct"
        path = "fz_" + self.seed.replace(".", "_").replace("-", "m") + ext
        f = ast.File(path, self.language, name(f"fz{self.seed.replace('.', '_').replace('-', 'm')}"), imports, items)
        return Generated(self.seed, self.language, f, self.functions, 8, on)

    def _lone(self) -> None:
        """One state machine, its events declared in it (RoboSim: in its contexts)."""
        spec = MachineSpec(self.x.fresh("M"), self.robosim)
        spec.inputs = self._events("in", self.rng.randint(1, 3))
        spec.outputs = self._events("out", self.rng.randint(0, 3))
        members = self._machine_decls(spec, events=True)
        self.items.append(self._machine_node(spec, members))

    def _module(self) -> None:
        rng = self.rng
        controllers = [self._controller_shell() for _ in range(rng.choice((1, 1, 1, 2)))]
        for c in controllers:  # three machines at most
            for _ in range(rng.choice((1, 1, 2, 2, 3)) if len(controllers) == 1 else rng.choice((1, 1, 2))):
                self._add_machine(c)
        for c in controllers:
            self._wire_machines(c)
        self.ops_iface = ops_iface = self._platform_operations(controllers)
        self.shared_iface = shared = self._shared_variables(controllers)
        self._platform_variables(controllers)
        for c in controllers:
            for m in c.machines:
                self._software_operations(c, m)
        for c in controllers:
            for m in c.machines:
                members = self._machine_decls(m.spec, events=True, ops_iface=ops_iface, shared=shared)
                m.node = self._machine_node(m.spec, members)
        self._emit(controllers)

    # ---------------------------------------------------------------- events

    def _events(self, direction: str, n: int) -> list[tuple[str, T.Type | None]]:
        out = []
        for _ in range(n):
            t: T.Type | None = None
            if self.rng.random() < 0.7:
                t = self.env.draw("port", 2)
                if not port_safe(t):
                    t = self.env.scalar("port")
            out.append((self.x.fresh("e"), t))
        return out

    # ---------------------------------------------------------------- controllers and machines

    def _controller_shell(self) -> _Controller:
        n = self.x.fresh("Ctl")
        inline = self.rng.random() < 0.3
        return _Controller(n, n.lower() if not inline and self.rng.random() < 0.7 else n, inline)

    def _add_machine(self, c: _Controller) -> None:
        rng = self.rng
        spec = MachineSpec(self.x.fresh("M"), self.robosim)
        inline = rng.random() < 0.25
        instance = spec.name if inline else spec.name.lower()
        m = _Machine(spec, instance, inline)
        c.machines.append(m)
        # events from the platform and to it, through the controller and the module
        for direction, n in (("in", rng.randint(1, 3)), ("out", rng.randint(0, 3))):
            for event, t in self._events(direction, n):
                outer = self.x.fresh("p") if rng.random() < 0.3 else event
                mid = self.x.fresh("c") if rng.random() < 0.3 else event
                c.events.append(ast.EventDecl(mid, type_ast(t) if t is not None else None))
                self.platform_members.append(ast.EventDecl(outer, type_ast(t) if t is not None else None))
                if direction == "in":
                    spec.inputs.append((event, t))
                    self.module_connections.append(ast.Connection("<platform>", outer, c.instance, mid, True))
                    c.connections.append(ast.Connection(c.name, mid, m.instance, event))
                else:
                    spec.outputs.append((event, t))
                    self.module_connections.append(ast.Connection(c.instance, mid, "<platform>", outer, True))
                    c.connections.append(ast.Connection(m.instance, event, c.name, mid))

    def _wire_machines(self, c: _Controller) -> None:
        """Events from a machine to a later one of the same controller."""
        rng = self.rng
        if "machine_connections" not in self.on:
            return
        for i, a in enumerate(c.machines):
            for b in c.machines[i + 1:]:
                for _ in range(rng.choice((0, 1, 1, 2))):
                    event, t = self._events("in", 1)[0]
                    target = self.x.fresh("e") if rng.random() < 0.3 else event
                    mult = "mult" in self.on and not self.robosim and rng.random() < 0.2
                    broadcast = "broadcast" in self.on and not self.robosim and mult and rng.random() < 0.5
                    a.spec.outputs.append((event, t))
                    b.spec.inputs.append((target, t))
                    if broadcast:
                        a.spec.broadcast.add(event)
                        b.spec.broadcast.add(target)
                    asynchronous = not mult and rng.random() < 0.3
                    c.connections.append(ast.Connection(a.instance, event, b.instance, target, asynchronous, mult))

    def _platform_operations(self, controllers: list[_Controller]) -> ast.Interface | None:
        rng = self.rng
        if "platform_operations" not in self.on or rng.random() < 0.4:
            return None
        sigs = []
        for _ in range(rng.randint(1, 2)):
            params = []
            for i in range(rng.randint(0, 2)):
                t = self.env.draw("port", 1)
                params.append((f"a{i + 1}", t if port_safe(t) and not isinstance(t, (T.SetT, T.SeqT)) else T.INT))
            sigs.append(OpInfo(self.x.fresh("op"), tuple(params), True))
        iface = ast.Interface(self.x.fresh("PO"), tuple(ast.OpSig(o.name, tuple(ast.Param(n, type_ast(t)) for n, t in o.params))
                                                       for o in sigs))
        self.interfaces.append(iface)
        self.platform_members.append(ast.InterfaceRef("provides", name(iface.name)))
        for c in controllers:
            c.members.append(ast.InterfaceRef("requires", name(iface.name)))
            for m in c.machines:
                m.spec.ops += sigs
        return iface

    def _shared_variables(self, controllers: list[_Controller]) -> ast.Interface | None:
        rng = self.rng
        if "shared_variables" not in self.on or rng.random() < 0.6:
            return None
        syms = [Sym(self.x.fresh("sv"), rng.choice((T.INT, T.NAT, T.REAL, T.BOOLEAN)), "shared") for _ in range(rng.randint(1, 2))]
        iface = ast.Interface(self.x.fresh("SV"), (ast.VarList(False, tuple(ast.VarDecl(s.name, type_ast(s.type)) for s in syms)),))
        self.interfaces.append(iface)
        for c in controllers:
            c.members.append(ast.InterfaceRef("provides", name(iface.name)))
            for m in c.machines:
                m.spec.shared += syms
        return iface

    def _platform_variables(self, controllers: list[_Controller]) -> None:
        """RoboSim: variables of the platform the machines read (``$x``, their input context
        requires them) and write (``$y = e``, their output context)."""
        rng = self.rng
        if not self.robosim or "platform_variables" not in self.on or rng.random() < 0.6:
            return
        for kind in ("read", "write"):
            syms = [Sym(self.x.fresh("pv"), rng.choice((T.INT, T.NAT, T.REAL, T.BOOLEAN)), "platform") for _ in range(rng.randint(0, 2))]
            if not syms:
                continue
            iface = ast.Interface(self.x.fresh("PV"), (ast.VarList(False, tuple(ast.VarDecl(v.name, type_ast(v.type)) for v in syms)),))
            self.interfaces.append(iface)
            self.platform_members.append(ast.InterfaceRef("provides", name(iface.name)))
            for c in controllers:
                c.members.append(ast.InterfaceRef("requires", name(iface.name)))
                for m in c.machines:
                    (m.spec.dollar_reads if kind == "read" else m.spec.dollar_writes).extend(syms)
                    (m.spec.read_ifaces if kind == "read" else m.spec.write_ifaces).append(iface.name)

    def _software_operations(self, c: _Controller, m: _Machine) -> None:
        """Operations only ``m`` calls, defined at the top level and referenced by ``c``."""
        rng = self.rng
        if "operations" not in self.on or rng.random() < 0.6:
            return
        for _ in range(rng.randint(1, 2)):
            params = tuple((f"q{i + 1}", self.env.draw("param", 1)) for i in range(rng.randint(0, 2)))
            params = tuple((n, t if not isinstance(t, T.FunctionT) else T.INT) for n, t in params)
            op = OpInfo(self.x.fresh("sop"), params, False)
            spec = MachineSpec(op.name, self.robosim, outputs=list(m.spec.outputs), shared=list(m.spec.shared),
                               params=[Sym(n, t, "param") for n, t in params], operation=True,
                               ops=[o for o in m.spec.ops if o.platform])
            spec.broadcast = set(m.spec.broadcast)
            abstract = "abstract_operations" in self.on and rng.random() < 0.3  # declared without behaviour
            body = [ast.Terminates()] if abstract else self._op_decls(spec) + self.machines_.body(spec)
            self.items.append(ast.OperationDef(op.name, tuple(ast.Param(n, type_ast(t)) for n, t in params), tuple(body)))
            iface = ast.Interface(self.x.fresh("SO"), (ast.OpSig(op.name, tuple(ast.Param(n, type_ast(t)) for n, t in params)),))
            self.interfaces.append(iface)
            m.spec.ops.append(op)
            m.spec.sw_ifaces.append(iface.name)
            c.members.append(ast.Reference(self.x.fresh("o"), kind="opref", target=name(op.name)))

    def _op_decls(self, spec: MachineSpec) -> list[ast.Node]:
        """An operation's own declarations: the events it sends, the variables it shares."""
        members: list[ast.Node] = []
        events: list[ast.Node] = [self._event_decl(e, t, spec) for e, t in spec.outputs]
        platform_ops = [ast.InterfaceRef("requires", name(self.ops_iface.name))] if self.ops_iface and spec.ops else []
        shared = [ast.InterfaceRef("requires", name(self.shared_iface.name))] if self.shared_iface and spec.shared else []
        if self.robosim:
            if events or platform_ops or shared:
                members.append(ast.Context("output", tuple(events + platform_ops + shared)))
            if shared:
                members.append(ast.Context("input", tuple(shared)))
            return members
        return members + events + platform_ops + shared

    # ---------------------------------------------------------------- declarations of a machine

    def _event_decl(self, event: str, t: T.Type | None, spec: MachineSpec) -> ast.EventDecl:
        broadcast = event in spec.broadcast
        return ast.EventDecl(event, type_ast(t) if t is not None else None, broadcast)

    def _requires(self, spec: MachineSpec, ops_iface: ast.Interface | None = None, shared: ast.Interface | None = None) -> list[ast.Node]:
        out: list[ast.Node] = []
        if spec.shared and shared is not None:
            out.append(ast.InterfaceRef("requires", name(shared.name)))
        for iface in spec.sw_ifaces:
            out.append(ast.InterfaceRef("requires", name(iface)))
        return out

    def _machine_decls(self, spec: MachineSpec, events: bool, ops_iface: ast.Interface | None = None,
                       shared: ast.Interface | None = None) -> list[ast.Node]:
        ins = [self._event_decl(e, t, spec) for e, t in spec.inputs]
        outs = [self._event_decl(e, t, spec) for e, t in spec.outputs if e not in {x for x, _ in spec.inputs}]
        platform_ops = [ast.InterfaceRef("requires", name(ops_iface.name))] if ops_iface is not None and spec.ops else []
        if not self.robosim:
            return [*ins, *outs, *platform_ops, *self._requires(spec, ops_iface, shared)]
        members: list[ast.Node] = [ast.CycleDef(ast.Binary("==", ast.Keyword("cycle"), _number(self.period)))]
        shared_ref = [ast.InterfaceRef("requires", name(shared.name))] if spec.shared and shared is not None else []
        reads = [ast.InterfaceRef("requires", name(i)) for i in spec.read_ifaces]
        writes = [ast.InterfaceRef("requires", name(i)) for i in spec.write_ifaces]
        members.append(ast.Context("input", tuple(ins) + tuple(shared_ref) + tuple(reads)))
        members.append(ast.Context("output", tuple(outs) + tuple(platform_ops) + tuple(shared_ref) + tuple(writes)))
        members += [ast.InterfaceRef("requires", name(i)) for i in spec.sw_ifaces]
        return members

    def _machine_node(self, spec: MachineSpec, members: list[ast.Node]) -> ast.StateMachine:
        body = self.machines_.body(spec)
        return ast.StateMachine(spec.name, tuple(members + body))

    # ---------------------------------------------------------------- the module

    def _emit(self, controllers: list[_Controller]) -> None:
        rng = self.rng
        platform_name = self.x.fresh("Pl")
        inline_platform = rng.random() < 0.4
        platform_instance = platform_name if inline_platform else platform_name.lower()
        platform = ast.Platform(platform_name, tuple(self.platform_members))
        module_members: list[ast.Node] = []
        if self.robosim:
            module_members.append(self._cycle_def())
        if inline_platform:
            module_members.append(platform)
        else:
            self.items.append(platform)
            module_members.append(ast.Reference(platform_instance, kind="rref", target=name(platform_name)))
        for c in controllers:
            node = self._controller_node(c)
            if c.inline:
                module_members.append(node)
            else:
                self.items.append(node)
                module_members.append(ast.Reference(c.instance, kind="cref", target=name(c.name)))
        for conn in self.module_connections:
            source = platform_instance if conn.source == "<platform>" else conn.source
            target = platform_instance if conn.target == "<platform>" else conn.target
            module_members.append(ast.Connection(source, conn.source_event, target, conn.target_event, True))
        self.items.append(ast.Module(self.x.fresh("Mod"), tuple(module_members)))

    def _controller_node(self, c: _Controller) -> ast.Controller:
        members: list[ast.Node] = []
        if self.robosim:
            members.append(self._cycle_def())
        members += c.members + c.events
        for m in c.machines:
            assert m.node is not None
            if m.inline:
                members.append(m.node)
            else:
                self.items.append(m.node)
                members.append(ast.Reference(m.instance, kind="sref", target=name(m.spec.name)))
        members += c.connections
        return ast.Controller(c.name, tuple(members))

    def _cycle_def(self) -> ast.CycleDef:
        return ast.CycleDef(ast.Binary("==", ast.Keyword("cycle"), _number(self.period)))


def _number(text: str | None) -> ast.Expr:
    assert text is not None
    return ast.RealLit(text) if "." in text else ast.IntLit(int(text))


def generate(seed: str, on: frozenset[str]) -> Generated:
    """The model of ``seed`` with the features ``on``."""
    return Builder(seed, on).build()


__all__ = ["Generated", "generate", "model_seed"]
