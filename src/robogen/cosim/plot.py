"""``robogen plot RESULTS.csv [--vars ...] -o FIG.png``: clocks as event stems, values as steps or lines.

One panel per group: clocks of one instance share a panel (one stem row each); each value
variable gets its own panel, drawn as a line when it is continuous-looking Float data and as a
step plot otherwise. Clocked values appear only where their clock was active (markers).
"""

from __future__ import annotations

import argparse
import csv
import fnmatch
import math
from pathlib import Path

from robogen.diagnostics import RobogenError, Span


def configure(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("results", help="a CSV written by 'robogen simulate'")
    parser.add_argument("--vars", nargs="+", metavar="NAME", help="columns to plot (glob patterns allowed, e.g. 'dmodel.*')")
    parser.add_argument("-o", "--output", default="results.png", help="figure file (default: results.png)")


def read_results(path: Path) -> tuple[list[str], list[list[str]]]:
    try:
        with open(path, newline="", encoding="utf-8") as f:
            rows = list(csv.reader(f))
    except OSError as exc:
        raise RobogenError.at(f"cannot read results: {exc.strerror}", Span.whole_file(str(path))) from None
    if not rows or rows[0][:2] != ["time", "superdense"]:
        raise RobogenError.at("not a results file of 'robogen simulate' (the header must start with time,superdense)", Span.point(str(path)))
    return rows[0], rows[1:]


def _number(text: str) -> float:
    if text == "":
        return math.nan
    if text in ("True", "False"):
        return 1.0 if text == "True" else 0.0
    try:
        return float(text)
    except ValueError:
        return math.nan


def plot(results: Path, output: Path, patterns: list[str] | None = None) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    header, rows = read_results(results)
    names = header[2:]
    if patterns:
        chosen = [n for n in names if any(fnmatch.fnmatchcase(n, p) for p in patterns)]
        unknown = [p for p in patterns if not any(fnmatch.fnmatchcase(n, p) for n in names)]
        if unknown:
            raise RobogenError.at(f"no column matches {', '.join(repr(u) for u in unknown)}", Span.point(str(results)))
        names = chosen
    times = [float(r[0]) for r in rows]
    cols = {n: [_number(r[header.index(n)]) for r in rows] for n in names}
    clocks = [n for n in names if set(cols[n]) <= {0.0, 1.0} and any(r[header.index(n)] == "1" for r in rows)
              and all(r[header.index(n)] in ("0", "1") for r in rows)]
    groups: list[tuple[str, list[str]]] = []
    for n in clocks:
        inst = n.split(".", 1)[0]
        if groups and groups[-1][0] == f"clocks of {inst}":
            groups[-1][1].append(n)
        else:
            groups.append((f"clocks of {inst}", [n]))
    groups += [(n, [n]) for n in names if n not in clocks]
    if not groups:
        raise RobogenError.at("nothing to plot", Span.point(str(results)))
    fig, axes = plt.subplots(len(groups), 1, sharex=True, figsize=(10, 1.6 + 1.4 * len(groups)), squeeze=False)
    for ax, (title, members) in zip(axes[:, 0], groups):
        if title.startswith("clocks of"):
            for level, n in enumerate(members):
                ticks = [t for t, v in zip(times, cols[n]) if v == 1.0]
                if ticks:
                    ax.stem(ticks, [level + 1] * len(ticks), bottom=level, basefmt=" ", markerfmt="o", linefmt="-", label=n)
            ax.set_yticks(range(1, len(members) + 1), [m.split(".", 1)[1] for m in members])
            ax.set_ylim(0, len(members) + 0.5)
        else:
            ys = cols[title]
            sparse = any(math.isnan(y) for y in ys)
            if sparse:  # a clocked variable: only where its clock ticked
                ax.plot([t for t, y in zip(times, ys) if not math.isnan(y)], [y for y in ys if not math.isnan(y)], "o", ms=3)
            elif all(float(y).is_integer() for y in ys):
                ax.step(times, ys, where="post")
            else:
                ax.plot(times, ys)
        ax.set_title(title, fontsize=9, loc="left")
        ax.grid(True, alpha=0.3)
    axes[-1, 0].set_xlabel("time [s]")
    fig.tight_layout()
    output.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(output, dpi=100)
    plt.close(fig)
    return output


def run(args: argparse.Namespace) -> int:
    out = plot(Path(args.results), Path(args.output), args.vars)
    print(f"wrote {out}")
    return 0
