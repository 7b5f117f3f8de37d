"""The parameter space of a campaign, expanded into the list of runs.

The space is the product of its parts, each optional: the explicit cases (one dimension, in
file order), the grid (the cartesian product of its lists, the first parameter varying slowest)
and the random samples (``samples`` draws of every random parameter). A run is one assignment
``name -> value``; runs are numbered in that order, which is the order of the results table.

Random draws come from one ``numpy.random.Generator`` (PCG64) seeded with ``seed``: draw i
takes the parameters in file order, so a campaign expands to the same runs on every machine.
"""

from __future__ import annotations

import itertools

import numpy as np

from robogen.campaign.spec import Campaign, Distribution, Value


def draw(dist: Distribution, rng: np.random.Generator) -> Value:
    if dist.kind == "uniform":
        return float(rng.uniform(*dist.args))
    if dist.kind == "normal":
        return float(rng.normal(*dist.args))
    return dist.args[int(rng.integers(len(dist.args)))]


def expand(campaign: Campaign) -> list[dict[str, Value]]:
    """Every run's assignment, in table order."""
    cases = campaign.cases or [{}]
    names = list(campaign.grid)
    grid = [dict(zip(names, point)) for point in itertools.product(*campaign.grid.values())]
    rng = np.random.Generator(np.random.PCG64(campaign.seed))
    samples = [{name: draw(d, rng) for name, d in campaign.random.items()} for _ in range(campaign.samples)] or [{}]
    return [{**case, **point, **sample} for case in cases for point in grid for sample in samples]
