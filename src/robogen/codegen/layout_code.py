"""C that moves a value between its FMI variables (robogen.ir.layout) and the model's memory,
for the values whose collections hold collections, vectors or enumerations with arguments: one
loop per nesting level. (A scalar, a record, a vector and a collection of scalars or of records
of scalars have the simpler forms of robogen.codegen.generate and robogen.codegen.c.)

Writing (an output, a local variable's view) zeroes each array first, then copies the elements
each collection has; reading (an input) starts from a zeroed value, takes at most a capacity of
elements per collection and puts each set in canonical order once its elements are read, inner
levels first, as robogen.ir.layout.build does.
"""

from __future__ import annotations

from robogen.ir import model as ir
from robogen.ir.supported import ArrayT, FunMapT, TaggedT
from robogen.semantics import types as T


def _entries(t: T.Type) -> int:
    """Entries of one value of a leaf type: a vector's or matrix's elements, else 1."""
    if isinstance(t, T.VectorT):
        return t.size or 0
    if isinstance(t, T.MatrixT):
        return (t.rows or 0) * (t.columns or 0)
    return 1


def _index(index: str | None, capacity: int, i: str) -> str:
    return i if index is None else f"({index}) * {capacity} + {i}"


def write(t: T.Type, source: str, fields: list[tuple[str, ir.Field_]], capacity_of, indent: str,
          skip: int = 0) -> list[str]:
    """Statements writing value ``source`` of type ``t`` to the FMI variables ``fields`` ((C
    member of rg_model_data, field); their paths from ``skip`` on are inside the value)."""
    lines = []
    for member, f in fields:
        path = f.path[skip:]
        depth = path.count("#elements")
        if isinstance(f.type, (T.VectorT, ArrayT)) and "#elements" in path:
            lines.append(f"{indent}memset(&d->{member}, 0, sizeof d->{member});")
        body = _write(t, source, path, None, 0, f"d->{member}", capacity_of, indent + "    ")
        variables = ", ".join(f"i{k}" for k in range(depth)) + (", j" if _leaf_loop(t, path) else "")
        lines += [f"{indent}{{", f"{indent}    uint64_t {variables};"] if variables else [f"{indent}{{"]
        lines += body + [f"{indent}}}"]
    return lines


def _leaf_loop(t: T.Type, path: tuple[str, ...]) -> bool:
    """Whether the leaf at ``path`` is a vector or matrix inside a collection (a loop of its own)."""
    for p in path:
        t = t.element if p == "#elements" else T.NAT if p == "#size" else t.field(p)  # type: ignore[attr-defined, assignment]
    return isinstance(t, (T.VectorT, T.MatrixT)) and "#elements" in path


def _write(t, source: str, path, index, depth: int, target: str, capacity_of, indent: str) -> list[str]:
    if not path:
        n = _entries(t)
        if index is None:
            return [f"{indent}{target} = {source};"]
        if not isinstance(t, (T.VectorT, T.MatrixT)):  # (a vector of one element is a struct all the same)
            return [f"{indent}{target}.a[{index}] = {source};"]
        return [f"{indent}for (j = 0; j < {n}; j++) {target}.a[({index}) * {n} + j] = {source}.a[j];"]
    p = path[0]
    if p == "#size":
        return [f"{indent}{target}{'' if index is None else f'.a[{index}]'} = {source}.n;"]
    if p == "#elements":
        i = f"i{depth}"
        inner = _write(t.element, f"{source}.a[{i}]", path[1:], _index(index, capacity_of(t), i), depth + 1, target,
                       capacity_of, indent + "    ")
        return [f"{indent}for ({i} = 0; {i} < {source}.n; {i}++) {{", *inner, f"{indent}}}"]
    return _write(t.field(p), f"{source}.{p}", path[1:], index, depth, target, capacity_of, indent)


def read(t: T.Type, target: str, fields: dict[tuple[str, ...], str], capacity_of, canon, indent: str) -> list[str]:
    """Statements assembling the value ``target`` of type ``t`` (zeroed before) from the FMI
    variables ``fields`` (path inside the value -> C member of rg_model_data); ``canon(t)``: the
    function putting a set of type ``t`` in canonical order."""
    depth = _depth(t)
    lines = [f"{indent}uint64_t " + ", ".join([f"i{k}" for k in range(depth)] + ["j"]) + ";"]
    lines.append(f"{indent}(void)j;")
    return lines + _read(t, target, (), None, 0, fields, capacity_of, canon, indent)


def _depth(t: T.Type) -> int:
    if isinstance(t, (T.SetT, T.SeqT)):
        return 1 + _depth(t.element)
    if isinstance(t, T.RecordT):
        return max([_depth(ft) for _, ft in t.fields], default=0)
    return 0


def _read(t, target: str, path, index, depth: int, fields, capacity_of, canon, indent: str) -> list[str]:
    if isinstance(t, (T.SetT, T.SeqT)):
        cap, i = capacity_of(t), f"i{depth}"
        size = f"d->{fields[path + ('#size',)]}" + ("" if index is None else f".a[{index}]")
        inner = _read(t.element, f"{target}.a[{i}]", path + ("#elements",), _index(index, cap, i), depth + 1, fields,
                      capacity_of, canon, indent + "    ")
        lines = [f"{indent}{target}.n = {size} > {cap} ? {cap} : {size};",
                 f"{indent}for ({i} = 0; {i} < {target}.n; {i}++) {{", *inner, f"{indent}}}"]
        if isinstance(t, T.SetT):
            lines.append(f"{indent}{target} = {canon(t)}(d, {target});")
        return lines
    if isinstance(t, TaggedT):  # an argument only when the tag selects its literal
        lines = _read(t.tag, f"{target}.tag", path + ("tag",), index, depth, fields, capacity_of, canon, indent)
        for k, literal in enumerate(t.tag.literals):
            args = t.arg_fields(literal)
            if args:
                lines.append(f"{indent}if ({target}.tag == {k}) {{")
                for n, ft in args:
                    lines += _read(ft, f"{target}.{n}", path + (n,), index, depth, fields, capacity_of, canon, indent + "    ")
                lines.append(f"{indent}}}")
        return lines
    if isinstance(t, FunMapT):  # a function value has no FMI variables: it stays zero
        return []
    if isinstance(t, T.RecordT):
        lines = []
        for n, ft in t.fields:
            lines += _read(ft, f"{target}.{n}", path + (n,), index, depth, fields, capacity_of, canon, indent)
        return lines
    member = f"d->{fields[path]}"
    n = _entries(t)
    if index is None:
        return [f"{indent}{target} = {member};"]
    if not isinstance(t, (T.VectorT, T.MatrixT)):
        return [f"{indent}{target} = {member}.a[{index}];"]
    return [f"{indent}for (j = 0; j < {n}; j++) {target}.a[j] = {member}.a[({index}) * {n} + j];"]


def views(fmu: ir.Fmu, members: list[tuple[str, str, T.Type, ir.Field_]]) -> list[str]:
    """The body of rg_model_views: the local FMI variables of machine variables whose values are
    not contiguous in memory, each written from its variable (``members``: (C access of the
    variable, C member of the view, variable type, leaf field))."""
    lines: list[str] = []
    for access, member, t, f in members:
        lines += write(t, access, [(member, f)], fmu.capacity_of, "    ")
    return lines


__all__ = ["write", "read", "views"]
