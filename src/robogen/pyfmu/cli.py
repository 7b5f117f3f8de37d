"""``robogen package-py MODULE:CLASS -o NAME.fmu [--set NAME=VALUE ...] [--platforms LIST]``."""

from __future__ import annotations

import argparse
import sys
import time

from robogen.fmu.platforms import HOST, select
from robogen.pyfmu.build import package


def configure(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("spec", metavar="MODULE:CLASS",
                        help="the robogen.pyfmu.Model subclass, e.g. robogen.platforms.ur5e:UR5ePlatform")
    parser.add_argument("-o", "--output", required=True, metavar="NAME.fmu", help="the FMU to write")
    parser.add_argument("--set", dest="settings", action="append", default=[], metavar="NAME=VALUE",
                        help="a packaging-time setting of the class (repeatable), e.g. sample_period=0.5")
    parser.add_argument("--model-identifier", metavar="ID",
                        help="the modelIdentifier (default: the class's model_identifier, else the output's stem)")
    parser.add_argument("--platforms", metavar="LIST", default=HOST.name,
                        help=f"platform tuples to build for; a Python FMU embeds this machine's CPython, so only "
                             f"{HOST.name} (the default)")


def run(args: argparse.Namespace) -> int:
    started = time.perf_counter()
    result = package(args.spec, args.output, args.settings, args.model_identifier, platforms=select(args.platforms))
    print(f"wrote {result.path} (modelIdentifier {result.model_identifier}, "
          f"{time.perf_counter() - started:.2f} s)", file=sys.stderr)
    return 0
