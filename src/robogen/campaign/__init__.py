"""Campaigns: many co-simulations of one system over a parameter space, on Dask.

Python API::

    from robogen.campaign import run_campaign
    result = run_campaign("examples/ur5e/campaign.toml", "build/ur5e/campaign", workers=2)
    result.counts           # {"ok": 1530, "failed": 6}
    result.folder           # runs.parquet, runs.csv, summary.md, summary.png, journal.jsonl

``run_campaign(path, out=None, *, workers=None, scheduler=None, retries=2, dry_run=False,
progress=None, echo=print) -> CampaignResult | None`` (None for a dry run).

The campaign file is documented in docs/campaign-toml.md, the execution model and its limits in
docs/scale-out.md. The stages: :mod:`~robogen.campaign.spec` (the file),
:mod:`~robogen.campaign.space` (expansion), :mod:`~robogen.campaign.plan` (resolution, checks,
hashes), :mod:`~robogen.campaign.engine` (Dask), :mod:`~robogen.campaign.worker` and
:mod:`~robogen.campaign.isolate` (one process per run), :mod:`~robogen.campaign.child` (the run),
:mod:`~robogen.campaign.metrics`, :mod:`~robogen.campaign.journal` (resuming),
:mod:`~robogen.campaign.results`, :mod:`~robogen.campaign.report` and
:mod:`~robogen.campaign.figure` (what is written).
"""

from robogen.campaign.runner import CampaignResult, run_campaign
from robogen.campaign.spec import load_campaign

__all__ = ["run_campaign", "load_campaign", "CampaignResult"]
