"""Shrunk failures as regression files, and reading them back.

A regression file is the shrunk model's text after a header of comments: the property it broke
and how, the seed of the model it was shrunk from, the generator's switches, the capacity of
collections, and the C and Python bodies of its user functions::

    // robogen fuzz regression: property package (compile), seed 1.17
    // features: default
    // capacity: 8
    // error: 'rg_rec_R2' undeclared (first use in this function)
    // function fn3 c: return a > b ? a : b;
    // function fn3 py: a if a > b else b

tests/fuzz/test_regressions.py runs every file of tests/fuzz/regressions through its property.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, replace
from pathlib import Path

from robogen.fuzz.exprs import UserFn
from robogen.fuzz.features import DEFAULT
from robogen.fuzz.model import Generated
from robogen.fuzz.properties import Budget, Failure, check_model, remove
from robogen.fuzz.shrink import shrink
from robogen.syntax import ast
from robogen.syntax.parser import parse_text

HEADER = "// robogen fuzz regression: property "


def _keep_functions(g: Generated, file: ast.File) -> tuple[UserFn, ...]:
    declared = {i.name for i in file.items if isinstance(i, ast.FunctionDef)}
    return tuple(f for f in g.functions if f.name in declared)


def shrink_failure(g: Generated, failure: Failure, budget: Budget, work: Path, seconds: float) -> Generated:
    """The smallest variant of ``g`` found in ``seconds`` that fails like ``failure``."""
    semantics = tuple(s for s in budget.semantics if failure.message.startswith(s)) or budget.semantics
    first = failure.message.splitlines()[0] if failure.message else ""
    focused = replace(budget, sanitize=failure.prop == "sanitize", semantics=semantics,
                      through=failure.prop if failure.prop in ("check", "package") else "sanitize",
                      build="code generation" not in first,
                      optimise=() if "(-O0)" in first else tuple(s for s in semantics if s in budget.optimise))
    count = [0]

    def fails(file: ast.File) -> bool:
        count[0] += 1
        candidate = replace(g, file=file, functions=_keep_functions(g, file))
        folder = work / f"v{count[0]}"
        try:
            return failure.same(check_model(candidate, folder, focused).failure)
        finally:
            remove(folder)

    small = shrink(g.file, fails, seconds=seconds)
    return replace(g, file=small, functions=_keep_functions(g, small))


def _features_line(on: frozenset[str]) -> str:
    added, removed = sorted(on - DEFAULT), sorted(DEFAULT - on)
    if not added and not removed:
        return "default"
    return " ".join([f"+{n}" for n in added] + [f"-{n}" for n in removed])


def _what(failure: Failure) -> str:
    """The failure in one line, without the paths of the folder it happened in."""
    lines = [x.strip() for x in failure.message.splitlines() if x.strip()] or [""]
    pick = next((x[x.index("error:"):] for x in lines if "error:" in x), lines[-1] if failure.kind == "internal" else lines[0])
    return re.sub(r"/\S*/", "", pick)[:200]


def text(g: Generated, failure: Failure, on: frozenset[str]) -> str:
    head = [f"{HEADER}{failure.prop} ({failure.kind}), seed {g.seed}",
            f"// features: {_features_line(on)}",
            f"// capacity: {g.capacity}",
            f"// failure: {_what(failure)}"]
    for f in g.functions:
        if f.c_body is not None:
            head += [f"// function {f.name} c: {f.c_body}", f"// function {f.name} py: {f.py}"]
    return "\n".join(head) + "\n" + g.text()


def write(folder: Path, g: Generated, failure: Failure, on: frozenset[str]) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    name = f"{failure.prop}_{failure.kind}_{g.seed.replace('.', '_').replace('-', 'm')}"
    path = folder / (name + (".rst" if g.language == "robosim" else ".rct"))
    path.write_text(text(g, failure, on), encoding="utf-8")
    return path


@dataclass
class Regression:
    path: Path
    prop: str
    kind: str
    seed: str
    generated: Generated


def read(path: Path) -> Regression:
    """A regression file as the model it holds."""
    source = path.read_text(encoding="utf-8")
    first = source.splitlines()[0]
    m = re.match(re.escape(HEADER) + r"(\w+) \((\w+)\), seed (\S+)", first)
    if m is None:
        raise ValueError(f"{path}: not a fuzz regression (the first line must start with '{HEADER}')")
    prop, kind, seed = m.groups()
    capacity = int(re.search(r"^// capacity: (\d+)", source, re.M).group(1))  # type: ignore[union-attr]
    bodies: dict[str, dict[str, str]] = {}
    for name, lang, body in re.findall(r"^// function (\w+) (c|py): (.*)$", source, re.M):
        bodies.setdefault(name, {})[lang] = body
    file = parse_text(source, str(path))
    functions = []
    for item in file.items:
        if isinstance(item, ast.FunctionDef) and item.name in bodies:
            functions.append(_function(item, bodies[item.name]))
    language = "robosim" if path.suffix == ".rst" else "robochart"
    return Regression(path, prop, kind, seed, Generated(seed, language, file, tuple(functions), capacity))


def _function(item: ast.FunctionDef, body: dict[str, str]) -> UserFn:
    from robogen.semantics import types as T

    def prim(t: ast.TypeExpr) -> T.Type:
        assert isinstance(t, ast.TypeRef)
        return T.PRIMITIVES[t.name.last]

    return UserFn(item.name, tuple((p.name, prim(p.type)) for p in item.params), prim(item.result), body["c"], body["py"])


def check(r: Regression, work: Path, budget: Budget | None = None) -> Failure | None:
    """Run the regression's model through its properties (property 5 too, if that is the one it
    broke): the failure, or None once the bug is fixed."""
    b = budget or Budget(sanitize=r.prop == "sanitize")
    return check_model(r.generated, work, b).failure


__all__ = ["shrink_failure", "write", "text", "read", "check", "Regression", "HEADER"]
