"""Results as the run goes: the CSV rows, the events log, real-time pacing and the progress bar.

The CSV has ``time`` and ``superdense`` columns, then one column per recorded variable
(``instance.variable``): clocks as 0/1, clocked variables only while their clock is active
(empty otherwise). Rows are written through a buffered file that is flushed at least every
0.25 s of wall time and always when the run ends, however it ends. Floats are written with
``repr`` (shortest round-trip form), so identical runs give byte-identical files.
"""

from __future__ import annotations

import csv
import io
import json
import sys
import time as _time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

FLUSH_SECONDS = 0.25
#: A communication point reached later than this after it was due counts as an overrun.
OVERRUN_SECONDS = 1e-3


class Recorder:
    """Where result rows go: kept in ``rows`` (``keep_rows``), written to the CSV, or both."""

    def __init__(self, columns: list[str], output: Path | None, events: Path | None, keep_rows: bool = True):
        self.columns = ["time", "superdense", *columns]
        self.rows: list[list] = []
        self.keep_rows = keep_rows
        self._file = self._events = None
        self._writer = None
        if output is not None:
            Path(output).parent.mkdir(parents=True, exist_ok=True)
            self._file = open(output, "w", newline="", encoding="utf-8", buffering=1 << 16)
            self._writer = csv.writer(self._file, lineterminator="\n")
            self._writer.writerow(self.columns)
        if events is not None:
            Path(events).parent.mkdir(parents=True, exist_ok=True)
            self._events = open(events, "w", encoding="utf-8", buffering=1 << 16)
        self._last_flush = _time.monotonic()
        self._written = 0  # rows written to the CSV: a flush is considered every 256

    def append_row(self, row: list) -> None:
        if self.keep_rows:
            self.rows.append(row)
        if self._writer is not None:
            self._writer.writerow(row)
            self._written += 1
            if self._written & 255 == 0:
                self._flush_if_due()

    def row_sink(self) -> Callable[[list], None]:
        """append_row as the cheapest callable for where the rows go (the kept list's own append
        when there is no file), for a loop that records a row at every step."""
        if self._writer is not None:
            return self.append_row
        return self.rows.append if self.keep_rows else _discard

    def append_rows(self, rows: list[list]) -> None:
        """Several rows at once (the C stretch's chunks); the same as append_row on each."""
        if self.keep_rows:
            self.rows.extend(rows)
        if self._writer is not None and rows:
            self._writer.writerows(rows)
            self._written += len(rows)
            self._flush_if_due()

    def _flush_if_due(self) -> None:
        if _time.monotonic() - self._last_flush > FLUSH_SECONDS:
            self.flush()

    def event(self, t: float, k: int, fmu: str, clock: str, values: dict) -> None:
        if self._events is not None:
            self._events.write(json.dumps({"time": t, "index": k, "fmu": fmu, "clock": clock, "values": values}) + "\n")

    def flush(self) -> None:
        self._last_flush = _time.monotonic()
        for f in (self._file, self._events):
            if f is not None:
                f.flush()

    def close(self) -> None:
        for f in (self._file, self._events):
            if f is not None and not f.closed:
                f.close()

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
