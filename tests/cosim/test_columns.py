"""Results kept in columns (robogen.cosim.columnar.Table): an array per column typed after its FMI
type, a validity array beside a column with empty cells, the same columns from the engine and
from the reference loop, the rows they give, and what they convert to."""

from __future__ import annotations

import numpy as np
import pyarrow as pa
import pytest

from robogen.cosim import RunError, SimulationResult, simulate_system
from robogen.cosim.columnar import Table
from robogen.cosim.recorder import Recorder

SUFFIXES = ("f32", "f64", "i8", "u8", "i16", "u16", "i32", "u32", "i64", "u64", "b", "s", "bin", "e")
#: NumPy's type of each alltypes column, by its suffix (an Enumeration as int64, a String or Binary as objects)
DTYPES = {"f32": "float32", "f64": "float64", "i8": "int8", "u8": "uint8", "i16": "int16", "u16": "uint16", "i32": "int32",
          "u32": "uint32", "i64": "int64", "u64": "uint64", "b": "bool", "s": "object", "bin": "object", "e": "int64"}
#: a's output clock (every 0.3 s) drives b's input clock and carries a value of every type; every
#: unclocked output of a feeds b's input of the same type
TYPES = ("connections = [" + ", ".join(['"a.out -> b.tin"'] + [f'"a.c_{x} -> b.ci_{x}"' for x in SUFFIXES]
                                       + [f'"a.y_{x} -> b.u_{x}"' for x in SUFFIXES])
         + ']\n[experiment]\nstop = 1.2\nstep = 0.1\n[instances.a]\nfmu = "{alltypes}"\n[instances.b]\nfmu = "{alltypes}"\n'
         '[record]\nvariables = [' + ", ".join(['"a.out"', '"b.tin"', *(f'"a.c_{x}", "b.ci_{x}", "b.y_{x}"' for x in SUFFIXES)]) + "]\n")
TRIVIAL = '[experiment]\nstop = 1.0\nstep = 1e-4\n[instances.t]\nfmu = "{trivial}"\n[record]\nvariables = ["t.y"]\n'
TICKER = '[experiment]\nstop = 3.0\nstep = 0.01\n[instances.k]\nfmu = "{ticker}"\n[instances.t]\nfmu = "{trivial}"\n'


def run(loop: str, monkeypatch, path, **kwargs) -> SimulationResult:
    if loop == "Python":
        monkeypatch.setenv("ROBOGEN_REFERENCE_LOOP", "1")
    else:
        monkeypatch.delenv("ROBOGEN_REFERENCE_LOOP", raising=False)
    result = simulate_system(path, **kwargs)
    assert result.stats.loop == loop
    return result


def signature(table: Table) -> list[tuple]:
    """Every column byte for byte: name, FMI type, NumPy type, values (objects as a list), validity."""
    out = []
    for name, kind, values, valid in zip(table.names, table.types, table.arrays, table.valid):
        data = values.tolist() if values.dtype == object else values.tobytes()
        out.append((name, kind, values.dtype.str, data, None if valid is None else valid.tobytes()))
    return out


@pytest.mark.parametrize("system", [TYPES, TRIVIAL, TICKER, TICKER + "[record]\nevery = 0.2\n"])
def test_the_engine_and_the_reference_loop_fill_the_same_columns(monkeypatch, write_system, system):
    path = write_system(system)
    python, c = run("Python", monkeypatch, path), run("C", monkeypatch, path)
    assert signature(c.table) == signature(python.table)
    assert len(c.table) == len(c.rows) > 10


def test_every_fmi_type_has_its_numpy_type_and_clocked_cells_their_validity(monkeypatch, write_system):
    result = run("C", monkeypatch, write_system(TYPES))
    table = result.table
    assert table.array("time").dtype == np.float64 and table.array("superdense").dtype == np.int32
    assert table.array("a.out").dtype == np.int8 and table.array("b.tin").dtype == np.int8  # clocks: 1 while active
    for x in SUFFIXES:
        for name in (f"a.c_{x}", f"b.ci_{x}", f"b.y_{x}"):
            assert table.array(name).dtype == np.dtype(DTYPES[x]), name
        assert table.validity(f"b.y_{x}") is None  # an unclocked value: a cell in every row
        valid = table.validity(f"a.c_{x}")  # a clocked output: a value only while its clock ticks
        assert valid is not None and valid.tolist() == (table.array("a.out") == 1).tolist()
    ticks = table.array("a.out") == 1
    assert 0 < ticks.sum() < len(table)  # the clock ticks in some rows only
    assert (table.array("a.c_f64")[~ticks] == 0).all() and all(v is None for v in table.array("a.c_s")[~ticks])
    rows = result.rows  # the rows are the columns' values, None where a cell is empty
    i = result.columns.index("a.c_f64")
    assert [r[i] for r in rows] == [v if t else None for v, t in zip(table.array("a.c_f64").tolist(), ticks.tolist())]
    assert result.column("a.c_bin") == [r[result.columns.index("a.c_bin")] for r in rows]
    assert all(isinstance(v, bytes) for v in result.column("a.c_bin") if v is not None)
    assert all(type(v) is bool for v in result.column("b.y_b"))


def test_a_row_of_one_float_costs_its_values_bytes(monkeypatch, write_system):
    result = run("C", monkeypatch, write_system(TRIVIAL))
    n = len(result.table)
    assert n == 10_002  # (0, 0), (0, 1) of the start's event iteration, then a row per step
    assert result.table.nbytes == n * (8 + 4 + 8)  # time, superdense, t.y: nothing else per row
    assert [a.base is None or a.base.nbytes == a.nbytes for a in result.table.arrays] == [True] * 3  # no spare room kept


def test_the_table_converts_to_numpy_and_arrow(monkeypatch, write_system):
    result = run("C", monkeypatch, write_system(TYPES))
    table = result.table
    records = table.to_numpy()
    assert records.dtype.names == tuple(result.columns) and len(records) == len(table)
    assert records["b.y_u64"].tolist() == table.array("b.y_u64").tolist()
    arrow = table.to_arrow()
    assert arrow.column_names == result.columns
    assert [list(r.values()) for r in arrow.to_pylist()] == result.rows  # null where a cell is empty
    assert arrow.schema.field("a.c_f32").type == pa.float32() and arrow.schema.field("b.y_s").type == pa.string()
    # a numeric column without empty cells is shared, not copied
    time = arrow.column("time").chunk(0)
    assert time.buffers()[1].address == table.array("time").ctypes.data


def test_rows_given_as_lists_keep_working():
    columns = ["time", "superdense", "m.v", "m.c", "m.s"]
    rows = [[0.0, 0, 1.5, 1, "a"], [0.5, 0, None, 0, None], [1.0, 1, -2.0, 1, "b"]]
    result = SimulationResult(columns, rows, None)
    assert result.rows is rows and result.column("m.v") == [1.5, None, -2.0] and result.column("m.s") == ["a", None, "b"]
    assert result.table.types == ["Float64", "Superdense", "Float64", "Int64", "String"]
    assert result.array("m.c").tolist() == [1, 0, 1] and result.table.validity("m.v").tolist() == [True, False, True]
    with pytest.raises(KeyError, match="no column 'm.w' was recorded"):
        result.column("m.w")


def test_rows_and_chunks_of_columns_join_in_order():
    recorder = Recorder(["a.x", "a.c", "a.s"], None, None, types=["Float32", "Clock", "String"], rows_hint=2)
    recorder.append_event_row([0.0, 0, 0.5, 1, "x"])
    chunk = [np.array([0.1, 0.2]), np.array([0, 0], np.int32), np.array([0.25, 3.0]), np.array([0, 1], np.uint64), [None, "y"]]
    valid = [None, None, None, None, np.array([False, True])]
    recorder.append_chunk(chunk, valid, 2, lambda: pytest.fail("no file: the rows are not made"))
    recorder.append_rows([[0.3, 1, None, 0, None]])
    table = recorder.table()
    assert table.rows == [[0.0, 0, 0.5, 1, "x"], [0.1, 0, 0.25, 0, None], [0.2, 0, 3.0, 1, "y"], [0.3, 1, None, 0, None]]
    assert table.array("a.x").dtype == np.float32 and table.validity("a.x").tolist() == [True, True, True, False]


def test_an_event_iteration_longer_than_a_chunk_keeps_every_column_in_place(monkeypatch, write_system):
    # 6,000 instants at t = 0.5 in one call of the engine: its rows outgrow the chunk's 4,096,
    # and the engine moves each column's values to its place in the larger chunk
    path = write_system('[experiment]\nstop = 3.0\nstep = 0.1\nmax_event_iterations = 6000\n[instances.z]\nfmu = "{zeno}"\n'
                        '[instances.k]\nfmu = "{ticker}"\n')
    tables = []
    for loop in ("Python", "C"):
        monkeypatch.setenv("ROBOGEN_REFERENCE_LOOP", "1") if loop == "Python" else monkeypatch.delenv("ROBOGEN_REFERENCE_LOOP", raising=False)
        with pytest.raises(RunError, match="did not settle after 6000 super-dense instants"):
            simulate_system(path, keep_rows=True, output=path.with_suffix(f".{loop}.csv"))
        tables.append(path.with_suffix(f".{loop}.csv").read_bytes())
    assert tables[0] == tables[1]
    lines = tables[1].decode().splitlines()
    assert len(lines) > 6000 and lines[-1].startswith("0.5,5999,")
    assert len(lines[0].split(",")) > 3  # columns beyond time and superdense, each moved
