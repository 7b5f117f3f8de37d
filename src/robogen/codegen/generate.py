"""Render an IR FMU into its sources: ``config.h``, ``model.c``, the unity file
``<modelIdentifier>.c``, ``modelDescription.xml``, ``sources/buildDescription.xml`` and
``documentation/``. Everything comes from the one IR, so value references cannot drift between
the C tables and the XML; output is deterministic (no time stamps, declaration order).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Sequence

import jinja2

from robogen import __version__
from robogen.codegen.c import (
    CNames,
    Emitter,
    c_comment,
    c_string,
    ctype,
    deliver,
    literal,
    mangle,
    string_literal,
    user_function_prototype,
)
from robogen.codegen.collections import CollectionCode, typedef as collection_typedef
from robogen.codegen.description import model_description
from robogen.codegen.layout_code import read, views as write_views
from robogen.codegen.lookahead_code import lookahead_code
from robogen.diagnostics import DiagnosticSink, Note, RobogenError, Span, error
from robogen.fmu.modeldesc import Dimension, Variable, instantiation_token
from robogen.fmu.modeldesc_writer import write_model_description
from robogen.ir import model as ir
from robogen.ir.dump import dump
from robogen.ir.layout import leaves, nested
from robogen.ir.supported import ArrayT, FunMapT, literal_conditions
from robogen.ir.walk import initial_order, value_types
from robogen.semantics import types as T

FMI_TYPE = {"int64_t": "Int64", "uint64_t": "UInt64", "double": "Float64", "bool": "Boolean"}
RG_TYPE = {"Int64": "RG_INT64", "UInt64": "RG_UINT64", "Float64": "RG_FLOAT64", "Boolean": "RG_BOOLEAN", "Enumeration": "RG_INT64",
           "String": "RG_STRING", "Clock": "RG_CLOCK"}
# A String variable holds the number of its string among the model's literals (robogen_runtime_values.c);
# an importer's other strings are kept by the instance, this many at most, each below RG_STRING_BYTES.
STRING_BYTES = 256


@dataclass(frozen=True)
class CodegenOptions:
    """How the sources are written (the model's meaning is fixed by the IR)."""

    line_comments: bool = True  # the model file:line in the C comments
    functions: Path | None = None  # the C file implementing the model's user functions (--functions)


@dataclass
class FmiVar:
    name: str
    vr: int
    fmi_type: str  # Float64 Int64 UInt64 Boolean Enumeration String Clock
    causality: str
    variability: str
    field: str = ""  # C member of rg_model_data ("" for clocks)
    initial: str | None = None
    start: str | None = None
    clock: int | None = None  # value reference of its clock
    clock_index: int = -1  # rg_clocks index of its clock
    declared_type: str | None = None
    description: str = ""
    dims: tuple[int, ...] = ()  # arrays: one <Dimension> each (vectors: 1, matrices: rows, columns)
    # clocks
    interval_variability: str | None = None
    interval: str | None = None
    shift: str | None = None
    span: Span | None = None  # the model element it comes from (None: one of robogen's own)

    @property
    def size(self) -> int | None:
        """Number of elements of an array (None for a scalar)."""
        if not self.dims:
            return None
        n = 1
        for d in self.dims:
            n *= d
        return n

    @property
    def rg_type(self) -> str:
        return RG_TYPE[self.fmi_type]

    @property
    def rg_causality(self) -> str:
        return {"parameter": "RG_PARAMETER", "input": "RG_INPUT", "output": "RG_OUTPUT", "local": "RG_LOCAL"}[self.causality]

    @property
    def rg_variability(self) -> str:
        return {"fixed": "RG_FIXED", "tunable": "RG_TUNABLE", "discrete": "RG_DISCRETE", "constant": "RG_CONSTANT"}[self.variability]

    @property
    def settable_in_init(self) -> bool:
        return self.causality in ("parameter", "input")

    def described(self) -> Variable:
        """How modelDescription.xml declares it."""
        if self.fmi_type == "Clock":
            return Variable(self.name, self.vr, "Clock", self.causality, "discrete", description=self.description,
                            interval_variability=self.interval_variability, interval_decimal=self.interval or None,
                            shift_decimal=self.shift if self.interval else None)
        start: tuple[str, ...] = () if self.start is None else (self.start,)
        if self.fmi_type == "String" and self.dims and self.start is not None:  # one <Start> per entry: the empty string
            start = ("",) * (self.size or 0)
        return Variable(self.name, self.vr, self.fmi_type, self.causality, self.variability, description=self.description,
                        initial=self.initial, start=start,
                        declared_type=self.declared_type, clocks=() if self.clock is None else (self.clock,),
                        dimensions=tuple(Dimension(start=d) for d in self.dims))


@dataclass
class EnumType:
    name: str
    items: list[tuple[str, int]]


@dataclass
class Generated:
    """The files of an FMU's sources, by relative path inside the FMU archive."""

    fmu: ir.Fmu
    model_identifier: str
    token: str
    files: dict[str, str] = field(default_factory=dict)
    variables: list[FmiVar] = field(default_factory=list)

    def write(self, folder: Path) -> list[Path]:
        written = []
        for rel, text in self.files.items():
            path = folder / rel
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(text, encoding="utf-8")
            written.append(path)
        return written


def _env() -> jinja2.Environment:
    env = jinja2.Environment(
        loader=jinja2.PackageLoader("robogen", "templates"),
        undefined=jinja2.StrictUndefined,
        keep_trailing_newline=True,
        trim_blocks=True,
        lstrip_blocks=True,
        autoescape=False,
    )
    env.filters["c_string"] = c_string
    env.filters["c_comment"] = c_comment
    return env


def _decimal(value: Fraction) -> str:
    """A decimal text of a time in seconds, exact when the fraction has a finite expansion."""
    f = float(value)
    text = repr(f)
    return text[:-2] if text.endswith(".0") else text


def generate(fmu: ir.Fmu, options: CodegenOptions | None = None, *, diagrams: Sequence[str] = ()) -> Generated:
    """The sources of ``fmu``.

    ``diagrams`` holds a Mermaid state diagram of each machine, in IR order, for the
    documentation. They are a finished input, drawn by the front end from the resolved model
    before lowering (see :func:`robogen.codegen.api.compile_model`): a diagram shows the model as
    written (composite states, transition labels in model syntax), which the IR no longer holds
    (its transitions are blocks), and the generator reads nothing but the IR and its options."""
    options = options or CodegenOptions()
    line_comments = options.line_comments
    functions = _functions_file(fmu, options.functions)
    names = CNames.of(fmu)
    layout = _Layout(fmu, names.vars)
    ir_text = dump(fmu)
    token = instantiation_token(ir_text)  # a hash of the path-free IR: changes with the model's meaning only
    gen = Generated(fmu, fmu.model_identifier, token, variables=layout.variables)
    env = _env()
    collections = CollectionCode(fmu)
    machines, sites, strings = _machines_code(fmu, layout, names, line_comments, collections)
    latch = {p.index: _latch(p, layout.port_fields_in.get(p.index, []), collections) for p in fmu.inputs}
    deliveries = {p.index: _deliveries(fmu, p, names) for p in fmu.inputs}
    needed = _declare_types(fmu, layout, collections, machines)
    equalities, bodies = _equalities(layout.types, set(needed))
    param_starts = {p.fmi_name: _param_starts(p, strings) for p in fmu.params}  # before the strings are written
    hooks = _hooks(fmu, machines)
    collection_code = collections.text()
    context = dict(
        user_functions=[(u, user_function_prototype(u)) for u in fmu.user_functions],
        names=names,
        cname=names.vars,
        typedefs=[_typedef(t, fmu.capacity_of(t)) for t in layout.types],
        sites=sites,
        **_strings(layout, strings, collections.texts or any(mc["texts"] for mc in machines)),
        views=write_views(fmu, layout.views),
        latch=latch,
        deliveries=deliveries,
        collection_code=collection_code,
        equality_bodies=bodies,
        param_starts=param_starts,
        diagrams={m.index: diagrams[m.index] if m.index < len(diagrams) else "stateDiagram-v2\n  %% (no diagram)" for m in fmu.machines},
        fmu=fmu,
        version=__version__,
        token=token,
        layout=layout,
        machines=machines,
        equalities=equalities,
        hooks=hooks,
        hook_names={h for h, _ in hooks},
        clock_constants=[(c, _clock_comment(fmu, c)) for c in layout.clocks],
        stepwise=fmu.semantics == "stepwise",
        line_comments=line_comments,
        sources=", ".join(fmu.source_names),
        place=fmu.place,
        interval=_decimal(fmu.clock_interval),
        ctype=ctype,
        literal=literal,
    )
    ident = fmu.model_identifier
    gen.files["modelDescription.xml"] = write_model_description(model_description(
        fmu, token, [v.described() for v in layout.variables], [(e.name, e.items) for e in layout.enums],
        context["interval"]))
    gen.files["sources/config.h"] = env.get_template("config.h.j2").render(**context)
    gen.files["sources/model.c"] = env.get_template("model.c.j2").render(**context)
    gen.files[f"sources/{ident}.c"] = env.get_template("unity.c.j2").render(**context)
    if functions is not None:
        gen.files["sources/user_functions.c"] = functions
    gen.files["sources/buildDescription.xml"] = env.get_template("buildDescription.xml.j2").render(**context)
    gen.files["documentation/index.md"] = env.get_template("documentation.md.j2").render(**context)
    gen.files["documentation/externalDependencies.txt"] = "none beyond libc and libm\n"
    gen.files["documentation/ir.txt"] = ir_text
    return gen


def _declare_types(fmu: ir.Fmu, layout: _Layout, collections: CollectionCode, machines: list) -> dict:
    """Declare in ``layout`` every C type the code uses, check their sizes, and return the types
    compared by name in the machines' code."""
    for t in collections.types:
        layout.declare(t)
    for u in fmu.user_functions:  # the C types a --functions file receives and returns
        for t in (*(pt for _, pt in u.params), u.result):
            layout.declare(t)
    needed = {name: t for mc in machines for name, t in mc["equalities"].items()}
    for t in needed.values():  # a type compared only inside an expression (a tuple key) is declared too
        layout.declare(t)
    for t in value_types(fmu):  # every other use: a literal, an operation's parameter, a local, ...
        layout.declare(t, enums=False)
    _check_sizes(fmu, layout.types)
    return needed


# The largest C value of a model type: values are passed and returned on the C stack (a set
# operation holds about four), which the host's thread gives (8 MiB by default on Linux, less in
# some hosts' threads); a larger one is an error at generation that names it.
VALUE_BYTES = 1 << 18


def value_bytes(t: T.Type, capacity_of) -> int:
    """The size of a C value of type ``t`` (members of 8 bytes aligned to 8)."""
    if t == T.BOOLEAN:
        return 1
    if isinstance(t, T.RecordT):
        sizes = [value_bytes(ft, capacity_of) for _, ft in t.fields]
        total = 0
        for n in sizes:
            total = (total + 7) // 8 * 8 + n if n >= 8 else total + n
        return (total + 7) // 8 * 8 if any(n >= 8 for n in sizes) else total
    if isinstance(t, (T.VectorT, T.MatrixT, ArrayT)):
        element, dims = _shape(t)
        count = 1
        for n in dims:
            count *= n
        return count * value_bytes(element, capacity_of)
    if isinstance(t, (T.SetT, T.SeqT)):
        return 8 + capacity_of(t) * max(value_bytes(t.element, capacity_of), 1)
    return 8


def _check_sizes(fmu: ir.Fmu, types: list[T.Type]) -> None:
    """Every C value of the model is below :data:`VALUE_BYTES` (the error names the first
    variable or event of a type that holds a larger one)."""
    for t in types:
        size = value_bytes(t, fmu.capacity_of)
        if size <= VALUE_BYTES:
            continue
        holders = [(v.span, v.type) for m in fmu.machines for v in m.vars] + \
                  [(e.span, e.type) for m in fmu.machines for e in m.events if e.type is not None]
        span = next((sp for sp, ht in holders if ht == t or t.show() in ht.show()), fmu.span)
        levels = ", ".join(map(str, fmu.levels))
        raise RobogenError.at(f"a value of type {t.show()} takes {size} bytes in C at capacities {levels}, more than the "
                              f"{VALUE_BYTES} bytes robogen gives one value (values are passed on the C stack): give the "
                              "inner levels of collections smaller capacities (--capacity 32,8)", span)


def _strings(layout: "_Layout", strings: list[str], texts: bool) -> dict:
    """What the templates need of the model's strings: the table of their texts (``strings``,
    None without String variables or a string compared or passed by its text: ``texts``)."""
    variables = any(v.fmi_type == "String" for v in layout.variables)
    return dict(strings=strings if variables or texts else None, string_variables=variables, texts=texts,
                string_bytes=STRING_BYTES)


def _functions_file(fmu: ir.Fmu, path: Path | None) -> str | None:
    """The user's C file with the model's functions, copied verbatim into sources/ (None if the
    model calls no user function). Each function the model calls without a C file is an error
    at its first call, naming the definition to write."""
    if not fmu.user_functions:
        return None
    if path is None:
        raise _unimplemented(fmu.user_functions, "give robogen a C file with --functions")
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise RobogenError.at(f"cannot read the functions file {path}: {exc}", Span.whole_file(str(path))) from None
    missing = [u for u in fmu.user_functions if not re.search(rf"\brg_user_{re.escape(u.cname)}\s*\(", text)]
    if missing:  # every one, located at its first call, rather than the C compiler's first complaint
        raise _unimplemented(missing, f"{path} does not define it")
    return text


def _unimplemented(functions: Sequence[ir.UserFunction], why: str) -> RobogenError:
    """One error per function, at its first call, spelling out the C definition to write."""
    return RobogenError([
        error(f"function '{u.name}'{f' (instantiated with {u.shown})' if u.shown else ''} has no implementation: {why}",
              u.first_call or u.span,
              Note(f"the file must define: {user_function_prototype(u)} {{ ... }}"))
        for u in functions
    ])


def _typedef(t: T.Type, capacity: int) -> str:
    if isinstance(t, (T.SetT, T.SeqT)):
        return collection_typedef(t, capacity)
    if isinstance(t, T.RecordT):
        fields = "\n".join(f"    {ctype(ft)} {n};" for n, ft in t.fields)
        what = f"a function value {t.show()}: its pairs and its default" if isinstance(t, FunMapT) else f"datatype {t.qname}"
        return f"/* {what} */\ntypedef struct {{\n{fields}\n}} {ctype(t)};"
    if isinstance(t, T.VectorT):
        return f"typedef struct {{ {ctype(t.element)} a[{t.size}]; }} {ctype(t)};  /* {t.show()} */"
    if isinstance(t, ArrayT):
        return f"typedef struct {{ {ctype(t.element)} a[{t.size}]; }} {ctype(t)};  /* {t.show()}, row-major */"
    assert isinstance(t, T.MatrixT)
    return f"typedef struct {{ {ctype(t.element)} a[{(t.rows or 0) * (t.columns or 0)}]; }} {ctype(t)};  /* {t.show()}, row-major */"


def _equalities(types: list[T.Type], needed: set[str]) -> tuple[list[str], dict[str, str]]:
    """Equality functions of the struct types ``needed`` and of the struct types they contain,
    in dependency order (``types`` is already dependency-ordered)."""
    by_name = {ctype(t): t for t in types}
    closure = set()

    def add(name: str) -> None:
        if name in closure:
            return
        closure.add(name)
        t = by_name[name]
        inner = [ft for _, ft in t.fields] if isinstance(t, T.RecordT) else [t.element]  # type: ignore[union-attr]
        for ft in inner:
            if isinstance(ft, STRUCTS):
                add(ctype(ft))

    for name in needed:
        add(name)
    order = [ctype(t) for t in types if ctype(t) in closure]
    bodies = {}
    for name in order:
        t = by_name[name]
        if isinstance(t, T.RecordT):
            tests = [
                f"rg_eq_{ctype(ft)}(a.{n}, b.{n})" if isinstance(ft, STRUCTS) else f"a.{n} == b.{n}"
                for n, ft in t.fields
            ]
            bodies[name] = "    return " + " && ".join(tests) + ";"
        elif isinstance(t, (T.SetT, T.SeqT)):
            same = f"rg_eq_{ctype(t.element)}(a.a[i], b.a[i])" if isinstance(t.element, STRUCTS) else "a.a[i] == b.a[i]"
            bodies[name] = (f"    uint64_t i;\n    if (a.n != b.n) return false;\n    for (i = 0; i < a.n; i++)\n"
                            f"        if (!({same})) return false;\n    return true;")
        else:
            size = t.size if isinstance(t, T.VectorT) else (t.rows or 0) * (t.columns or 0)  # type: ignore[union-attr]
            bodies[name] = (f"    int i;\n    for (i = 0; i < {size}; i++)\n        if (a.a[i] != b.a[i]) return false;\n    return true;")
    return order, bodies


STRUCTS = (T.RecordT, T.VectorT, T.MatrixT, T.SetT, T.SeqT)  # C types compared by a function rg_eq_<type>


def _latch(port: ir.Port, fields: list[tuple[str, ir.Field_]], collections: CollectionCode) -> list[str]:
    """The statements of rg_model_latch that assemble the value ``v`` of input port ``port`` from
    its clocked inputs. A set or sequence takes the array's first ``size`` elements (at most the
    capacity), a set then in canonical order (robogen.ir.collections.received)."""
    if nested(port.type):  # collections of collections, vectors or tagged values: a loop per level
        by_path = {f.path: member for member, f in fields}
        return ["memset(&v, 0, sizeof v);", *read(port.type, "v", by_path, collections.capacity_of,
                                                  lambda t: collections.need("canon", t), "")]
    lines, made = [], []
    for member, f in fields:
        *inner, last = f.path or ("",)
        if "#elements" in f.path[:-1]:  # one field of a collection's records, element by element
            k = f.path.index("#elements")
            at = "v" + "".join("." + p for p in f.path[:k])
            field = "".join("." + p for p in f.path[k + 1:])
            lines.append(f"{{ uint64_t i; for (i = 0; i < {collections.capacity}; i++) {at}.a[i]{field} = d->{member}.a[i]; }}")
        elif last in ("#elements", "#size"):
            at = "v" + "".join("." + p for p in inner)
            cap = collections.capacity
            if last == "#elements":
                lines.append(f"memcpy({at}.a, d->{member}.a, sizeof {at}.a);")
            else:
                lines.append(f"{at}.n = d->{member} > {cap} ? {cap} : d->{member};")
                made.append((at, _type_at(port.type, tuple(inner))))
        else:
            # an argument of an enumeration literal only when the tag selects the literal
            tests = [f"v{''.join('.' + p for p in at)} == {index}" for at, index in literal_conditions(port.type, f.path)]
            value = f"{' && '.join(tests)} ? d->{member} : 0" if tests else f"d->{member}"
            lines.append("v" + "".join("." + p for p in f.path) + f" = {value};")
    for at, t in made:
        lines.append(f"{at} = {collections.need('canon', t)}(d, {at});")
    return lines


def _deliveries(fmu: ir.Fmu, port: ir.Port, names: CNames) -> list[str]:
    """The statements of rg_model_latch that deliver the value ``v`` of input port ``port`` (if
    it carries one) to the machine events it reaches; its sender is the boundary, number 0."""
    value = "v" if port.type is not None else None
    return [line for mi, ei in port.routes
            for line in deliver(names.machines[mi], fmu.machines[mi].events[ei], value, port.type, 0, " " * 8)]


def _type_at(t, path: tuple[str, ...]) -> T.Type:
    for p in path:
        t = t.field(p)
    return t


def _param_starts(p: ir.Param, strings: list[str]) -> list[tuple[str, str]]:
    """The start values rg_model_reset writes: (C access inside the parameter, value); each
    element of a vector or matrix. None for records and for a value the model leaves out: the
    instance's memory starts zeroed, which is their default value. A string is its number in
    ``strings``, the model's strings (added there if the model does not write it)."""
    t = p.var.type
    if t == T.STRING and p.value is not None:
        return [("", string_literal(strings, p.value))]  # type: ignore[arg-type]
    if isinstance(t, (T.VectorT, T.MatrixT)) and isinstance(p.value, list):
        return [(f".a[{k}]", literal(x, t.element)) for k, x in enumerate(p.value)]
    if p.value is None or isinstance(t, (T.RecordT, T.VectorT, T.MatrixT)):
        return []
    return [("", literal(p.value, t))]


# ---------------------------------------------------------------------------- layout


class _Layout:
    """FMI variables (value references in a stable order), their C storage, and the C types."""

    def __init__(self, fmu: ir.Fmu, names: dict[ir.Var, str]):
        self.fmu = fmu
        self.variables: list[FmiVar] = []
        self.clocks: list[FmiVar] = []
        self.clock_index: dict[str, int] = {}
        self.port_fields_in: dict[int, list[tuple[str, ir.Field_]]] = {}
        self.port_fields_out: dict[int, list[tuple[str, ir.Field_]]] = {}
        self.data_fields: list[tuple[str, str, str]] = []  # (C type, member, comment)
        self.enums: list[EnumType] = []
        self.types: list[T.Type] = []  # struct types, dependencies first
        self.names = names  # machine variable -> C member name
        # locals shown through a view: (C access of the variable, view member, its type, leaf)
        self.views: list[tuple[str, str, T.Type, ir.Field_]] = []
        self._vr = 0
        self._build()

    def _next_vr(self) -> int:
        self._vr += 1
        return self._vr

    def _enum(self, t: T.EnumT) -> str:
        name = t.qname.replace("::", ".")
        if not any(e.name == name for e in self.enums):
            self.enums.append(EnumType(name, [(lit, i) for i, lit in enumerate(t.literals)]))
        return name

    def declare(self, t: T.Type, enums: bool = True) -> None:
        """Register a struct type (and what it contains) in dependency order; with ``enums``,
        the enumerations it holds as FMI types too."""
        if isinstance(t, T.RecordT):
            for _, ft in t.fields:
                self.declare(ft, enums)
        elif isinstance(t, (T.VectorT, T.MatrixT, T.SetT, T.SeqT, ArrayT)):
            self.declare(t.element, enums)
        else:
            if isinstance(t, T.EnumT) and enums:
                self._enum(t)
            return
        if not any(ctype(x) == ctype(t) for x in self.types):
            self.types.append(t)

    def _scalar(self, t: T.Type) -> tuple[str, str | None]:
        """(FMI type, declaredType) of a scalar or array element type."""
        if isinstance(t, T.EnumT):
            return "Enumeration", self._enum(t)
        if t == T.STRING:
            return "String", None
        return FMI_TYPE[ctype(t)], None

    def _start(self, t: T.Type, value: object = None) -> str:
        if isinstance(t, (T.VectorT, T.MatrixT, ArrayT)):
            element, dims = _shape(t)
            if isinstance(value, list):
                return " ".join(self._start(element, x) for x in value)
            count = 1
            for n in dims:
                count *= n
            return " ".join([self._start(element)] * count)
        if t == T.BOOLEAN:
            return "true" if value else "false"
        if t == T.REAL:
            return repr(float(value or 0))
        if t == T.STRING:
            return str(value or "")
        return str(int(value or 0))

    def _port(self, port, causality: str) -> None:
        """An event or operation port: its triggered clock, then one clocked variable per field."""
        inward = causality == "input"
        if inward:
            what = f"input event {port.source}"
        else:
            what = ("output event " if port.kind != "operation" else
                    "call of abstract operation " if port.abstract else "call of platform operation ") + port.source
        if port.model_name:
            what += f" (renamed: the FMU has another variable named {port.source})"
        c = FmiVar(port.name, self._next_vr(), "Clock", causality, "discrete", interval_variability="triggered",
                   description=what, span=port.span)
        self._add_clock(c, "RG_CLOCK_INPUT_TRIGGERED" if inward else "RG_CLOCK_OUTPUT_TRIGGERED")
        fields = (self.port_fields_in if inward else self.port_fields_out)[port.index] = []
        for f in port.fields:
            member = ("in_" if inward else "out_") + mangle(f.fmi_name)
            self._data(f.type, member, f"clocked {causality} {f.fmi_name}")
            fmi_type, declared = self._scalar(_shape(f.type)[0])
            if inward:
                description = f"value of input event {port.source}"
            elif port.kind == "operation":
                description = f"argument {f.path[0]} of {'abstract' if port.abstract else 'platform'} operation {port.source}"
            else:
                description = f"value of output event {port.source}"
            self.variables.append(FmiVar(
                f.fmi_name, self._next_vr(), fmi_type, causality, "discrete", member,
                start=self._start(f.type) if inward else None, clock=c.vr, clock_index=self.clock_index[port.name],
                declared_type=declared, dims=_shape(f.type)[1], span=port.span, description=description))
            fields.append((member, f))

    def _build(self) -> None:
        fmu = self.fmu
        vr = self._next_vr()  # the periodic clock's; a time-free FMU, which counts its tocks, leaves it unused so
        if not fmu.time_free:  # that both RoboChart variants number the other variables alike
            clock = FmiVar(fmu.clock_name, vr, "Clock", "input", "discrete",
                           interval_variability="constant", interval=_decimal(fmu.clock_interval), shift="0",
                           description=("one RoboSim cycle" if fmu.language == "robosim" else "one RoboChart time unit (tock)"))
            self._add_clock(clock, "RG_CLOCK_INPUT_CONSTANT")
        for port in fmu.inputs:
            self._port(port, "input")
        for port in fmu.outputs:
            self._port(port, "output")
        for p in fmu.params:
            member = f"m{p.machine}.v_{self.names[p.var]}"
            for name, t, access, _ in _flat(p.fmi_name, p.var.type, "", fmu.capacity_of):
                fmi_type, declared = self._scalar(_shape(t)[0])
                value = p.value if not access else None
                self.variables.append(FmiVar(
                    name, self._next_vr(), fmi_type, "parameter", "fixed", member + access,
                    start=self._start(t, value), declared_type=declared, dims=_shape(t)[1],
                    description=(f"constant {p.var.name}" if p.fmi_name != ir.RANDOM_SEED_NAME else
                                 "seed of the generator of nondeterministic waits and probabilistic junctions (SplitMix64)"),
                    span=p.var.span))
        for m in fmu.machines:
            enum_name = f"{m.name}.Node"
            self.enums.append(EnumType(enum_name, [(n.label, n.id) for n in m.nodes]))
            self.variables.append(FmiVar(
                f"{m.name}.state", self._next_vr(), "Enumeration", "output", "discrete", f"m{m.index}.node",
                initial="exact", start=str(m.initial_node), declared_type=enum_name,
                description=f"the node where state machine {m.name} rests"))
        self.variables.append(FmiVar("cycles", self._next_vr(), "UInt64", "output", "discrete", "cycles", initial="exact", start="0",
                                     description=f"ticks of {fmu.clock_name} processed" + (" (counted by the FMU: no clock)" if fmu.time_free else "")))
        self.variables.append(FmiVar("dropped_events", self._next_vr(), "UInt64", "output", "discrete", "dropped_events", initial="exact", start="0",
                                     description="input events overwritten by a newer one before a machine used them"))
        self.variables.append(FmiVar("deadline_misses", self._next_vr(), "UInt64", "output", "discrete", "deadline_misses", initial="exact", start="0",
                                     description="RoboChart deadlines missed (counted and logged, never enforced)"))
        parameters = {id(p.var) for p in fmu.params}
        for m in fmu.machines:
            for v in m.vars:
                self.declare(v.type)
                if v.kind not in ("var", "const") or id(v) in parameters:
                    continue  # constants are parameters, but those computed from an initialiser (sets, ...)
                for name, t, access, leaf in _flat(f"{m.name}.{v.name}", v.type, "", fmu.capacity_of):
                    member = f"m{m.index}.v_{self.names[v]}{access}"
                    if access is None:  # not contiguous in memory: a view, written after each instant
                        member = "view_" + mangle(name)
                        self._data(t, member, f"local {name}: a view of variable {v.name}")
                        self.views.append((f"d->m{m.index}.v_{self.names[v]}", member, v.type, ir.Field_(name, t, leaf)))
                    fmi_type, declared = self._scalar(_shape(t)[0])
                    self.variables.append(FmiVar(
                        name, self._next_vr(), fmi_type, "local", "discrete", member,
                        initial="calculated", declared_type=declared, dims=_shape(t)[1],
                        description=f"variable {v.name} of {m.name}", span=v.span))
            for e in m.events:
                if e.type is not None:
                    self.declare(e.type)
        self._check_names()

    def _check_names(self) -> None:
        """FMI variable names must be unique: a model name may clash with another, or with one of
        robogen's own (the periodic clock, the counters, the state outputs)."""
        sink = DiagnosticSink()
        first: dict[str, FmiVar] = {}
        for v in self.variables:
            other = first.setdefault(v.name, v)
            if other is v:
                continue
            culprit, kept = (v, other) if v.span is not None else (other, v)
            if kept.span is None:
                note = Note(f"'{kept.name}' is one of robogen's own FMI variables: the periodic clock (cycle in RoboSim, "
                            "tock in RoboChart), the counters cycles, dropped_events and deadline_misses, and the "
                            "state output <machine>.state of each state machine")
            else:
                note = Note(f"the {kept.description} has that name too", kept.span)
            sink.error(f"the FMU would have two variables named '{v.name}' ({culprit.description}); rename it in the "
                       "model", culprit.span, note)
        sink.raise_if_errors()

    def _add_clock(self, c: FmiVar, kind: str) -> None:
        self.clock_index[c.name] = len(self.clocks)
        c.field = kind  # the rg_clock_kind, for the clock table
        self.clocks.append(c)
        self.variables.append(c)

    def _data(self, t: T.Type, member: str, comment: str) -> None:
        self.declare(t)
        self.data_fields.append((ctype(t), member, comment))


def _shape(t: T.Type) -> tuple[T.Type, tuple[int, ...]]:
    """The element type and the dimensions of an FMI variable of type ``t`` (() for a scalar)."""
    if isinstance(t, T.VectorT):
        return t.element, (t.size or 0,)
    if isinstance(t, T.MatrixT):
        return t.element, (t.rows or 0, t.columns or 0)
    if isinstance(t, ArrayT):
        return t.element, t.dims
    return t, ()


def _flat(name: str, t: T.Type, access: str, capacity_of):
    """(FMI name, scalar or array type, C member access, path) of each leaf of a value
    (robogen.ir.layout). The access is None for a leaf that is not contiguous in memory (a field
    of the elements of a collection, the elements of a collection of collections): it is shown
    through a view."""
    for leaf in leaves(t, capacity_of):
        path = leaf.path
        inner = path[:-1] if path and path[-1] == "#elements" else path
        direct = "#elements" not in inner
        at = "".join(".n" if p == "#size" else ".a" if p == "#elements" else "." + p for p in path)
        yield ".".join((name,) + leaf.name), leaf.type, (access + at) if direct else None, path


# ---------------------------------------------------------------------------- machines


def _machines_code(fmu: ir.Fmu, layout: _Layout, names: CNames, line_comments: bool,
                   collections: CollectionCode) -> tuple[list[dict], list[str], list[str]]:
    """What the templates need of each machine: its run function's cases, initial values, block
    labels, and whether it has an event table (RoboChart machines join their buffers through it;
    any machine that events are delivered to is latched through it)."""
    emitters = [Emitter(fmu, m, layout.port_fields_out, names, line_comments) for m in fmu.machines]
    sites: list[str] = []  # one list for the FMU: each emitter numbers its sites after the others'
    strings = [""]  # one numbering of the strings for the FMU
    for em in emitters:
        em.collections, em.sites, em.strings = collections, sites, strings
    codes = [_machine_code(fmu, em, line_comments) for em in emitters]
    delivered = {mi for p in fmu.inputs for mi, _ in p.routes} | {mi for em in emitters for mi in em.delivers_to}
    for m, code in zip(fmu.machines, codes):
        code["event_table"] = bool(m.events) and (fmu.robochart or m.index in delivered)
    return codes, sites, strings


# A machine of more blocks than this runs as one C function per this many blocks (and a dispatcher
# over them), not one function of all of them: GCC needs time and memory superlinear in the size
# of one function (a 10,000-state machine, 30,000 blocks in one switch, did not compile at -O2
# with 14 GB). Smaller machines keep the one function.
PART_SIZE = 512


def _machine_code(fmu: ir.Fmu, em: Emitter, line_comments: bool) -> dict:
    m = em.m
    assert m.nodes, f"machine {m.name} has no node"
    cases = []
    for b in m.blocks:
        where = f"  {fmu.place(b.span)}" if (line_comments and b.span is not None) else ""
        lines = [f"        case {b.id}: /* b{b.id}: {c_comment(b.label)}{where} */"]
        if b.step:
            lines += em.step("            ")
        lines += em.stmts(b.stmts, "            ")
        assert b.term is not None
        lines += em.terminator(b.term, "            ")
        cases.append("\n".join(lines))
    inits = []
    for v in initial_order(m):  # variables, computed constants and the generator's state
        em.fallible = False
        value = em.expr(v.init)
        inits.append((f"m->v_{em.names.vars[v]}", value, em.fallible, v.name))
    labels = [c_string(f"b{b.id}: {b.label}" + (f" ({fmu.place(b.span)})" if b.span else "")) for b in m.blocks]
    lookahead = lookahead_code(fmu, em, line_comments) if fmu.time_free else []
    parts = [cases[k:k + PART_SIZE] for k in range(0, len(cases), PART_SIZE)]
    return dict(machine=m, names=em.own, cases=cases, parts=parts, part_size=PART_SIZE, inits=inits, labels=labels,
                lookahead=lookahead, equalities=em.equalities, texts=em.texts, helpers=em.helpers,
                event_types=[(e.index, ctype(e.type) if e.type is not None else None) for e in m.events])


def _hooks(fmu: ir.Fmu, machines: list[dict]) -> list[tuple[str, str]]:
    """The capability macros of config.h: the hooks model.c implements, each with why. The
    runtime's defaults stand in for the others (fmi3DoStep's, for one: the machines only react
    in Event Mode)."""
    hooks = []
    if any(mc["inits"] for mc in machines):
        hooks.append(("RG_HAS_EXIT_INITIALIZATION", "variables with initial values computed from the parameters"))
    if any(p.routes for p in fmu.inputs):
        hooks.append(("RG_HAS_LATCH", "input clocks carry events to the state machines"))
    hooks.append(("RG_HAS_EVALUATE", "the state machines run in Event Mode"))
    hooks.append(("RG_HAS_UPDATE", "a stepwise cycle, or an event waiting, needs another instant" +
                  ("; the next tock at which anything can happen is the next event time" if fmu.time_free else "")))
    if fmu.time_free:
        hooks.append(("RG_HAS_DO_STEP", "the tocks a step passes are counted (none of them can do anything)"))
    return hooks


def _clock_comment(fmu: ir.Fmu, clock: FmiVar) -> str:
    """What a clock is, for the comment beside its index constant."""
    port = next((p for p in fmu.inputs if p.name == clock.name), None)
    if port is not None and not port.routes:
        return f"{clock.description}: reaches no state machine"
    return clock.description


__all__ = ["generate", "CodegenOptions", "Generated", "FmiVar"]
