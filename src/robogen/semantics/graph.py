"""`robogen graph`: each state machine (and software operation) as a Graphviz or Mermaid diagram.

Composite states become clusters (dot) or nested states (Mermaid); transition labels use the
paper's `trigger [guard] / action` form, with `exec` marked and exec transitions dashed.
Graphviz itself is not needed: emitting the text is the feature.
"""

from __future__ import annotations

import argparse
import sys

from robogen.diagnostics import RobogenError, UsageError, did_you_mean, error
from robogen.outputs import check_not_input, output_file, write_text
from robogen.semantics import check_paths
from robogen.semantics.model import MachineScope, Region, SemanticModel
from robogen.syntax import ast
from robogen.syntax.printer import stmt, transition_label

FORMATS = ("dot", "mermaid")


def configure(p: argparse.ArgumentParser) -> None:
    p.add_argument("paths", nargs="+", metavar="MODEL", help="model files and/or directories")
    p.add_argument("--machine", metavar="NAME", help="draw only this state machine or operation")
    p.add_argument("--format", choices=FORMATS, default="dot", help="diagram language (default: dot)")
    p.add_argument("-o", "--output", metavar="FILE",
                   help="write to FILE instead of standard output (never one of the models; replaced only once complete)")


def run(args: argparse.Namespace) -> int:
    output = output_file(args.output, inputs=args.paths) if args.output else None
    model = check_paths(args.paths)
    if model.errors:
        raise RobogenError(model.errors)
    scopes = select(model, args.machine)
    text = render(scopes, args.format)
    if output is not None:
        check_not_input(output, [f.path for f in model.files])  # a model file found in a folder given
        write_text(output, text)
    else:
        sys.stdout.write(text)
    return 0


def select(model: SemanticModel, name: str | None) -> list[MachineScope]:
    scopes = sorted(model.scopes, key=lambda s: (s.file.path, s.node.span.line if s.node.span else 0))
    scopes = [s for s in scopes if isinstance(s.node, (ast.StateMachine, ast.OperationDef))]
    if name is None:
        if not scopes:
            raise RobogenError(error("the models contain no state machine", None))
        return scopes
    chosen = [s for s in scopes if s.name == name or s.qname == name]
    if not chosen:
        raise UsageError(f"robogen graph: no state machine '{name}'" + did_you_mean(name, [s.name for s in scopes]))
    return chosen[:1]


def render(scopes: list[MachineScope], fmt: str) -> str:
    if fmt == "dot":
        return "".join(dot(s) for s in scopes)
    if len(scopes) == 1:
        return mermaid(scopes[0])
    return "".join(f"## {s.kind} {s.qname}\n\n```mermaid\n{mermaid(s)}```\n\n" for s in scopes)


# ---------------------------------------------------------------------------- Graphviz


def _q(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'


def _id(path: tuple[str, ...]) -> str:
    return _q(".".join(path))


def _actions_label(node: ast.State) -> str:
    lines = [node.name]
    for m in node.members:
        if isinstance(m, ast.StateAction):
            lines.append(f"{m.kind} / {stmt(m.stmt)}")
    return "\n".join(lines)


def dot(scope: MachineScope) -> str:
    assert scope.region is not None
    out = [f"digraph {_q(scope.qname)} {{", "  compound=true;", "  rankdir=LR;",
           f"  label={_q(f'{scope.kind} {scope.qname}')};", "  labelloc=t;",
           '  node [shape=box, style="rounded", fontname="Helvetica"];', '  edge [fontname="Helvetica", fontsize=10];']
    _dot_region(scope.region, (), out, "  ")
    for region in scope.region.walk():
        for t in region.transitions:
            src, dst = region.path + (t.source,), region.path + (t.target,)
            attrs = [f"label={_q(transition_label(t))}"]
            if t.exec:
                attrs.append("style=dashed")
            tail, head = _anchor(region, t.source, src), _anchor(region, t.target, dst)
            if t.source in region.children:
                attrs.append(f"ltail={_q('cluster_' + '.'.join(src))}")
            if t.target in region.children:
                attrs.append(f"lhead={_q('cluster_' + '.'.join(dst))}")
            out.append(f"  {tail} -> {head} [{', '.join(attrs)}];")
    out.append("}\n")
    return "\n".join(out)


def _anchor(region: Region, name: str, path: tuple[str, ...]) -> str:
    if name in region.children:
        return _id(path + ("__anchor",))
    return _id(path)


def _dot_region(region: Region, path: tuple[str, ...], out: list[str], pad: str) -> None:
    for name, node in region.nodes.items():
        p = path + (name,)
        if name in region.children:
            out.append(f"{pad}subgraph {_q('cluster_' + '.'.join(p))} {{")
            out.append(f"{pad}  label={_q(_actions_label(node))};  style=rounded;")  # type: ignore[arg-type]
            out.append(f"{pad}  {_id(p + ('__anchor',))} [shape=point, style=invis, width=0];")
            _dot_region(region.children[name], p, out, pad + "  ")
            out.append(f"{pad}}}")
        elif isinstance(node, ast.Initial):
            out.append(f"{pad}{_id(p)} [shape=point, width=0.15, label={_q(name)}];")
        elif isinstance(node, ast.Final):
            out.append(f"{pad}{_id(p)} [shape=doublecircle, width=0.2, label=\"\"];")
        elif isinstance(node, ast.Junction):
            out.append(f"{pad}{_id(p)} [shape=circle, width=0.25, label={_q(name)}, fontsize=9];")
        elif isinstance(node, ast.Probabilistic):
            out.append(f"{pad}{_id(p)} [shape=diamond, width=0.3, label=\"P\"];")
        else:
            out.append(f"{pad}{_id(p)} [label={_q(_actions_label(node))}];")  # type: ignore[arg-type]


# ---------------------------------------------------------------------------- Mermaid


class _Ids:
    """Mermaid ids: one per node path (s0, s1, ...), so names that only differ in nesting
    (a state `A_B` and a state `B` inside `A`) never merge; the label shows the name."""

    def __init__(self) -> None:
        self._ids: dict[tuple[str, ...], str] = {}

    def __call__(self, path: tuple[str, ...]) -> str:
        if path not in self._ids:
            self._ids[path] = f"s{len(self._ids)}"
        return self._ids[path]


def _mlabel(text: str) -> str:
    # Mermaid labels end at a newline and dislike ':' and ';' inside; use look-alikes.
    return text.replace(":", "\u2236").replace(";", "\uff1b").replace("\n", " ")


def mermaid(scope: MachineScope) -> str:
    assert scope.region is not None
    out = ["stateDiagram-v2", f"  %% {scope.kind} {scope.qname}"]
    _mermaid_region(scope.region, (), out, "  ", _Ids())
    out.append("")
    return "\n".join(out)


def _mermaid_region(region: Region, path: tuple[str, ...], out: list[str], pad: str, _mid: _Ids) -> None:
    for name, node in region.nodes.items():
        p = path + (name,)
        if isinstance(node, (ast.Junction, ast.Probabilistic)):
            out.append(f"{pad}state {_mid(p)} <<choice>>")
            out.append(f"{pad}note right of {_mid(p)} : {_mlabel(name)}")
        elif isinstance(node, ast.State):
            out.append(f"{pad}state \"{_mlabel(name)}\" as {_mid(p)}")
            for m in node.members:
                if isinstance(m, ast.StateAction):
                    out.append(f"{pad}{_mid(p)} : {_mlabel(f'{m.kind} / {stmt(m.stmt)}')}")
            if name in region.children:
                out.append(f"{pad}state {_mid(p)} {{")
                _mermaid_region(region.children[name], p, out, pad + "  ", _mid)
                out.append(f"{pad}}}")
    for t in region.transitions:
        src, dst = region.nodes.get(t.source), region.nodes.get(t.target)
        a = "[*]" if isinstance(src, ast.Initial) else _mid(path + (t.source,))
        b = "[*]" if isinstance(dst, ast.Final) else _mid(path + (t.target,))
        label = transition_label(t)
        out.append(f"{pad}{a} --> {b}" + (f" : {_mlabel(label)}" if label else ""))
