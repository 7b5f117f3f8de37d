"""`robogen package MODEL...|SOURCE_DIR -o NAME.fmu [--platforms LIST]`: compile a model (or the
sources `robogen compile` wrote) into a binary per platform and zip a validated FMI 3.0 FMU."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from robogen.codegen.api import build_fmu, package_model
from robogen.codegen.cli import add_model_options, codegen_options_from, options_from, print_warnings
from robogen.fmu.platforms import BUILT, HOST, select


def configure(p: argparse.ArgumentParser) -> None:
    p.add_argument("paths", nargs="+", metavar="MODEL|SOURCE_DIR",
                   help="model files/directories, or one folder written by `robogen compile`")
    add_model_options(p)
    p.add_argument("-o", "--output", metavar="NAME.fmu", required=True, help="the FMU to write")
    add_platforms_option(p)
    p.add_argument("--no-validate", action="store_true", help="skip `robogen validate` of the result")


def add_platforms_option(p: argparse.ArgumentParser) -> None:
    p.add_argument("--platforms", metavar="LIST", default=HOST.name,
                   help=f"FMI 3.0 platform tuples to build a binary for, comma-separated, or all "
                        f"({', '.join(b.name for b in BUILT)}; default {HOST.name}). {HOST.name} uses the system C "
                        "compiler, the others zig (pip install 'robogen[cross]')")


def _is_source_dir(paths: list[str]) -> bool:
    return len(paths) == 1 and Path(paths[0]).is_dir() and (Path(paths[0]) / "sources" / "buildDescription.xml").is_file()


def run(args: argparse.Namespace) -> int:
    platforms = select(args.platforms)
    if _is_source_dir(args.paths):
        target = build_fmu(args.paths[0], args.output, platforms=platforms, validate=not args.no_validate)
    else:
        target, compiled = package_model(args.paths, args.output, module=args.module, machine=args.machine,
                                         options=options_from(args), codegen=codegen_options_from(args),
                                         platforms=platforms, validate=not args.no_validate)
        print_warnings(compiled.fmu, args)
    shown = "" if platforms == (HOST,) else f" for {', '.join(p.name for p in platforms)}"
    print(f"wrote {target}{shown}" + ("" if args.no_validate else " (valid)"), file=sys.stderr)
    return 0
