"""A workspace: every model file given to robogen, parsed, indexed by package, like a RoboTool
project. Imports and package-qualified names resolve across all its files.

Global name lookup for a simple name ``N`` used in a file of package ``P`` tries, in order:
the declarations of the file itself (Xtext resolves a resource's own elements before the global
index, so a name declared in the same file shadows its declarations in other files), those of
``P`` (in any file), the file's explicit imports (``import Q::N``), its
wildcard imports (``import Q::*``), declarations of files without a package (visible everywhere,
as in RoboTool), the built-in ``core`` package. As a last resort, a declaration of that simple
name anywhere in the workspace is used with a warning naming the import that is missing
(RoboTool's automatic translations rely on this); the toolkits' functions are not found that
way: as in RoboTool, they must be imported or qualified.

Each lookup asks for declarations of some kinds (a type, an interface, a function, ...) and
sees only those, as RoboTool's scopes do: a function ``real`` does not hide the type ``real``.
Functions and the other declarations are separate name spaces, so a function and a type of
one package may share a name. Like RoboTool, robogen only warns about an import that finds
nothing and about two declarations of one qualified name and kind (RoboTool's "is not unique",
which counts the declarations of one kind); a use takes the one of its own file, else the first.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterable, Sequence

from robogen.diagnostics import DiagnosticSink, Note, RobogenError, Span, did_you_mean, error
from robogen.semantics.toolkit import Builtin, library
from robogen.semantics.types import PRIMITIVES
from robogen.syntax import ast
from robogen.syntax.parser import EXTENSIONS, language_of, parse_file

TOP_LEVEL_KINDS = {
    ast.Interface: "interface",
    ast.Platform: "robotic platform",
    ast.GivenType: "type",
    ast.Record: "datatype",
    ast.Enumeration: "enumeration",
    ast.Controller: "controller",
    ast.StateMachine: "state machine",
    ast.OperationDef: "operation",
    ast.FunctionDef: "function",
    ast.Module: "module",
}
TYPE_DECLS = (ast.GivenType, ast.Record, ast.Enumeration)


@dataclass(eq=False)
class Decl:
    """A top-level declaration (or a built-in) registered in a package."""

    name: str
    package: str | None
    node: ast.Node | None
    file: ast.File | None
    builtin: Builtin | None = None
    primitive: str | None = None

    @property
    def qname(self) -> str:
        return f"{self.package}::{self.name}" if self.package else self.name

    @property
    def kind(self) -> str:
        if self.builtin is not None:
            return "function"
        if self.primitive is not None:
            return "type"
        return TOP_LEVEL_KINDS.get(type(self.node), type(self.node).__name__)

    @property
    def span(self) -> Span | None:
        return getattr(self.node, "name_span", None) if self.node is not None else None

    def is_a(self, kinds: tuple[type, ...]) -> bool:
        if self.primitive is not None:
            return ast.GivenType in kinds or ast.TypeRef in kinds
        if self.builtin is not None:
            return ast.FunctionDef in kinds
        return isinstance(self.node, kinds)


@dataclass
class Package:
    name: str | None
    decls: dict[str, list[Decl]] = field(default_factory=dict)

    def add(self, decl: Decl) -> None:
        self.decls.setdefault(decl.name, []).append(decl)


class Workspace:
    """The parsed files and their packages. ``root`` is the workspace root (see
    :func:`workspace_root`); by default the common folder of the files."""

    def __init__(self, files: Sequence[ast.File], sink: DiagnosticSink | None = None, root: str | None = None):
        self.files = list(files)
        self.sink = sink or DiagnosticSink()
        self.root = root if root is not None else workspace_root([os.path.dirname(f.path) for f in self.files])
        self.packages: dict[str | None, Package] = {}
        self.by_simple: dict[str, list[Decl]] = {}
        self._imports: dict[int, tuple[list[tuple[ast.Import, Decl]], list[tuple[ast.Import, Package]]]] = {}
        self._builtins()
        for f in self.files:
            self._index(f)
        self._check_duplicates()
        for f in self.files:
            self._resolve_imports(f)

    # -- construction

    def _builtins(self) -> None:
        core = self.packages.setdefault("core", Package("core"))
        for name in PRIMITIVES:
            core.add(Decl(name, "core", None, None, primitive=name))
        for pkg_name, functions in library().items():
            pkg = self.packages.setdefault(pkg_name, Package(pkg_name))
            for name, b in functions.items():
                pkg.add(Decl(name, pkg_name, None, None, builtin=b))

    def _index(self, f: ast.File) -> None:
        pkg_name = f.package.text if f.package else None
        pkg = self.packages.setdefault(pkg_name, Package(pkg_name))
        for item in f.items:
            if isinstance(item, ast.Named) and not isinstance(item, ast.Diagram):
                d = Decl(item.name, pkg_name, item, f)
                pkg.add(d)
                self.by_simple.setdefault(item.name, []).append(d)
                if isinstance(item, ast.Module):
                    # A module's inline platform and controllers are declarations of the package too
                    # (RoboTool lets other modules reference them).
                    for m in item.members:
                        if isinstance(m, (ast.Platform, ast.Controller)):
                            self.by_simple.setdefault(m.name, []).append(Decl(m.name, pkg_name, m, f))

    def _check_duplicates(self) -> None:
        """Two declarations of one qualified name and kind (two interfaces ``p::I``, in one file or
        two): a warning, as RoboTool's UniqueQualifiedName check gives (it counts the exported
        objects of one class; declarations of other kinds, a machine and a type of one name, do
        not clash there, and lookups ask for a kind). A use takes the one declared in its own
        file, else the first (see :meth:`lookup`)."""
        for pkg in self.packages.values():
            for name, decls in pkg.decls.items():
                by_kind: dict[type, list[Decl]] = {}
                for d in decls:
                    if d.node is not None:
                        by_kind.setdefault(type(d.node), []).append(d)
                for same in by_kind.values():
                    for d in same[1:]:
                        self.sink.warning(
                            f"'{name}' is not unique: {_article(d.kind)} of that name is declared twice in {_pkg_text(pkg.name)}; "
                            "a file that declares one uses its own, the other files the first", d.span,
                            Note(f"'{name}' is first declared here", same[0].span))

    def _resolve_imports(self, f: ast.File) -> None:
        singles: list[tuple[ast.Import, Decl]] = []
        wildcards: list[tuple[ast.Import, Package]] = []
        for imp in f.imports:
            parts = imp.name.parts
            if imp.wildcard:
                pkg = self.packages.get("::".join(parts))
                if pkg is None:
                    self.sink.warning(
                        f"no package '{imp.name.text}' in this workspace: the import brings nothing"
                        + did_you_mean(imp.name.text, self._package_names()),
                        imp.name.span,
                        Note("packages come from the 'package' line of the files given to robogen"),
                    )
                    continue
                wildcards.append((imp, pkg))
                continue
            if len(parts) < 2:
                self.sink.error(f"import '{imp.name.text}' must name a package and a declaration (pkg::Name or pkg::*)", imp.name.span)
                continue
            pkg_name, name = "::".join(parts[:-1]), parts[-1]
            pkg = self.packages.get(pkg_name)
            if pkg is None:
                self.sink.warning(
                    f"no package '{pkg_name}' in this workspace: the import brings nothing"
                    + did_you_mean(pkg_name, self._package_names()), imp.name.span
                )
                continue
            decls = pkg.decls.get(name)
            if not decls:
                self.sink.warning(
                    f"package '{pkg_name}' declares no '{name}': the import brings nothing" + did_you_mean(name, pkg.decls),
                    imp.name.span,
                )
                continue
            singles += [(imp, d) for d in decls]  # each kind of that name: a lookup asks for one
        self._imports[id(f)] = (singles, wildcards)

    def _package_names(self) -> list[str]:
        return [p for p in self.packages if p]

    # -- lookup

    def lookup(
        self,
        name: ast.Name,
        file: ast.File,
        kinds: tuple[type, ...],
        what: str,
        report: bool = True,
        sink: DiagnosticSink | None = None,
    ) -> Decl | None:
        """Resolve a global name to a declaration of one of ``kinds``; report problems at its span."""
        sink = sink or self.sink
        if name.qualified:
            pkg_name, simple = "::".join(name.parts[:-1]), name.last
            pkg = self.packages.get(pkg_name)
            if pkg is None:
                if report:
                    sink.error(f"unknown package '{pkg_name}' in '{name.text}'" + did_you_mean(pkg_name, self._package_names()), name.span)
                return None
            found = sorted((d for d in pkg.decls.get(simple, ()) if d.is_a(kinds)), key=lambda d: d.file is not file)
            if not found:
                if report:
                    other = pkg.decls.get(simple)
                    if other:
                        sink.error(f"'{name.text}' is {_article(other[0].kind)}, not {_article(what)}", name.span, Note("declared here", other[0].span))
                    else:
                        cands = [n for n, ds in pkg.decls.items() if any(d.is_a(kinds) for d in ds)]
                        sink.error(f"package '{pkg_name}' declares no {what} '{simple}'" + did_you_mean(simple, cands), name.span)
                return None
            return found[0]
        simple = name.last
        elsewhere: Decl | None = None  # a visible declaration of another kind, for the message
        for candidates in self._visible(simple, file):
            matching = _unique([d for d in candidates if d.is_a(kinds)])
            if len(matching) == 1 or (matching and _one_name(matching)):
                return matching[0]
            if len(matching) > 1:
                if report:
                    sink.error(
                        f"'{simple}' is ambiguous here: " + ", ".join(d.qname for d in matching),
                        name.span,
                        *(Note(f"'{d.qname}' is declared here", d.span) for d in matching),
                    )
                return matching[0]
            elsewhere = elsewhere or (candidates[0] if candidates else None)
        anywhere = _unique([d for d in self.by_simple.get(simple, []) if d.is_a(kinds)])
        if anywhere:
            return self._anywhere(anywhere, name, file, report, sink)
        if not report:
            return None
        if elsewhere is not None:
            sink.error(f"'{simple}' is {_article(elsewhere.kind)}, not {_article(what)}", name.span, Note("declared here", elsewhere.span))
            return None
        notes = [Note(f"'{d.qname}' is a toolkit function: add 'import {d.package}::*' (or '::{simple}') to the file")
                 for d in self._toolkit(simple, kinds)]
        sink.error(f"unknown {what} '{simple}'" + did_you_mean(simple, self._visible_names(file, kinds)), name.span, *notes)
        return None

    def _anywhere(self, anywhere: list[Decl], name: ast.Name, file: ast.File, report: bool, sink: DiagnosticSink) -> Decl | None:
        """The last resort: among the model's declarations of this simple name (``anywhere``),
        the one of the closest package, with a warning naming the import."""
        simple = name.last
        best = _closest_package(anywhere, file)
        if best is not None:
            if report:
                sink.warning(
                    f"'{simple}' is not imported here; using '{best.qname}'",
                    name.span,
                    Note(f"add 'import {best.package}::{simple}' (or '::*') to the file" if best.package else "declared here", best.span),
                )
            return best
        if report:
            sink.error(
                f"'{simple}' is not imported here, and several packages declare it: " + ", ".join(d.qname for d in anywhere),
                name.span,
            )
        return None

    def _toolkit(self, simple: str, kinds: tuple[type, ...]) -> list[Decl]:
        """The toolkit functions of this name (named in the message when one is not imported)."""
        return [d for pkg in library() for d in self.packages[pkg].decls.get(simple, []) if d.is_a(kinds)]

    def _visible(self, simple: str, file: ast.File) -> Iterable[list[Decl]]:
        pkg_name = file.package.text if file.package else None
        own = list(self.packages[pkg_name].decls.get(simple, ())) if pkg_name in self.packages else []
        yield [d for d in own if d.file is file]  # the file's own declarations shadow the others (Xtext's local scope)
        yield own
        singles, wildcards = self._imports.get(id(file), ([], []))
        yield [d for imp, d in singles if d.name == simple]
        yield [d for imp, pkg in wildcards for d in pkg.decls.get(simple, ())]
        if pkg_name is not None and None in self.packages:
            yield list(self.packages[None].decls.get(simple, ()))
        yield list(self.packages["core"].decls.get(simple, ()))

    def _visible_names(self, file: ast.File, kinds: tuple[type, ...]) -> list[str]:
        pkg_name = file.package.text if file.package else None
        names = []
        pkgs = [self.packages.get(pkg_name), self.packages.get(None), self.packages["core"]]
        singles, wildcards = self._imports.get(id(file), ([], []))
        pkgs += [p for _, p in wildcards]
        for pkg in pkgs:
            if pkg:
                names += [n for n, ds in pkg.decls.items() if any(d.is_a(kinds) for d in ds)]
        names += [d.name for _, d in singles if d.is_a(kinds)]
        return names

    def decls(self, kinds: tuple[type, ...]) -> list[Decl]:
        out = []
        for f in self.files:
            pkg_name = f.package.text if f.package else None
            for item in f.items:
                if isinstance(item, kinds):
                    out.append(Decl(item.name, pkg_name, item, f))  # type: ignore[attr-defined]
        return out


def _unique(decls: list[Decl]) -> list[Decl]:
    seen: list[Decl] = []
    for d in decls:
        if not any(d is s or (d.node is not None and d.node is s.node) for s in seen):
            seen.append(d)
    return seen


def _closest_package(decls: list[Decl], file: ast.File) -> Decl | None:
    """Among declarations of one simple name, the one whose package shares the longest prefix
    with the file's package; None if that does not single one out."""
    if len(decls) == 1:
        return decls[0]
    here = file.package.text if file.package else ""

    def common(d: Decl) -> int:
        there = d.package or ""
        n = 0
        for a, b in zip(here, there):
            if a != b:
                break
            n += 1
        return n

    scored = sorted(decls, key=common, reverse=True)
    if common(scored[0]) > common(scored[1]):
        return scored[0]
    return None


def _one_name(decls: list[Decl]) -> bool:
    """Are these one qualified name declared more than once? (a warning at the declarations of
    one kind; lookups use the first, as RoboTool links one of them)"""
    return all(d.node is not None for d in decls) and len({d.package for d in decls}) == 1


def _article(what: str) -> str:
    return f"an {what}" if what[:1] in "aeiou" else f"a {what}"


def _pkg_text(pkg: str | None) -> str:
    return f"package '{pkg}'" if pkg else "the files without a package"


# ---------------------------------------------------------------------------- loading


def collect_model_paths(paths: Sequence[str | os.PathLike], problems: DiagnosticSink | None = None, *,
                        empty_is_error: bool = False) -> list[str]:
    """Files given directly, plus every .rct/.rst/.rsim file below each directory (sorted).
    Missing paths and non-model files are reported to ``problems`` (raised if not given). A
    directory without a model file is an empty project, which RoboTool loads without complaint:
    a warning, located at the directory; ``empty_is_error``: an error (``robogen check``, whose
    caller would otherwise believe its models checked)."""
    found: list[str] = []
    own = problems is None
    problems = problems if problems is not None else DiagnosticSink()
    for p in paths:
        path = Path(p)
        if path.is_dir():
            inside = sorted(str(q) for q in path.rglob("*") if q.suffix.lower() in EXTENSIONS and q.is_file())
            if not inside:
                (problems.error if empty_is_error else problems.warning)(
                    f"no model files (.rct, .rst, .rsim) in directory {path}", Span.of_path(str(path)))
            found += inside
        elif path.is_file():
            if language_of(path) is None:
                problems.error(f"not a model file: {path} (expected a .rct (RoboChart), .rst or .rsim (RoboSim) file)", None)
            else:
                found.append(str(path))
        elif path.exists():
            problems.error(f"{path} is neither a file nor a directory", None)
        else:
            problems.error(f"no such file or directory: {path}", None)
    if own:
        problems.raise_if_errors()
    # one copy of each file, in a stable order
    unique: list[str] = []
    seen: set[str] = set()
    for f in found:
        key = os.path.realpath(f)
        if key not in seen:
            seen.add(key)
            unique.append(f)
    return unique


def workspace_root(paths: Sequence[str | os.PathLike]) -> str:
    """The workspace root: the deepest folder holding every path robogen was given (a file's
    folder, a directory itself), as an absolute path. Generated files name model files relative
    to it, so `robogen compile models/ur5e/ur5e.rst` names ``ur5e.rst`` from any current folder
    and in any checkout, and a workspace given as a directory names its files from there."""
    folders = [os.path.abspath(p if os.path.isdir(p) else os.path.dirname(p) or os.curdir) for p in paths]
    return os.path.commonpath(folders) if folders else os.path.abspath(os.curdir)


def load(paths: Sequence[str | os.PathLike], sink: DiagnosticSink | None = None, *, empty_is_error: bool = False) -> Workspace:
    """Parse every model under ``paths`` into one workspace; syntax errors of a file are recorded
    in the sink and that file is left out, so the other files are still checked
    (``empty_is_error``: see :func:`collect_model_paths`)."""
    sink = sink or DiagnosticSink()
    files = []
    for path in collect_model_paths(paths, sink, empty_is_error=empty_is_error):
        try:
            files.append(parse_file(path))
        except RobogenError as exc:
            sink.extend(exc.diagnostics)
        else:
            sink.extend(files[-1].notices)
    return Workspace(files, sink, workspace_root(paths))


def from_texts(texts: dict[str, str], sink: DiagnosticSink | None = None) -> Workspace:
    """A workspace from in-memory files (path -> text), for tests and tools."""
    from robogen.syntax.parser import parse_text

    sink = sink or DiagnosticSink()
    files = []
    for path, text in texts.items():
        try:
            files.append(parse_text(text, path))
        except RobogenError as exc:
            sink.extend(exc.diagnostics)
        else:
            sink.extend(files[-1].notices)
    return Workspace(files, sink, workspace_root(list(texts)))


__all__ = ["Decl", "Package", "Workspace", "load", "from_texts", "collect_model_paths", "workspace_root", "TYPE_DECLS", "error"]
