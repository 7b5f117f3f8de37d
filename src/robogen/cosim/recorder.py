"""Results as the run goes: the CSV rows, the events log, real-time pacing and the progress bar.

The CSV has ``time`` and ``superdense`` columns, then one column per recorded variable
(``instance.variable``): clocks as 0/1, clocked variables only while their clock is active
(empty otherwise). Floats are written with ``repr`` (shortest round-trip form), so identical
runs give byte-identical files; integers in decimal, Booleans as ``True``/``False``; a String
always in double quotes (a quote inside doubled, as RFC 4180 quotes), so the empty String ``""``
differs from an empty cell; a Binary as ``0x`` and two lowercase hexadecimal digits per byte
(``0x`` alone when empty). The events log writes Binaries the same way, as JSON strings.

A results path ending in ``.parquet`` gets the same columns and values as Apache Parquet,
written in row groups of bounded size (:mod:`robogen.cosim.columnar`).

Decimation (``[record] every = SECONDS``) cuts time into intervals [start + n * every,
start + (n + 1) * every) (a point within the time tolerance of a bound counting as reached).
Every row of an event iteration is kept; a plain row (a communication point without an event,
however it was stepped) is kept when it is the first row of its interval, so a kept event row
makes the plain rows after it in its interval redundant; and the last row of the run is kept
whatever it is, so the results end where the run ended. Without ``every``, every row is kept.

Rows arrive one at a time (:meth:`Recorder.append_row`, :meth:`Recorder.append_event_row`:
the reference loop), in batches of plain rows (:meth:`Recorder.append_rows`), or as a chunk of
columns (:meth:`Recorder.append_chunk`: the engine's rows, as arrays); each goes to the results
file and to the table kept in memory (:meth:`Recorder.table`, a
:class:`~robogen.cosim.columnar.Table`: one array per column, whichever way the rows came).

Each file is written under a temporary name next to it and renamed over it when the recorder
closes (:func:`robogen.outputs.replacing`): a run that recorded rows, however it ended, leaves
them at the name asked for; a run that failed before its first row leaves the previous file
untouched. Rows go through a buffered file that is flushed at every event iteration (the master
calls :meth:`Recorder.flush`), at least every :data:`FLUSH_SECONDS` of wall time, and at the end.
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
import math
import sys
import time as _time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Sequence

from robogen.cosim.clocks import grid_index
from robogen.fmu.fmi import tolerance
from robogen.cosim.columnar import LEADING_TYPES, ParquetSink, Table, TableBuilder, is_parquet
from robogen.outputs import replacing

FLUSH_SECONDS = 0.2
#: Rows the reference loop's rows are kept as lists before they join the table's columns.
PENDING_ROWS = 4096
#: A communication point reached later than this after it was due counts as an overrun.
OVERRUN_SECONDS = 1e-3


def string_cell(value: str | None) -> str:
    """A String's CSV cell: always quoted (an absent value is an empty cell)."""
    return "" if value is None else '"' + value.replace('"', '""') + '"'


def binary_cell(value: bytes | None) -> str:
    """A Binary's CSV cell (and events-log string): ``0x`` and its bytes in hexadecimal."""
    return "" if value is None else "0x" + bytes(value).hex()


def _plain_cell(value) -> str:
    """Any other value's cell, as the csv module writes it."""
    return "" if value is None else str(value)


_CELLS = {"String": string_cell, "Binary": binary_cell}


def _json_value(value):
    if isinstance(value, (bytes, bytearray)):
        return binary_cell(value)
    raise TypeError(f"{type(value).__name__} is not a value of an FMI type")


class _Discarded(Exception):
    """Closes a temporary output without renaming it (nothing worth keeping was written)."""


class Recorder:
    """Where result rows go: kept in memory as a table (``keep_rows``), written to the CSV, or both.

    ``types`` are the FMI types of the recorded columns (after ``time`` and ``superdense``);
    ``rows_hint`` the rows the run is expected to record (the table makes room for them at once);
    ``files`` lists (temporary path, final path) of each file being written, for a process that
    must rename them after this one died (:mod:`robogen.cosim.crash`).
    """

    def __init__(self, columns: list[str], output: Path | None, events: Path | None, keep_rows: bool = True,
                 types: Sequence[str] = (), every: float | None = None, start: float = 0.0, rows_hint: int = 0):
        self.columns = ["time", "superdense", *columns]
        self.keep_rows = keep_rows
        self._kept = TableBuilder(self.columns, [*LEADING_TYPES, *types], rows_hint if keep_rows else 0)
        self._pending: list[list] = []  # rows kept, not yet in the table's columns
        self.recorded = 0  # rows recorded so far (counted where there is a file: it is kept if any)
        self.kept: Path | None = None  # the results file, once closed with rows in it
        self.files: list[tuple[Path, Path]] = []
        self._file = self._events = None
        self._writer = None
        self._table: ParquetSink | None = None
        self._outputs = contextlib.ExitStack()
        cells = [_CELLS.get(t, _plain_cell) for t in types]
        self._cells = [_plain_cell, _plain_cell, *cells] if any(c is not _plain_cell for c in cells) else None
        self._output = output
        self.every, self.start = every, start
        self._next_kept = 0  # decimation: the grid index of the next plain row to keep
        self._held: list | None = None  # decimation: the last plain row dropped, kept if it ends the run
        try:
            if output is not None and is_parquet(output):
                temporary = self._temporary(output)
                self._table = self._outputs.enter_context(ParquetSink(temporary, self.columns, list(types)))
            elif output is not None:
                self._file = self._open(output, newline="")
                self._writer = csv.writer(self._file, lineterminator="\n")
                self._writer.writerow(self.columns)
                self._write = self._writer.writerow if self._cells is None else self._write_cells
            if events is not None:
                self._events = self._open(events)
        except BaseException:
            self._outputs.__exit__(_Discarded, _Discarded(), None)
            raise
        self._flush_due = _time.monotonic() + FLUSH_SECONDS

    def _temporary(self, path: Path) -> Path:
        """A temporary name for ``path``, renamed to it when closed with rows."""
        temporary = self._outputs.enter_context(replacing(path))
        self.files.append((temporary, Path(path)))
        return temporary

    def _open(self, path: Path, newline: str | None = None):
        """A file written under a temporary name, renamed to ``path`` when closed with rows."""
        return self._outputs.enter_context(open(self._temporary(path), "w", newline=newline, encoding="utf-8",
                                                buffering=1 << 16))

    def _decimated(self, t: float) -> bool:
        """Whether the plain row at t is dropped (see the module docstring); notes the next one kept."""
        n = grid_index(self.start, self.every, t, tolerance(t, self.every))
        if n < self._next_kept:
            return True
        self._next_kept = n + 1
        return False

    def append_row(self, row: list) -> None:
        """A plain row: a communication point without an event (dropped by decimation)."""
        if self.every is not None and self._decimated(row[0]):
            self._held = row
            return
        self.append_event_row(row)

    def append_event_row(self, row: list) -> None:
        """A row of an event iteration: always kept."""
        self._held = None
        if self.every is not None:  # a row in this decimation interval is kept: no plain one needed
            t = row[0]
            self._next_kept = max(self._next_kept, grid_index(self.start, self.every, t, tolerance(t, self.every)) + 1)
        self.recorded += 1
        if self.keep_rows:
            self._keep(row)
        if self._writer is not None:
            self._write(row)
            if _time.monotonic() > self._flush_due:
                self.flush()
        elif self._table is not None:
            self._table.write(row)

    def _write_cells(self, row: list) -> None:
        """A row with String or Binary columns, each cell in its format."""
        self._file.write(",".join([cell(v) for cell, v in zip(self._cells, row)]) + "\n")

    def _keep(self, row: list) -> None:
        """A row kept: with the others pending, which join the table's columns by the thousand."""
        self._pending.append(row)
        if len(self._pending) >= PENDING_ROWS:
            self._settle()

    def _settle(self) -> None:
        """The pending rows into the table's columns."""
        rows, self._pending = self._pending, []
        self._kept.append_rows(rows)

    def table(self) -> Table:
        """The rows kept (``keep_rows``), as columns; once asked, no more rows may be recorded."""
        self._settle()
        return self._kept.finish()

    @property
    def rows(self) -> list[list]:
        """The rows kept, as lists (:attr:`Table.rows`)."""
        return self.table().rows

    def row_sink(self) -> Callable[[list], None]:
        """append_row as the cheapest callable for where the rows go, for a loop that records a
        row at every step."""
        if self._writer is not None or self._table is not None or self.every is not None:
            return self.append_row
        return self._keep if self.keep_rows else _discard  # no file: nothing to keep or rename

    def append_chunk(self, columns: Sequence, valid: Sequence, count: int, rows: Callable[[], list[list]]) -> None:
        """``count`` plain rows as columns (the engine's chunk: an array or list per column, and
        per column where its cells have a value, or None: everywhere); ``rows()`` gives them as
        lists, for the results file. The same as append_rows(rows())."""
        if self.every is not None:
            self.append_rows(rows())
            return
        if self.keep_rows:
            self._settle()
            self._kept.append_arrays(columns, valid, count)
        self.recorded += count
        if self._table is not None:
            self._table.write_arrays(columns, valid, count)
        if self._writer is not None:
            self._write_rows(rows())

    def append_rows(self, rows: list[list]) -> None:
        """Several plain rows at once (the C stretch's chunks); the same as append_row on each."""
        if self.every is not None:
            for row in rows:
                self.append_row(row)
            return
        self.recorded += len(rows)
        if self.keep_rows:
            self._settle()
            self._kept.append_rows(rows)
        self._write_rows(rows)

    def _write_rows(self, rows: list[list]) -> None:
        """Plain rows to the results file, if any."""
        if self._table is not None:
            self._table.write_rows(rows)
        elif self._writer is not None and rows:
            if self._cells is None:
                self._writer.writerows(rows)
            else:
                for row in rows:
                    self._write_cells(row)
            if _time.monotonic() > self._flush_due:
                self.flush()

    @property
    def takes_text(self) -> bool:
        """Whether rows may come as CSV lines (:meth:`append_text`): they go to a CSV file only,
        every one of them (no decimation)."""
        return self._writer is not None and not self.keep_rows and self.every is None

    @property
    def discards(self) -> bool:
        """Whether rows go nowhere (no CSV or Parquet file, not kept)."""
        return self._writer is None and self._table is None and not self.keep_rows

    @property
    def flush_due(self) -> float:
        """The time.monotonic() by which the rows appended so far are to be flushed (never
        without a results file)."""
        return self._flush_due if self._file is not None else math.inf

    def append_text(self, text: str, rows: int) -> None:
        """``rows`` rows already written as the CSV lines append_row would write (the C stretch's
        chunks, where :attr:`takes_text`)."""
        self.recorded += rows
        self._file.write(text)
        if _time.monotonic() > self._flush_due:
            self.flush()

    def text_file(self) -> int:
        """Where :attr:`takes_text`: the CSV file's descriptor, for a loop that writes lines to it
        itself, its buffer flushed first (then :meth:`wrote_rows`); else -1."""
        if not self.takes_text:
            return -1
        self.flush()
        return self._file.fileno()

    def events_file(self) -> int:
        """The events log's descriptor, its buffer flushed, for a loop that writes events to it
        itself (as :meth:`event` writes them); -1 without an events log."""
        if self._events is None:
            return -1
        self._events.flush()
        return self._events.fileno()

    def wrote_rows(self, rows: int) -> None:
        """``rows`` rows recorded without this recorder: written to the CSV file through
        :meth:`text_file` (flushed), or going nowhere (:attr:`discards`)."""
        self.recorded += rows

    def event(self, t: float, k: int, fmu: str, clock: str, values: dict) -> None:
        if self._events is not None:
            record = {"time": t, "index": k, "fmu": fmu, "clock": clock, "values": values}
            self._events.write(json.dumps(record, default=_json_value) + "\n")

    def flush(self) -> None:
        """Flush the CSV and events files (a Parquet file is written by row groups and completed
        at close: flushing would only make its row groups small)."""
        if self._file is None and self._events is None:
            return  # nothing to flush (rows kept in memory, or a Parquet file)
        self._flush_due = _time.monotonic() + FLUSH_SECONDS
        for f in (self._file, self._events):
            if f is not None:
                f.flush()

    def close(self) -> None:
        """Close the files: renamed to their names if rows were recorded, else removed (the
        previous files, if any, stay). Under decimation the run's last row is written first."""
        if self._held is not None:
            self.append_event_row(self._held)
        if self.recorded:
            self._outputs.close()
            self.kept = self._output
        else:
            self._outputs.__exit__(_Discarded, _Discarded(), None)

    @property
    def recording_events(self) -> bool:
        return self._events is not None


@dataclass
class Pacer:
    """Paces simulated time against a monotonic clock: point t is due at wall0 + (t - t0) / factor."""

    factor: float
    t0: float
    wall0: float = field(default_factory=_time.monotonic)
    lags: list[float] = field(default_factory=list)
    overruns: int = 0
    threshold: float = OVERRUN_SECONDS

    def wait(self, t: float) -> None:
        due = self.wall0 + (t - self.t0) / self.factor
        now = _time.monotonic()
        if now < due:
            _time.sleep(due - now)
            self.lags.append(0.0)
        else:
            lag = now - due
            self.lags.append(lag)
            if lag > self.threshold:
                self.overruns += 1

    def summary(self) -> dict:
        n = len(self.lags)
        return {
            "factor": self.factor,
            "points": n,
            "mean_lag": sum(self.lags) / n if n else 0.0,
            "worst_lag": max(self.lags) if n else 0.0,
            "overruns": self.overruns,
        }


class Progress:
    """A one-line progress bar on stderr, redrawn at most ten times a second; silent when not a TTY."""

    def __init__(self, t0: float, t1: float, stream: io.TextIOBase | None = None, enabled: bool | None = None):
        self.stream = stream or sys.stderr
        self.enabled = self.stream.isatty() if enabled is None else enabled
        self.t0, self.t1 = t0, t1
        self._last = 0.0

    def update(self, t: float) -> None:
        if not self.enabled:
            return
        now = _time.monotonic()
        if now - self._last < 0.1:
            return
        self._last = now
        frac = 1.0 if self.t1 <= self.t0 else min(1.0, max(0.0, (t - self.t0) / (self.t1 - self.t0)))
        bar = "#" * int(frac * 30)
        self.stream.write(f"\r[{bar:<30}] {100 * frac:5.1f}%  t = {t:.6g} / {self.t1:.6g} s")
        self.stream.flush()

    def close(self) -> None:
        if self.enabled:
            self.stream.write("\r" + " " * 70 + "\r")
            self.stream.flush()


def _discard(row: list) -> None:
    """append_row where rows go nowhere (no file, rows not kept)."""
