"""``robogen export-ssp SYSTEM -o SYSTEM.ssp``: a system (a system file, or an SSP) written as an
SSP 2.0 archive with its FMUs (:mod:`robogen.cosim.ssp_write`, docs/ssp.md).

Exit status: 0 the archive is written; 1 a problem in the system or its FMUs (located, nothing
written). Warnings (parameter values an SSP binds to nothing) go to standard error.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from robogen.diagnostics import Diagnostic, SourceMap, render


def configure(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("system", help="the system: a system file (TOML, docs/system-toml.md) or an SSP (.ssp, .ssd)")
    parser.add_argument("-o", "--output", help="the SSP archive to write (default: build/SYSTEM.ssp, under the working directory)")


def run(args: argparse.Namespace) -> int:
    from robogen.cosim.ssp_write import export_ssp

    def warn(d: Diagnostic) -> None:
        print(render(d, SourceMap()), file=sys.stderr)

    output = Path(args.output) if args.output else Path("build") / f"{Path(args.system).stem}.ssp"
    written = export_ssp(args.system, output, warn)
    print(f"wrote {written}", file=sys.stderr)
    return 0
