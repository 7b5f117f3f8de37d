"""Models to FMUs, cached by content: a second run with an unchanged model does no compiling.

:func:`model_fmu` packages a model (the options of ``robogen package``) into the cache folder,
``$ROBOGEN_CACHE`` or ``$XDG_CACHE_HOME/robogen/fmus`` (``~/.cache/robogen/fmus``), under the
SHA-256 of everything the FMU depends on: the text of every model file (a folder: every
``.rct``, ``.rst`` and ``.rsim`` below it) and of ``--functions``, the options, robogen's own
sources (its front end, generator, templates and runtime) and the C compiler named by ``$CC``.
An FMU is written under a temporary name and renamed, so concurrent runs never read half a file.
"""

from __future__ import annotations

import argparse
import hashlib
import os
import tempfile
import time
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Sequence

from robogen.codegen.api import package_model
from robogen.codegen.cli import add_model_options, codegen_options_from, options_from
from robogen.diagnostics import Note, RobogenError, Span, did_you_mean

MODEL_SUFFIXES = (".rct", ".rst", ".rsim")
#: What of robogen an FMU depends on: the stages up to the archive.
_STAGES = ("syntax", "semantics", "ir", "codegen", "templates", "runtime", "fmu")


@dataclass(frozen=True)
class Built:
    fmu: Path
    compiled: bool  # False: taken from the cache (or given)
    seconds: float
    warnings: tuple = ()
    given: bool = False  # an FMU given as the model: not built here


def cache_dir() -> Path:
    explicit = os.environ.get("ROBOGEN_CACHE")
    if explicit:
        return Path(explicit)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "robogen" / "fmus"


def model_parser() -> argparse.ArgumentParser:
    """The options of ``robogen package`` that give an FMU its meaning (for [options] of a scenario)."""
    parser = _Parser(prog="[options]", add_help=False)
    add_model_options(parser)
    return parser


class _Parser(argparse.ArgumentParser):
    def error(self, message: str):  # type: ignore[override]
        raise ValueError(message)


def options_argv(options: dict, span_of) -> list[str]:
    """A scenario's ``[options]`` table as the command-line options of ``robogen package``:
    ``semantics = "stepwise"`` is ``--semantics stepwise``, ``no_line_comments = true`` is
    ``--no-line-comments``, ``set = { c = 2 }`` is ``--set c=2``."""
    known = vars(parse_options([], None))
    argv: list[str] = []
    for key, value in options.items():
        dest = key.replace("-", "_")
        if dest not in known:
            raise RobogenError.at(f"unknown option '{key}'{did_you_mean(dest, known)}", span_of(key),
                                  Note("[options] takes the options of 'robogen package', without the dashes"))
        flag = "--" + dest.replace("_", "-")
        if dest == "set":
            if not isinstance(value, dict):
                raise RobogenError.at("'set' must be a table of constant = value", span_of(key))
            argv += [a for name, v in value.items() for a in (flag, f"{name}={_text(v)}")]
        elif isinstance(value, bool):
            argv += [flag] if value else []
        else:
            argv += [flag, _text(value)]
    return argv


def _text(value) -> str:
    return ("true" if value else "false") if isinstance(value, bool) else str(value)


def parse_options(argv: Sequence[str], span: Span | None) -> argparse.Namespace:
    try:
        return model_parser().parse_args(list(argv))
    except ValueError as exc:
        raise RobogenError.at(f"bad option: {exc}", span) from None


@cache
def _robogen_fingerprint() -> str:
    root = Path(__file__).resolve().parents[1]
    h = hashlib.sha256()
    for stage in _STAGES:
        for path in sorted((root / stage).rglob("*")):
            if path.is_file() and "__pycache__" not in path.parts:
                h.update(path.relative_to(root).as_posix().encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()


def model_files(paths: Sequence[str | os.PathLike]) -> list[Path]:
    files = []
    for p in map(Path, paths):
        if p.is_dir():
            files += sorted(f for f in p.rglob("*") if f.suffix in MODEL_SUFFIXES and f.is_file())
        else:
            files.append(p)
    return files


def fmu_key(paths: Sequence[str | os.PathLike], args: argparse.Namespace) -> str:
    """The cache key of the FMU of ``paths`` built with ``args`` (the options of ``robogen package``)."""
    h = hashlib.sha256(_robogen_fingerprint().encode())
    for f in model_files(paths):
        try:
            h.update(f.name.encode() + b"\0" + f.read_bytes() + b"\0")
        except OSError:
            h.update(f"missing {f}".encode())  # the build reports it
    known = vars(parse_options([], None))
    options = {k: v for k, v in sorted(vars(args).items()) if k in known}
    h.update(repr(options).encode())
    if args.functions and Path(args.functions).is_file():
        h.update(Path(args.functions).read_bytes())
    h.update(os.environ.get("CC", "cc").encode())
    return h.hexdigest()[:32]


def model_fmu(paths: Sequence[str | os.PathLike], args: argparse.Namespace) -> Built:
    """The FMU of the model at ``paths``: from the cache, or packaged into it."""
    started = time.perf_counter()
    folder = cache_dir()
    target = folder / f"{fmu_key(paths, args)}.fmu"
    if target.is_file():
        return Built(target, False, time.perf_counter() - started)
    folder.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=folder, prefix=".build-") as tmp:
        made, compiled = package_model([str(p) for p in paths], Path(tmp) / "model.fmu", module=args.module,
                                       machine=args.machine, options=options_from(args), codegen=codegen_options_from(args))
        os.replace(made, target)
    return Built(target, True, time.perf_counter() - started, tuple(compiled.fmu.warnings))
