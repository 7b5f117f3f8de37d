"""Results as Apache Parquet (``robogen simulate -o results.parquet``), written in batches.

The file has the CSV's columns, in its order and with its names: ``time`` (float64),
``superdense`` (int64), then one column per recorded variable typed after its FMI type
(:data:`ARROW_TYPES`): FloatN, IntN and UIntN as the Arrow type of the same width, Boolean as
bool, String as string (UTF-8), Binary as binary, an Enumeration as int64, a clock as int8 (1
while active, else 0). A clocked variable whose clock is inactive is null, as its CSV cell is
empty. So each value reads back as the one the CSV holds: the same float (the CSV writes the
shortest text that reads back as it), the same integer, Boolean and String; a Binary as its
bytes where the CSV shows them in hexadecimal.

Rows are kept in memory only until :data:`BATCH_ROWS` of them are there; each batch becomes one
row group of the file, so a run of any length is written in memory bounded by one batch. The
file's footer is written when the recorder closes: a run that ends in any way the master handles
(an error, a signal, an FMU's request) leaves a complete file; a process killed outright leaves
none that Parquet readers open.
"""

from __future__ import annotations

from pathlib import Path
from typing import Sequence

#: Rows per row group (and the most rows held in memory before they are written).
BATCH_ROWS = 65_536

#: The Arrow type of each FMI type (by the name of its pyarrow factory).
ARROW_TYPES = {
    "Float32": "float32", "Float64": "float64", "Int8": "int8", "UInt8": "uint8", "Int16": "int16",
    "UInt16": "uint16", "Int32": "int32", "UInt32": "uint32", "Int64": "int64", "UInt64": "uint64",
    "Boolean": "bool_", "String": "string", "Binary": "binary", "Enumeration": "int64", "Clock": "int8",
}


def is_parquet(path: str | Path) -> bool:
    """Whether results go to ``path`` as Parquet (its suffix is ``.parquet``, any case)."""
    return Path(path).suffix.lower() == ".parquet"


class ParquetSink:
    """Rows to a Parquet file at ``path``, one row group per :data:`BATCH_ROWS` rows."""

    def __init__(self, path: Path, columns: Sequence[str], types: Sequence[str], batch_rows: int | None = None):
        import pyarrow as pa  # only for Parquet output: the import takes a while
        import pyarrow.parquet as pq

        self._pa = pa
        arrow = [pa.float64(), pa.int64(), *(getattr(pa, ARROW_TYPES[t])() for t in types)]
        self.schema = pa.schema([pa.field(name, kind) for name, kind in zip(columns, arrow)])
        self._writer = pq.ParquetWriter(str(path), self.schema)
        self._rows: list[Sequence] = []
        self.batch_rows = batch_rows or BATCH_ROWS

    def write(self, row: Sequence) -> None:
        self._rows.append(row)
        if len(self._rows) >= self.batch_rows:
            self._write_batch()

    def write_rows(self, rows: list[Sequence]) -> None:
        for row in rows:
            self.write(row)

    def _write_batch(self) -> None:
        rows, self._rows = self._rows, []
        if not rows:
            return
        pa = self._pa
        columns = [pa.array(column, type=field.type) for column, field in zip(zip(*rows), self.schema)]
        self._writer.write_batch(pa.RecordBatch.from_arrays(columns, schema=self.schema))

    def close(self) -> None:
        """Write the rows held and the footer."""
        if self._writer is not None:
            try:
                self._write_batch()
            finally:
                self._writer.close()
                self._writer = None

    def __enter__(self) -> "ParquetSink":
        return self

    def __exit__(self, *exc) -> None:
        self.close()
