"""The ``robogen`` command. Thin: each subcommand lives next to the stage it drives.

A subcommand module defines ``configure(parser)`` (adds its arguments) and ``run(args) -> int``.
Exit codes: 0 success, 1 problems in the input (models, system files, FMUs), 2 usage errors,
3 internal errors (a bug in robogen; the message names the model location being processed),
4 a simulation that ended before its stop time because an FMU asked to terminate.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
import traceback
from typing import Sequence

from robogen import __version__
from robogen.diagnostics import RobogenError, SourceMap, UsageError, current_location, render_all

EXIT_OK, EXIT_INPUT, EXIT_USAGE, EXIT_INTERNAL = 0, 1, 2, 3

# name -> (module, one-line help). Order is the order of `robogen --help`.
COMMANDS: dict[str, tuple[str, str]] = {
    "check": ("robogen.semantics.cli", "parse, resolve and check RoboChart/RoboSim models"),
    "graph": ("robogen.semantics.graph", "draw state machines as Graphviz dot or Mermaid"),
    "compile": ("robogen.codegen.cli", "generate the C sources of an FMI 3.0 FMU from a model"),
    "package": ("robogen.codegen.package_cli", "compile and zip a model (or generated sources) into an .fmu"),
    "validate": ("robogen.fmu.validate_cli", "check an .fmu against the FMI 3.0 schema and robogen's clock rules"),
    "package-py": ("robogen.pyfmu.cli", "package a Python class as an FMI 3.0 FMU (cffi embedding)"),
    "simulate": ("robogen.scenarios.simulate_cli", "co-simulate a system of FMI 3.0 FMUs described in TOML or SSP, "
                 "or a model driven by a scenario"),
    "export-ssp": ("robogen.cosim.ssp_cli", "write a system as an SSP 2.0 archive with its FMUs"),
    "scenario": ("robogen.scenarios.template", "write a commented skeleton of a scenario for a model or an FMU"),
    "test": ("robogen.scenarios.runner", "run scenarios with expectations as tests (pass/fail lines, JUnit XML)"),
    "plot": ("robogen.cosim.plot", "plot a results CSV written by 'robogen simulate'"),
    "campaign": ("robogen.campaign.cli", "run many co-simulations over a parameter space on Dask"),
}


class _Parser(argparse.ArgumentParser):
    """argparse that raises UsageError instead of exiting, so main() owns the exit code."""

    def error(self, message: str):  # type: ignore[override]
        raise UsageError(f"{self.prog}: {message}")


def build_parser(selected: str | None = None) -> argparse.ArgumentParser:
    """The parser; only ``selected``'s module is imported (to add its arguments), so a command
    never pays for, or depends on, the other stages."""
    parser = _Parser(
        prog="robogen",
        description="RoboChart/RoboSim models to FMI 3.0 co-simulation FMUs, and a clock-aware master.",
    )
    parser.add_argument("--version", action="version", version=f"robogen {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name, (module_name, help_text) in COMMANDS.items():
        p = sub.add_parser(name, help=help_text, description=help_text)
        p.set_defaults(command_module=module_name)
        if name == selected:
            module = _load(module_name)
            if module is not None:
                module.configure(p)
    return parser


def _load(module_name: str):
    try:
        return importlib.import_module(module_name)
    except ModuleNotFoundError as exc:
        if exc.name == module_name:
            return None
        raise


def _selected(argv: Sequence[str]) -> str | None:
    """The subcommand named on the command line (the first argument that is not an option)."""
    for arg in argv:
        if not arg.startswith("-"):
            return arg if arg in COMMANDS else None
    return None


def main(argv: Sequence[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    try:
        parser = build_parser(_selected(argv))
        args = parser.parse_args(argv)
        if not getattr(args, "command", None):
            parser.print_help()
            return EXIT_USAGE
        module = _load(args.command_module)
        if module is None:
            raise UsageError(f"robogen {args.command}: not available in this installation")
        return int(module.run(args) or 0)
    except UsageError as exc:
        print(exc, file=sys.stderr)
        return EXIT_USAGE
    except RobogenError as exc:
        print(render_all(exc.diagnostics, SourceMap()), file=sys.stderr)
        return EXIT_INPUT
    except KeyboardInterrupt:
        print("robogen: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return EXIT_OK
    except Exception as exc:  # a bug in robogen: say so, with where it was working
        where = current_location()
        at = f" while processing {where}" if where else ""
        print(f"robogen: internal error{at}: {type(exc).__name__}: {exc}", file=sys.stderr)
        if os.environ.get("ROBOGEN_DEBUG"):
            traceback.print_exc()
        else:
            print("(set ROBOGEN_DEBUG=1 for the Python traceback)", file=sys.stderr)
        return EXIT_INTERNAL


if __name__ == "__main__":
    sys.exit(main())
