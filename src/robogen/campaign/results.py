"""The campaign's tables: ``runs.parquet`` (and ``runs.csv``), and per-run time series.

One row per run, in the order the space expands to: ``run`` (its number), ``id`` (the first 12
hex digits of its specification hash), one column per parameter, one per metric, then
``status`` (ok, terminated, failed, lost), ``error``, ``end_time`` (simulated time reached),
``wall_time`` (seconds, on the worker, process start to result) and ``worker``. Everything but
the last two is the same whichever worker ran which run, so tables of the same campaign on one
worker and on many are equal once ``wall_time`` and ``worker`` are dropped.
"""

from __future__ import annotations

from pathlib import Path

import pyarrow as pa
import pyarrow.csv
import pyarrow.parquet as pq

from robogen.campaign.plan import CampaignPlan
from robogen.outputs import replacing

#: Columns that depend on where and when a run executed.
PLACEMENT = ("wall_time", "worker")
STATUS = ("status", "error", "end_time")


def _column(values: list) -> pa.Array:
    """An Arrow column of Python values; a column mixing kinds (numbers and names) is text."""
    try:
        return pa.array(values)
    except (pa.ArrowInvalid, pa.ArrowTypeError, TypeError):
        return pa.array([None if v is None else str(v) for v in values], type=pa.string())


def metric_names(plan: CampaignPlan, rows: list[dict]) -> list[str]:
    """Built-in metrics in declaration order, with each user metric's columns in its place
    (names in the order they first appear, in run order)."""
    names: list[str] = []
    builtins = {m.name for m in plan.campaign.metrics if m.kind != "function"}
    for metric in plan.campaign.metrics:
        if metric.kind != "function":
            names.append(metric.name)
            continue
        for row in rows:
            for name in (row.get("metrics") or {}):
                if name not in names and name not in builtins:
                    names.append(name)
    return names


def table(plan: CampaignPlan, rows: list[dict]) -> pa.Table:
    """The runs table; ``rows[i]`` is the row of ``plan.runs[i]``."""
    params = list(plan.campaign.targets)
    metrics = metric_names(plan, rows)
    columns: dict[str, list] = {"run": [r.index for r in plan.runs], "id": [r.id for r in plan.runs]}
    for name in params:
        columns[name] = [r.values.get(name) for r in plan.runs]
    for name in metrics:
        columns[name] = [(row.get("metrics") or {}).get(name) for row in rows]
    for name in (*STATUS, *PLACEMENT):
        columns[name] = [row.get(name) for row in rows]
    return pa.table({name: _column(values) for name, values in columns.items()})


def write_tables(runs: pa.Table, folder: Path) -> tuple[Path, Path]:
    parquet, csv = folder / "runs.parquet", folder / "runs.csv"
    with replacing(parquet) as tmp:
        pq.write_table(runs, tmp)
    with replacing(csv) as tmp:
        pyarrow.csv.write_csv(runs, tmp)
    return parquet, csv


def write_series(columns: list[str], rows: list[list], path: Path) -> Path:
    """One run's time series as Parquet: the columns of ``robogen simulate``'s CSV."""
    data = {name: _column([row[i] for row in rows]) for i, name in enumerate(columns)}
    path.parent.mkdir(parents=True, exist_ok=True)
    with replacing(path) as tmp:
        pq.write_table(pa.table(data), tmp)
    return path
