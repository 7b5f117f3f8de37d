"""The campaign's memory: one JSON line per finished run, keyed by the hash of its specification.

``DIR/journal.jsonl`` is appended to (and flushed) as each run's result arrives, so a campaign
stopped at any moment (Ctrl-C, a killed client, a lost machine) keeps every run it finished; a
line cut short by the stop is ignored when the journal is read again. Running the campaign again
skips every run whose key is in the journal: only what was missing runs. A run's time series
(keep = "results") is written before its line, so a journaled run always has its file.
"""

from __future__ import annotations

import json
from pathlib import Path

#: The fields of a row that the journal keeps (the time series go to their own files).
FIELDS = ("status", "error", "end_time", "metrics", "wall_time", "worker")


class Journal:
    def __init__(self, path: Path) -> None:
        self.path = path
        self.rows: dict[str, dict] = {}
        if path.is_file():
            for line in path.read_text(encoding="utf-8").splitlines():
                try:
                    entry = json.loads(line)
                except json.JSONDecodeError:
                    continue  # the last line of a campaign that was stopped while writing it
                if isinstance(entry, dict) and isinstance(entry.get("key"), str):
                    self.rows[entry["key"]] = {k: entry.get(k) for k in FIELDS}
        self._file = None

    def __contains__(self, key: str) -> bool:
        return key in self.rows

    def add(self, key: str, row: dict) -> None:
        if self._file is None:
            cut = self.path.is_file() and not self.path.read_bytes().endswith(b"\n") and self.path.stat().st_size > 0
            self._file = self.path.open("a", encoding="utf-8")
            if cut:  # end the line a stopped campaign left unfinished
                self._file.write("\n")
        kept = {k: row.get(k) for k in FIELDS}
        self._file.write(json.dumps({"key": key, **kept}, sort_keys=True) + "\n")
        self._file.flush()
        self.rows[key] = kept

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None
