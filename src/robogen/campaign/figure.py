"""The summary figure: a metric against one or two parameters (heat map, lines or scatter).

What is drawn comes from ``[figure]`` (docs/campaign-toml.md) or, without it, from the
campaign: the first numeric metric against the first parameter that varies (lines), or against
the first two (a heat map when both take few values, else a scatter coloured by the metric).

- heat map: one cell per (x, y), coloured by the mean of the metric over the runs in it; cells
  where the ``where`` metric is false for every run are hatched grey ("not WHERE"), cells whose
  runs all failed are red, cells without a value are white (outlined); one panel per ``facet``
  value, one colour scale for all;
- lines: the metric's mean against x, one line per ``series`` value (each its own marker and
  dashes, so that lines that coincide stay visible), the band from min to max (random samples
  fall in the band);
- scatter: x against the metric, or x against y coloured by the metric.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from robogen.campaign.spec import Figure

MAX_HEATMAP_VALUES = 60


@dataclass
class Choice:
    metrics: tuple[str, ...]
    x: str
    y: str | None
    facet: str | None
    series: str | None
    kind: str
    where: str | None


def _numeric(values: list) -> bool:
    present = [v for v in values if v is not None]
    return bool(present) and all(isinstance(v, (int, float)) for v in present)


def choose(figure: Figure | None, records: list[dict], params: list[str], metrics: list[str]) -> Choice | None:
    """What to draw, or None when the campaign has no numeric metric or no varying parameter."""
    varying = [p for p in params if len({r[p] for r in records}) > 1]
    if figure is not None:
        x, y = figure.x, figure.y
        kind = figure.kind or _default_kind(records, x, y)
        return Choice(figure.metrics, x, y, figure.facet, figure.series, kind, figure.where)
    numeric = [m for m in metrics if _numeric([r.get(m) for r in records])]
    if not numeric or not varying:
        return None
    x = varying[0]
    y = varying[1] if len(varying) > 1 else None
    return Choice((numeric[0],), x, y, None, None, _default_kind(records, x, y), None)


def _default_kind(records: list[dict], x: str, y: str | None) -> str:
    few = all(len({r[a] for r in records}) <= MAX_HEATMAP_VALUES for a in (x, y) if a)
    if y is None:
        return "line" if few else "scatter"
    return "heatmap" if few else "scatter"


def _value(v) -> float:
    """A metric as a number (a boolean as 0 or 1); NaN for none or a name."""
    if v is None or isinstance(v, str):
        return math.nan
    return float(v)


def sorted_values(records: list[dict], name: str) -> list:
    values = {r[name] for r in records if r[name] is not None}
    try:
        return sorted(values)
    except TypeError:
        return sorted(values, key=str)


def _panels(choice: Choice, records: list[dict]) -> list[tuple[str, str, list[dict]]]:
    """(title, metric, records) per panel: every metric, times every facet value."""
    facets = sorted_values(records, choice.facet) if choice.facet else [None]
    panels = []
    for metric in choice.metrics:
        for value in facets:
            subset = [r for r in records if choice.facet is None or r[choice.facet] == value]
            title = metric if value is None else f"{metric}, {choice.facet} = {value}"
            panels.append((title, metric, subset))
    return panels


def draw(choice: Choice, records: list[dict], path: Path, title: str) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = _panels(choice, records)
    ncols = math.ceil(math.sqrt(len(panels)))
    nrows = math.ceil(len(panels) / ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(5.2 * ncols + 0.8, 4.2 * nrows), squeeze=False,
                             layout="constrained")
    shared = len(choice.metrics) == 1  # one colour scale for every panel, else one per panel
    artist = None
    for ax, (panel_title, metric, subset) in zip(axes.flat, panels):
        ax.set_title(panel_title, fontsize=10)
        limits = _limits(records, metric)
        if choice.kind == "heatmap":
            artist = _heatmap(ax, choice, metric, subset, records, limits) or artist
        elif choice.kind == "line":
            _lines(ax, choice, metric, subset)
        else:
            artist = _scatter(ax, choice, metric, subset, limits) or artist
        if artist is not None and not shared:
            fig.colorbar(artist, ax=ax, label=metric)
            artist = None
    for ax in list(axes.flat)[len(panels):]:
        ax.set_visible(False)
    if artist is not None:
        fig.colorbar(artist, ax=axes.ravel().tolist(), shrink=0.8, label=choice.metrics[0])
    fig.suptitle(title)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _limits(records: list[dict], metric: str) -> tuple[float, float] | tuple[None, None]:
    """The colour range of a metric over the whole campaign (so that panels compare)."""
    values = [v for v in (_value(r.get(metric)) for r in records) if not math.isnan(v)]
    return (min(values), max(values)) if values else (None, None)


def _cell_stats(runs: list[dict], metric: str, where: str | None) -> tuple[float, str]:
    """(mean metric, state) of one heat-map cell; state: value, masked, failed, empty."""
    if runs and all(r["status"] == "failed" or r["status"] == "lost" for r in runs):
        return math.nan, "failed"
    if where and runs and all(r.get(where) is False for r in runs):
        return math.nan, "masked"
    values = [_value(r.get(metric)) for r in runs if r.get(metric) is not None]
    values = [v for v in values if not math.isnan(v)]
    return (sum(values) / len(values), "value") if values else (math.nan, "empty")


def _heatmap(ax, choice: Choice, metric: str, subset: list[dict], records: list[dict], limits):
    import numpy as np
    from matplotlib.patches import Patch, Rectangle

    xs, ys = sorted_values(records, choice.x), sorted_values(records, choice.y)
    grid = np.full((len(ys), len(xs)), np.nan)
    marks: dict[str, list[tuple[int, int]]] = {"masked": [], "failed": [], "empty": []}
    for j, yv in enumerate(ys):
        for i, xv in enumerate(xs):
            runs = [r for r in subset if r[choice.x] == xv and r[choice.y] == yv]
            grid[j, i], state = _cell_stats(runs, metric, choice.where)
            if state in marks:
                marks[state].append((i, j))
    finite = grid[np.isfinite(grid)]
    image = ax.imshow(np.ma.masked_invalid(grid), origin="lower", aspect="auto", cmap="viridis",
                      vmin=limits[0], vmax=limits[1], extent=(-0.5, len(xs) - 0.5, -0.5, len(ys) - 0.5))
    styles = {"masked": dict(facecolor="#bbbbbb", hatch="xx", edgecolor="#888888"), "failed": dict(facecolor="#d62728"),
              "empty": dict(facecolor="#ffffff", edgecolor="#999999")}
    for state, cells in marks.items():
        for i, j in cells:
            ax.add_patch(Rectangle((i - 0.5, j - 0.5), 1, 1, linewidth=0.5 if state == "empty" else 0, **styles[state]))
    _ticks(ax.set_xticks, ax.set_xticklabels, xs)
    _ticks(ax.set_yticks, ax.set_yticklabels, ys)
    ax.set_xlabel(choice.x)
    ax.set_ylabel(choice.y)
    labels = {"masked": f"not {choice.where}", "failed": "run failed", "empty": f"no {metric}"}
    legend = [Patch(label=labels[state], **styles[state]) for state in marks if marks[state]]
    if legend:
        ax.legend(handles=legend, loc="upper right", fontsize=7, framealpha=0.8)
    return image if finite.size else None


def _ticks(set_ticks, set_labels, values: list) -> None:
    every = max(1, math.ceil(len(values) / 12))
    positions = list(range(0, len(values), every))
    set_ticks(positions)
    set_labels([f"{values[p]:g}" if isinstance(values[p], float) else str(values[p]) for p in positions], fontsize=8)


def _lines(ax, choice: Choice, metric: str, subset: list[dict]) -> None:
    groups = sorted_values(subset, choice.series) if choice.series else [None]
    for n, group in enumerate(groups):  # markers and dashes tell apart series that coincide
        runs = [r for r in subset if choice.series is None or r[choice.series] == group]
        xs = sorted_values(runs, choice.x)
        stats = []
        for xv in xs:
            values = [_value(r.get(metric)) for r in runs if r[choice.x] == xv and r.get(metric) is not None]
            stats.append((xv, sum(values) / len(values), min(values), max(values)) if values else (xv, math.nan, math.nan, math.nan))
        label = None if group is None else f"{choice.series} = {group}"
        line, = ax.plot([s[0] for s in stats], [s[1] for s in stats], marker="os^vD<>p"[n % 8], markersize=8 - n % 4,
                        linestyle=("-", "--", ":", "-.")[n % 4], label=label)
        ax.fill_between([s[0] for s in stats], [s[2] for s in stats], [s[3] for s in stats], alpha=0.08,
                        color=line.get_color())
    ax.set_xlabel(choice.x)
    ax.set_ylabel(metric)
    ax.grid(alpha=0.3)
    if choice.series:
        ax.legend(fontsize=8)


def _scatter(ax, choice: Choice, metric: str, subset: list[dict], limits):
    runs = [r for r in subset if r.get(metric) is not None]
    if choice.y is None:
        ax.scatter([r[choice.x] for r in runs], [_value(r[metric]) for r in runs], s=10)
        ax.set_xlabel(choice.x)
        ax.set_ylabel(metric)
        return None
    points = ax.scatter([r[choice.x] for r in runs], [r[choice.y] for r in runs], c=[_value(r[metric]) for r in runs],
                        s=12, cmap="viridis", vmin=limits[0], vmax=limits[1])
    ax.set_xlabel(choice.x)
    ax.set_ylabel(choice.y)
    return points if runs else None
