"""``robogen plot RESULTS.csv [--vars ...] -o FIG.png``: clocks as event stems, values as steps or lines.

One panel per group: clocks of one instance share a panel (one stem row each); each value
variable gets its own panel, drawn as a line when it is continuous-looking Float data and as a
step plot otherwise. Clocked values appear only where their clock was active (markers).

``--vars`` selects columns as ``[record]`` does (:func:`robogen.cosim.system.matching`: a name,
or a shell-style pattern). A cell that is neither a number, ``True``/``False`` nor empty is an
error naming it, except in columns that hold only such text (String and Binary outputs), which
are left out with a note. The figure is written under a temporary name and renamed
(:mod:`robogen.outputs`); it may not be the results file itself.
"""

from __future__ import annotations

import argparse
import csv
import math
import sys
from pathlib import Path

from robogen.cosim.system import matching
from robogen.diagnostics import Note, RobogenError, Span
from robogen.outputs import output_file, replacing

#: Where the figure goes unless -o says otherwise.
DEFAULT_OUTPUT = Path("build") / "results.png"


def configure(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("results", help="a CSV written by 'robogen simulate'")
    parser.add_argument("--vars", nargs="+", metavar="NAME",
                        help="columns to plot: names or glob patterns, e.g. 'dmodel.*' (as in [record])")
    parser.add_argument("-o", "--output", default=str(DEFAULT_OUTPUT),
                        help=f"figure file; its suffix gives the format (default: {DEFAULT_OUTPUT})")


def read_results(path: Path) -> tuple[list[str], list[list[str]]]:
    """The header and the rows of a results CSV; a file that is not one is a located error."""
    where = Span.whole_file(str(path))
    try:
        with open(path, newline="", encoding="utf-8") as f:
            rows = list(csv.reader(f))
    except OSError as exc:
        raise RobogenError.at(f"cannot read results: {exc.strerror}", where) from None
    except UnicodeDecodeError:
        raise RobogenError.at("not a results file of 'robogen simulate': it is not UTF-8 text", where) from None
    except csv.Error as exc:
        raise RobogenError.at(f"not a results file of 'robogen simulate': {exc}", where) from None
    if not rows or rows[0][:2] != ["time", "superdense"]:
        raise RobogenError.at("not a results file of 'robogen simulate' (the header must start with time,superdense)", Span.point(str(path)))
    for line, row in enumerate(rows[1:], start=2):
        if len(row) != len(rows[0]):
            raise RobogenError.at(f"row {line} has {len(row)} cells; the header names {len(rows[0])} columns", Span.point(str(path), line))
    return rows[0], rows[1:]


def _number(text: str) -> float | None:
    """A cell as a number (empty: NaN); None if it is not one."""
    if text == "":
        return math.nan
    if text in ("True", "False"):
        return 1.0 if text == "True" else 0.0
    try:
        return float(text)
    except ValueError:
        return None


class _Columns:
    """The chosen columns of a results file as numbers, text columns set aside."""

    def __init__(self, path: Path, header: list[str], rows: list[list[str]], patterns: list[str] | None):
        self.path = path
        names = header[2:]
        if patterns:
            unknown = [p for p in patterns if not matching(p, names)]
            if unknown:
                raise RobogenError.at(f"no column matches {', '.join(repr(u) for u in unknown)}", Span.point(str(path)),
                                      Note(f"columns: {', '.join(names[:12])}{', ...' if len(names) > 12 else ''}"))
            names = [n for n in names if any(n in matching(p, names) for p in patterns)]
        self.times = self._numbers(header, rows, 0)
        self.values: dict[str, list[float]] = {}
        self.text: list[str] = []
        self.clocks: list[str] = []  # columns of 0 and 1 only, with a 1 somewhere
        for name in names:
            index = header.index(name)
            column = self._numbers(header, rows, index)
            if column is None:
                self.text.append(name)
                continue
            self.values[name] = column
            if any(r[index] == "1" for r in rows) and all(r[index] in ("0", "1") for r in rows):
                self.clocks.append(name)

    def _numbers(self, header: list[str], rows: list[list[str]], index: int) -> list[float] | None:
        """Column ``index`` as numbers; None if it holds only text; a mix is an error naming the cell."""
        numbers = [_number(r[index]) for r in rows]
        bad = [k for k, x in enumerate(numbers) if x is None]
        if not bad:
            return numbers
        if index > 0 and all(x is None or math.isnan(x) for x in numbers):
            return None  # a String or Binary column
        k = bad[0]
        raise RobogenError.at(f"column '{header[index]}' has the non-numeric value {rows[k][index]!r} in row {k + 2}",
                              Span.point(str(self.path), k + 2, 1 + sum(len(c) + 1 for c in rows[k][:index])))


def _groups(cols: _Columns) -> list[tuple[str, list[str]]]:
    """Clocks of one instance share a panel; each value has its own."""
    groups: list[tuple[str, list[str]]] = []
    for n in cols.clocks:
        inst = n.split(".", 1)[0]
        if groups and groups[-1][0] == f"clocks of {inst}":
            groups[-1][1].append(n)
        else:
            groups.append((f"clocks of {inst}", [n]))
    return groups + [(n, [n]) for n in cols.values if n not in cols.clocks]


def plot(results: Path, output: Path, patterns: list[str] | None = None,
         labels: dict[str, dict[int, str]] | None = None) -> Path:
    """Draw the chosen columns of ``results`` into ``output``; ``labels`` names the values of
    step-plotted columns on their axis (an Enumeration's items: a state machine's states)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    output = output_file(output, inputs=[results])
    header, rows = read_results(results)
    cols = _Columns(results, header, rows, patterns)
    if cols.text:
        print(f"robogen plot: left out the text columns (String or Binary values): {', '.join(cols.text)}", file=sys.stderr)
    groups = _groups(cols)
    if not groups:
        raise RobogenError.at("nothing to plot", Span.point(str(results)))
    fig, axes = plt.subplots(len(groups), 1, sharex=True, figsize=(10, 1.6 + 1.4 * len(groups)), squeeze=False)
    try:
        fmt = _format(fig, output)
        for ax, (title, members) in zip(axes[:, 0], groups):
            _draw(ax, title, members, cols, (labels or {}).get(title))
        axes[-1, 0].set_xlabel("time [s]")
        fig.tight_layout()
        with replacing(output) as tmp:
            fig.savefig(tmp, dpi=100, format=fmt)
    finally:
        plt.close(fig)
    return output


def _format(fig, output: Path) -> str:
    fmt = output.suffix[1:].lower() or "png"
    supported = fig.canvas.get_supported_filetypes()
    if fmt not in supported:
        raise RobogenError.at(f"-o {output}: no figure format '{fmt}' (the suffix gives it: {', '.join(sorted(supported))})", None)
    return fmt


def _draw(ax, title: str, members: list[str], cols: _Columns, names: dict[int, str] | None = None) -> None:
    times = cols.times
    if title.startswith("clocks of"):
        for level, n in enumerate(members):
            ticks = [t for t, v in zip(times, cols.values[n]) if v == 1.0]
            if ticks:
                ax.stem(ticks, [level + 1] * len(ticks), bottom=level, basefmt=" ", markerfmt="o", linefmt="-", label=n)
        ax.set_yticks(range(1, len(members) + 1), [m.split(".", 1)[1] for m in members])
        ax.set_ylim(0, len(members) + 0.5)
    else:
        ys = cols.values[title]
        if any(math.isnan(y) for y in ys):  # a clocked variable: only where its clock ticked
            ax.plot([t for t, y in zip(times, ys) if not math.isnan(y)], [y for y in ys if not math.isnan(y)], "o", ms=3)
        elif all(float(y).is_integer() for y in ys):
            ax.step(times, ys, where="post")
            if names:
                ax.set_yticks(sorted(names), [names[k] for k in sorted(names)])
        else:
            ax.plot(times, ys)
    ax.set_title(title, fontsize=9, loc="left")
    ax.grid(True, alpha=0.3)


def run(args: argparse.Namespace) -> int:
    out = plot(Path(args.results), Path(args.output), args.vars)
    print(f"wrote {out}")
    return 0
