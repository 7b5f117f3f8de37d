"""`robogen package MODEL...|SOURCE_DIR -o NAME.fmu`: compile a model (or the sources `robogen
compile` wrote) with the system C compiler and zip a validated FMI 3.0 FMU."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from robogen.codegen.api import build_fmu, package_model
from robogen.codegen.cli import add_model_options, codegen_options_from, options_from, print_warnings


def configure(p: argparse.ArgumentParser) -> None:
    p.add_argument("paths", nargs="+", metavar="MODEL|SOURCE_DIR",
                   help="model files/directories, or one folder written by `robogen compile`")
    add_model_options(p)
    p.add_argument("-o", "--output", metavar="NAME.fmu", required=True, help="the FMU to write")
    p.add_argument("--no-validate", action="store_true", help="skip `robogen validate` of the result")


def _is_source_dir(paths: list[str]) -> bool:
    return len(paths) == 1 and Path(paths[0]).is_dir() and (Path(paths[0]) / "sources" / "buildDescription.xml").is_file()


def run(args: argparse.Namespace) -> int:
    if _is_source_dir(args.paths):
        target = build_fmu(args.paths[0], args.output, validate=not args.no_validate)
    else:
        target, compiled = package_model(args.paths, args.output, module=args.module, machine=args.machine,
                                  options=options_from(args), codegen=codegen_options_from(args),
                                  validate=not args.no_validate)
        print_warnings(compiled.fmu, args)
    print(f"wrote {target}" + ("" if args.no_validate else " (valid)"), file=sys.stderr)
    return 0
