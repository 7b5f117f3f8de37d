"""Results for large runs: Parquet output (-o results.parquet) with the CSV's columns and values,
written in bounded memory, and decimation ([record] every = SECONDS)."""

from __future__ import annotations

import tracemalloc

import pyarrow.parquet as pq
import pytest

from robogen.cosim import columnar, simulate_system
from robogen.cosim.recorder import Recorder
from robogen.diagnostics import RobogenError

TYPES = ("f32", "f64", "i8", "u8", "i16", "u16", "i32", "u32", "i64", "u64", "b", "s", "bin", "e")
ALLTYPES = f"""connections = {[f"a.y_{t} -> b.u_{t}" for t in TYPES] + ["a.out -> b.tin"] + [f"a.c_{t} -> b.ci_{t}" for t in TYPES]}
[experiment]
stop = 1.2
step = 0.1
[instances.a]
fmu = "{{alltypes}}"
[instances.b]
fmu = "{{alltypes}}"
[record]
variables = {["a.*", "b.*"] + [f"b.ci_{t}" for t in TYPES]}
""".replace("'", '"')


def test_parquet_holds_the_csvs_columns_and_values(write_system, tmp_path):
    # Every FMI type, clocks, and clocked values that are absent while their clock is not active.
    path = write_system(ALLTYPES)
    csv_run = simulate_system(path, output=tmp_path / "r.csv")
    parquet_run = simulate_system(path, output=tmp_path / "r.parquet", keep_rows=False)
    table = pq.read_table(tmp_path / "r.parquet")
    assert table.column_names == csv_run.columns
    rows = [list(r.values()) for r in table.to_pylist()]
    assert rows == csv_run.rows  # the same values, None where the CSV cell is empty
    assert parquet_run.stats.steps == csv_run.stats.steps
    types = dict(zip(table.column_names, (str(f.type) for f in table.schema)))
    assert (types["a.y_f32"], types["a.y_u64"], types["a.y_b"], types["a.y_s"], types["a.y_bin"], types["a.tick"]) == (
        "float", "uint64", "bool", "string", "binary", "int8")
    assert rows[0][table.column_names.index("a.c_bin")] == b"\x01"  # (0, 0): the tick's clocked Binary
    assert rows[1][table.column_names.index("a.c_bin")] is None  # (0, 1): gone with its clock
    # Written back as CSV by the recorder, the Parquet values give the CSV byte for byte.
    again = Recorder(csv_run.columns[2:], tmp_path / "again.csv", None, keep_rows=False, types=_fmi_types(path))
    again.append_rows(rows)
    again.close()
    assert (tmp_path / "again.csv").read_bytes() == (tmp_path / "r.csv").read_bytes()


def _fmi_types(path) -> list[str]:
    """The FMI types of the system's recorded variables, in column order."""
    from robogen.cosim.assemble import build_master

    master, cache = build_master(path, keep_rows=False)
    cache.close()
    return [column.variable.type for column in master.plan.wiring.columns]


def _peak(write_system, tmp_path, stop: float) -> tuple[int, int]:
    path = write_system(f'[experiment]\nstop = {stop}\nstep = 0.001\n[instances.a]\nfmu = "{{trivial}}"\n',
                        name=f"long{stop}.toml")
    tracemalloc.start()
    try:
        simulate_system(path, output=tmp_path / f"long{stop}.parquet", keep_rows=False)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    return peak, pq.ParquetFile(tmp_path / f"long{stop}.parquet").metadata.num_rows


def test_a_parquet_run_holds_one_batch_of_rows_at_most(write_system, tmp_path, monkeypatch):
    monkeypatch.setattr(columnar, "BATCH_CELLS", 6_000)  # 3 columns (time, superdense, a.y): batches of 2,000 rows
    small, small_rows = _peak(write_system, tmp_path, 10.0)
    large, large_rows = _peak(write_system, tmp_path, 40.0)
    assert (small_rows, large_rows) == (10_002, 40_002)  # (0, 0), (0, 1) of the start's event iteration, then a row per step
    # Four times the rows, not four times the memory: rows held in Python cost ~100 bytes each,
    # so 30,000 more rows held would add ~3 MB; the peak grows by far less than that.
    assert large - small < 500_000, (small, large)
    assert pq.ParquetFile(tmp_path / "long40.0.parquet").metadata.num_row_groups == 21  # 20 batches of 2,000 rows, then the last 2


# ----------------------------------------------------------------------------------------
# Decimation


def test_decimation_keeps_every_event_row_and_one_plain_row_per_interval(write_system):
    # ticker ticks every 0.25 s (event iterations: rows (t, 0) and (t, 1)); communication step 0.05.
    text = """
[experiment]
stop = 1.0
step = 0.05
[instances.ticker]
fmu = "{ticker}"
[record]
variables = ["ticker.tick", "ticker.ticks"]
"""
    full = simulate_system(write_system(text, name="full.toml"))
    rows = simulate_system(write_system(text + "every = 0.2\n", name="decimated.toml")).rows
    kept = [(round(t, 9), k) for t, k, *_ in rows]
    # intervals [0, 0.2), [0.2, 0.4), ...: the event at 0 covers the first, a plain row starts
    # each of the others, and an event in an interval with a row already kept is kept too.
    assert kept == [(0.0, 0), (0.0, 1), (0.2, 0), (0.25, 0), (0.25, 1), (0.4, 0), (0.5, 0), (0.5, 1), (0.6, 0),
                    (0.75, 0), (0.75, 1), (0.8, 0), (1.0, 0), (1.0, 1)]
    assert all(row in full.rows for row in rows)  # the same rows, values and all, only fewer


def test_decimation_keeps_the_last_row_of_the_run(write_system, tmp_path):
    path = write_system('[experiment]\nstop = 1.0\nstep = 0.3\n[instances.a]\nfmu = "{trivial}"\n[record]\nevery = 0.4\n')
    result = simulate_system(path, output=tmp_path / "r.csv")
    # the start's event iteration (0, 0), (0, 1), then points 0.3, 0.6, 0.9 and the stop time 1.0;
    # intervals of 0.4: [0, 0.4) has the event's rows, 0.6 and 0.9 start theirs, and 1.0 is the last
    assert [(round(r[0], 9), r[1]) for r in result.rows] == [(0.0, 0), (0.0, 1), (0.6, 0), (0.9, 0), (1.0, 0)]
    assert result.columns == ["time", "superdense", "a.y"]  # [record] without variables: the default
    assert len((tmp_path / "r.csv").read_text().splitlines()) == 6


def test_decimation_holds_when_rows_only_go_to_the_csv(write_system, tmp_path):
    # Without rows kept in memory the quiet stretches may write CSV lines themselves (the C loop):
    # decimation must still apply. Same system as above: the same five rows, in the file.
    path = write_system('[experiment]\nstop = 1.0\nstep = 0.3\n[instances.a]\nfmu = "{trivial}"\n[record]\nevery = 0.4\n')
    simulate_system(path, output=tmp_path / "r.csv", keep_rows=False)
    lines = (tmp_path / "r.csv").read_text().splitlines()
    rows = [line.split(",") for line in lines[1:]]
    assert [(round(float(t), 9), int(k)) for t, k, *_ in rows] == [(0.0, 0), (0.0, 1), (0.6, 0), (0.9, 0), (1.0, 0)]


@pytest.mark.parametrize("value, message", [
    ("0", "'every' must be positive"),
    ('"0.1"', "'every' must be a finite number"),
    ("inf", "'every' must be a finite number"),
])
def test_a_bad_decimation_interval_is_reported_at_its_key(write_system, value, message):
    path = write_system(f'[experiment]\nstop = 1.0\nstep = 0.1\n[instances.a]\nfmu = "{{trivial}}"\n[record]\nevery = {value}\n')
    with pytest.raises(RobogenError) as failure:
        simulate_system(path)
    [diagnostic] = failure.value.diagnostics
    assert diagnostic.message == message
    assert (diagnostic.span.path, diagnostic.span.line, diagnostic.span.column) == (str(path), 7, 1)  # at the key
