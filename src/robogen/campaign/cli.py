"""``robogen campaign CAMPAIGN.toml [-o DIR] [--workers N] [--scheduler ADDRESS] [--retries N] [--dry-run]``."""

from __future__ import annotations

import argparse
import sys


def _count(text: str, least: int) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not an integer") from None
    if value < least:
        raise argparse.ArgumentTypeError(f"must be at least {least}")
    return value


def configure(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("campaign", help="the campaign file (TOML, see docs/campaign-toml.md)")
    parser.add_argument("-o", "--output", metavar="DIR",
                        help="results folder (default: CAMPAIGN-results in the current folder); rerunning into "
                             "the same folder runs only what is missing")
    parser.add_argument("--workers", type=lambda t: _count(t, 1), metavar="N",
                        help="worker processes of the local cluster (default: the number of cores)")
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help="run on an existing Dask cluster (tcp://host:8786) instead of a local one")
    parser.add_argument("--retries", type=lambda t: _count(t, 0), default=2, metavar="N",
                        help="times a run is submitted again when its worker is lost (default 2)")
    parser.add_argument("--dry-run", action="store_true", help="check the campaign and list its runs; run nothing")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar even on a terminal")


def run(args: argparse.Namespace) -> int:
    from robogen.campaign.runner import run_campaign
    from robogen.diagnostics import UsageError

    if args.workers and args.scheduler:
        raise UsageError("robogen campaign: --workers sizes the local cluster; a cluster given by --scheduler has its own")
    result = run_campaign(args.campaign, args.output, workers=args.workers, scheduler=args.scheduler,
                          retries=args.retries, dry_run=args.dry_run, progress=False if args.no_progress else None,
                          echo=lambda line: print(line, file=sys.stderr if not args.dry_run else sys.stdout, flush=True))
    if result is None:
        return 0
    return 1 if result.counts.get("lost") else 0
