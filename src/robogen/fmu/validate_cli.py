"""``robogen validate NAME.fmu ...``: the FMI 3.0 XSD, fmpy's checks and robogen's clock rules."""

from __future__ import annotations

import argparse
import sys

from robogen.diagnostics import SourceMap, Summary, render_all


def configure(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("fmus", nargs="+", metavar="NAME.fmu", help="FMU archives to check")
    parser.add_argument("--quiet", action="store_true", help="print only problems, no summary line")


def run(args: argparse.Namespace) -> int:
    from robogen.fmu.validate import validate_fmu_texts

    failed = False
    for fmu in args.fmus:
        diagnostics, texts = validate_fmu_texts(fmu)
        summary = Summary(errors=sum(d.is_error for d in diagnostics), warnings=sum(not d.is_error for d in diagnostics))
        if diagnostics:
            print(render_all(diagnostics, SourceMap(texts)), file=sys.stderr)
        if not args.quiet:
            print(f"{fmu}: {summary.line()}", file=sys.stderr)
        failed = failed or summary.errors > 0
    return 1 if failed else 0
