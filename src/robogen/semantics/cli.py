"""`robogen check PATH...`: parse, resolve and check models; report every problem at once.

The diagnostics go to standard error; the summary line (``checked N files: ...``), the command's
result, to standard output."""

from __future__ import annotations

import argparse
import sys

from robogen.diagnostics import SourceMap, render
from robogen.semantics import check_paths


def configure(p: argparse.ArgumentParser) -> None:
    p.add_argument("paths", nargs="+", metavar="PATH", help="model files (.rct, .rst, .rsim) and/or directories searched recursively")
    p.add_argument("-w", "--no-warnings", action="store_true", help="report errors only")
    p.add_argument("--werror", action="store_true", help="treat warnings as errors (exit 1 if any)")


def run(args: argparse.Namespace) -> int:
    model = check_paths(args.paths, empty_is_error=True)  # a script would believe an empty folder's models checked
    sources = SourceMap()
    shown = [d for d in model.diagnostics if d.is_error or not args.no_warnings]
    for d in shown:
        print(render(d, sources), file=sys.stderr)
    # files that did not load count too; a folder (a span of the path alone, line 0) does not
    n_files = len(model.files) + len({d.span.path for d in model.errors if d.span and d.span.line} - {f.path for f in model.files})
    errors, warnings = len(model.errors), len(model.warnings)
    print(
        f"checked {n_files} file{'s' if n_files != 1 else ''}: "
        f"{errors} error{'s' if errors != 1 else ''}, {warnings} warning{'s' if warnings != 1 else ''}"
    )
    if errors or (args.werror and warnings):
        return 1
    return 0
