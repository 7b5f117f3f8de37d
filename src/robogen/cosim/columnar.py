"""Results in columns: the table a run keeps in memory, and Apache Parquet files.

**The table** (:class:`Table`): one NumPy array per column, in the CSV's order and with its names:
``time`` (float64), ``superdense`` (int32, the super-dense index), then one array per recorded
variable typed after its FMI type (:data:`NUMPY_TYPES`): FloatN, IntN and UIntN as the NumPy type
of the same width, Boolean as bool, an Enumeration as int64, a clock as int8 (1 while active,
else 0), String and Binary as object arrays of ``str`` and ``bytes``. A column that has empty
cells (a clocked variable whose clock is inactive) has a validity array beside it (True where
the cell has a value; the value array holds 0, or None, elsewhere). A run's rows are appended in
chunks (:class:`TableBuilder`): arrays from the engine, or rows from the reference loop; the
arrays grow in place and are cut to the rows when the run ends, so a row costs the width of its
values (20 bytes for ``time``, ``superdense`` and one Float64). :meth:`Table.rows` gives the
same rows as lists, :meth:`Table.to_numpy` a structured array (as ``fmpy.simulate_fmu`` returns),
:meth:`Table.to_arrow` a ``pyarrow.Table`` sharing the numeric arrays' memory where Arrow's
layout is NumPy's (a column without empty cells, not Boolean).

**Parquet** (:class:`ParquetSink`, ``robogen simulate -o results.parquet``): the same columns,
typed after the same FMI types (:data:`ARROW_TYPES`): FloatN, IntN and UIntN as the Arrow type of
the same width, Boolean as bool, String as string (UTF-8), Binary as binary, an Enumeration as
int64, a clock as int8, ``superdense`` as int64. A clocked variable whose clock is inactive is
null, as its CSV cell is empty. So each value reads back as the one the CSV holds: the same float
(the CSV writes the shortest text that reads back as it), the same integer, Boolean and String; a
Binary as its bytes where the CSV shows them in hexadecimal.

Rows are kept in memory only until a batch of :data:`BATCH_CELLS` values (rows times columns, at
least :data:`MIN_BATCH_ROWS` rows) is there; each batch becomes one row group of the file, so a
run of any length and width is written in memory bounded by one batch (about 10 MB of Python
values). The
file's footer is written when the recorder closes: a run that ends in any way the master handles
(an error, a signal, an FMU's request) leaves a complete file; a process killed outright leaves
none that Parquet readers open.
"""

from __future__ import annotations

import functools
from pathlib import Path
from typing import Sequence

import numpy as np

#: Values (rows times columns) per row group: the most held in memory before they are written.
BATCH_CELLS = 262_144
#: Rows per row group at least, however wide the rows.
MIN_BATCH_ROWS = 256
#: The most rows a table makes room for before its first row (a longer run grows it).
MAX_INITIAL_ROWS = 1 << 22

#: The Arrow type of each FMI type (by the name of its pyarrow factory).
ARROW_TYPES = {
    "Float32": "float32", "Float64": "float64", "Int8": "int8", "UInt8": "uint8", "Int16": "int16",
    "UInt16": "uint16", "Int32": "int32", "UInt32": "uint32", "Int64": "int64", "UInt64": "uint64",
    "Boolean": "bool_", "String": "string", "Binary": "binary", "Enumeration": "int64", "Clock": "int8",
}
#: The NumPy type of each FMI type's column in a table (object: Python ``str`` or ``bytes``).
NUMPY_TYPES = {
    "Float32": "float32", "Float64": "float64", "Int8": "int8", "UInt8": "uint8", "Int16": "int16",
    "UInt16": "uint16", "Int32": "int32", "UInt32": "uint32", "Int64": "int64", "UInt64": "uint64",
    "Boolean": "bool", "String": "object", "Binary": "object", "Enumeration": "int64", "Clock": "int8",
}
#: The types of the two columns every table starts with: ``time`` and ``superdense``.
LEADING_TYPES = ("Float64", "Superdense")
_DTYPES = {**NUMPY_TYPES, "Superdense": "int32"}


def is_parquet(path: str | Path) -> bool:
    """Whether results go to ``path`` as Parquet (its suffix is ``.parquet``, any case)."""
    return Path(path).suffix.lower() == ".parquet"


class ParquetSink:
    """Rows to a Parquet file at ``path``, one row group per batch (``batch_rows``, by default
    :data:`BATCH_CELLS` values' worth of rows). Rows come as lists (:meth:`write`,
    :meth:`write_rows`) or as chunks of columns (:meth:`write_arrays`); a batch is held as a
    table's columns (:class:`TableBuilder`) whichever way its rows came."""

    def __init__(self, path: Path, columns: Sequence[str], types: Sequence[str], batch_rows: int | None = None):
        import pyarrow as pa  # only for Parquet output: the import takes a while
        import pyarrow.parquet as pq

        self._pa = pa
        arrow = [pa.float64(), pa.int64(), *(getattr(pa, ARROW_TYPES[t])() for t in types)]
        self.schema = pa.schema([pa.field(name, kind) for name, kind in zip(columns, arrow)])
        self._writer = pq.ParquetWriter(str(path), self.schema)
        self._names, self._types = list(columns), [*LEADING_TYPES, *types]
        self.batch_rows = batch_rows or max(MIN_BATCH_ROWS, BATCH_CELLS // len(self.schema))
        self._batch = TableBuilder(self._names, self._types, self.batch_rows)
        self._rows: list[Sequence] = []  # rows after the batch's columns, not in them yet

    def write(self, row: Sequence) -> None:
        self._rows.append(row)
        if self._batch.rows + len(self._rows) >= self.batch_rows:
            self._write_batch()

    def write_rows(self, rows: list[Sequence]) -> None:
        for row in rows:
            self.write(row)

    def write_arrays(self, columns: Sequence, valid: Sequence, count: int) -> None:
        """``count`` rows as columns (:meth:`TableBuilder.append_arrays`)."""
        self._settle()
        done = 0
        while done < count:
            take = min(count - done, self.batch_rows - self._batch.rows)
            part = slice(done, done + take)
            self._batch.append_arrays([c[part] for c in columns], [None if ok is None else ok[part] for ok in valid], take)
            done += take
            if self._batch.rows >= self.batch_rows:
                self._write_batch()

    def _settle(self) -> None:
        rows, self._rows = self._rows, []
        self._batch.append_rows(rows)

    def _write_batch(self) -> None:
        self._settle()
        if not self._batch.rows:
            return
        table, self._batch = self._batch.finish(), TableBuilder(self._names, self._types, self.batch_rows)
        pa = self._pa
        columns = [pa.array(a, type=field.type, mask=None if ok is None else ~ok, from_pandas=False)
                   for a, ok, field in zip(table.arrays, table.valid, self.schema)]
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


class Table:
    """A run's results in columns (see the module's docstring): ``names`` and FMI ``types`` of
    the columns (``time`` and ``superdense`` first), their ``arrays``, and per column its
    validity array or None (no empty cell)."""

    def __init__(self, names: Sequence[str], types: Sequence[str], arrays: Sequence[np.ndarray],
                 valid: Sequence[np.ndarray | None]):
        self.names, self.types = list(names), list(types)
        self.arrays, self.valid = list(arrays), list(valid)
        self._index = {name: i for i, name in enumerate(self.names)}

    @classmethod
    def from_rows(cls, names: Sequence[str], rows: list[list]) -> "Table":
        """The table of rows given as lists (each column typed after its values), whose
        :attr:`rows` are these very lists."""
        types = [*LEADING_TYPES, *(_type_of([row[c] for row in rows]) for c in range(2, len(names)))]
        builder = TableBuilder(names, types, len(rows))
        builder.append_rows(rows)
        table = builder.finish()
        table.__dict__["rows"] = rows
        return table

    def __len__(self) -> int:
        return len(self.arrays[0]) if self.arrays else 0

    def _at(self, name: str) -> int:
        try:
            return self._index[name]
        except KeyError:
            raise KeyError(f"no column {name!r} was recorded (the columns: {', '.join(self.names)})") from None

    def array(self, name: str) -> np.ndarray:
        """The column's values as its array (where the cell is empty: 0, or None)."""
        return self.arrays[self._at(name)]

    def validity(self, name: str) -> np.ndarray | None:
        """Where the column's cells have a value (None: in every row)."""
        return self.valid[self._at(name)]

    def column(self, name: str) -> list:
        """The column's values as Python values, None for an empty cell."""
        return self._values(self._at(name))

    def _values(self, c: int) -> list:
        values, valid = self.arrays[c].tolist(), self.valid[c]
        if valid is None:
            return values
        return [v if ok else None for v, ok in zip(values, valid.tolist())]

    @functools.cached_property
    def rows(self) -> list[list]:
        """One list per row ([time, superdense, values...]; None for an empty cell), as the CSV
        writes them."""
        return list(map(list, zip(*(self._values(c) for c in range(len(self.names))))))

    def to_numpy(self) -> np.ndarray:
        """The rows as one structured array, a field per column (an empty cell holds 0 or None:
        :meth:`validity` says where)."""
        out = np.empty(len(self), dtype=[(name, a.dtype) for name, a in zip(self.names, self.arrays)])
        for name, a in zip(self.names, self.arrays):
            out[name] = a
        return out

    def to_arrow(self):
        """The table as a ``pyarrow.Table`` (empty cells null), typed as the Parquet file is."""
        import pyarrow as pa

        arrow = [pa.float64(), pa.int32(), *(getattr(pa, ARROW_TYPES[t])() for t in self.types[2:])]
        columns = [pa.array(a, type=kind, mask=None if ok is None else ~ok, from_pandas=False)
                   for a, ok, kind in zip(self.arrays, self.valid, arrow)]
        return pa.Table.from_arrays(columns, names=self.names)

    @property
    def nbytes(self) -> int:
        """The bytes of the arrays (of the objects too: a String's or Binary's, not their pointers')."""
        size = 0
        for a, ok in zip(self.arrays, self.valid):
            size += a.nbytes + (0 if ok is None else ok.nbytes)
        return size


def _type_of(values: list) -> str:
    """The FMI type a column of Python values is held as (Table.from_rows)."""
    present = [v for v in values if v is not None]
    if present and all(isinstance(v, bool) for v in present):
        return "Boolean"
    if present and all(isinstance(v, int) and not isinstance(v, bool) for v in present):
        return "Int64"
    if any(isinstance(v, str) for v in present):
        return "String"
    if any(isinstance(v, (bytes, bytearray)) for v in present):
        return "Binary"
    return "Float64"


class TableBuilder:
    """A table filled as a run goes (:meth:`append_arrays`, :meth:`append_rows`), with room for
    ``capacity`` rows at first; :meth:`finish` cuts the arrays to the rows."""

    def __init__(self, names: Sequence[str], types: Sequence[str], capacity: int = 0):
        self.names, self.types = list(names), list(types)
        self.rows = 0
        self._capacity = max(16, min(capacity, MAX_INITIAL_ROWS))
        self._objects = [_DTYPES[t] == "object" for t in self.types]
        self._arrays: list = [[] if obj else np.zeros(self._capacity, _DTYPES[t]) for t, obj in zip(self.types, self._objects)]
        self._valid: list[np.ndarray | None] = [None] * len(self.types)
        self._table: Table | None = None

    def _room(self, count: int) -> None:
        """Room for ``count`` more rows (the arrays doubled in place, as often as needed)."""
        need = self.rows + count
        if need <= self._capacity:
            return
        capacity = max(need, 2 * self._capacity)
        for a in (*self._arrays, *self._valid):
            if isinstance(a, np.ndarray):
                a.resize(capacity, refcheck=False)  # realloc: the new room is zeros
        self._capacity = capacity

    def append_arrays(self, columns: Sequence, valid: Sequence[np.ndarray | None], count: int) -> None:
        """``count`` rows as one array (or list, for an object column) per column, and per column
        where its cells have a value (None: in every row)."""
        self._room(count)
        n = self.rows
        for c, (values, ok) in enumerate(zip(columns, valid)):
            empty = ok is not None and not ok.all()
            if self._objects[c]:
                self._arrays[c].extend(values)
            else:  # an empty cell's value is 0 (what its slot held is nothing the FMU said)
                self._arrays[c][n:n + count] = np.where(ok, values, 0) if empty else values
            if empty or (ok is not None and self._valid[c] is not None):
                if self._valid[c] is None:
                    self._valid[c] = np.ones(self._capacity, bool)
                self._valid[c][n:n + count] = ok
        self.rows = n + count

    def append_rows(self, rows: list[list]) -> None:
        """Rows given as lists ([time, superdense, values...], None for an empty cell)."""
        if not rows:
            return
        count = len(rows)
        columns: list = []
        valid: list = []
        for c, obj in enumerate(self._objects):
            values = [row[c] for row in rows]
            ok = None
            if None in values:
                ok = np.array([v is not None for v in values], bool)
                if not obj:
                    values = [0 if v is None else v for v in values]
            columns.append(values if obj else np.array(values, _DTYPES[self.types[c]]))
            valid.append(ok)
        self.append_arrays(columns, valid, count)

    def finish(self) -> Table:
        """The table of the rows appended (the arrays cut to them; nothing may be appended after)."""
        if self._table is None:
            arrays = []
            for values, obj in zip(self._arrays, self._objects):
                if obj:
                    a = np.empty(self.rows, object)
                    a[:] = values
                else:
                    a = values
                    a.resize(self.rows, refcheck=False)
                arrays.append(a)
            for ok in self._valid:
                if ok is not None:
                    ok.resize(self.rows, refcheck=False)
            self._table = Table(self.names, self.types, arrays, self._valid)
        return self._table
