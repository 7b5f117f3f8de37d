"""The recorder: cell formats, results files replaced only by a run that recorded rows, flushes."""

from __future__ import annotations

import csv
import io

import pytest

from robogen.cosim import RunError, simulate_system
from robogen.cosim.recorder import Recorder, binary_cell, string_cell


def test_strings_are_always_quoted_and_binaries_are_hexadecimal():
    assert string_cell("") == '""' and string_cell(None) == ""  # the empty String is not an absent value
    assert string_cell('say "hi", twice') == '"say ""hi"", twice"'
    assert binary_cell(b"") == "0x" and binary_cell(b"\x00\xff\x10") == "0x00ff10" and binary_cell(None) == ""
    assert next(csv.reader(io.StringIO('"say ""hi"", twice",0x00ff10,""'))) == ['say "hi", twice', "0x00ff10", ""]


def test_rows_with_text_columns_are_written_cell_by_cell(tmp_path):
    out = tmp_path / "r.csv"
    recorder = Recorder(["a.s", "a.bin", "a.x", "a.b"], out, None, keep_rows=False, types=["String", "Binary", "Float64", "Boolean"])
    recorder.append_row([0.0, 0, "x,y", b"\x01", 0.1, True])
    recorder.append_rows([[0.5, 0, None, None, 1e-300, False]])
    recorder.close()
    assert out.read_text() == 'time,superdense,a.s,a.bin,a.x,a.b\n0.0,0,"x,y",0x01,0.1,True\n0.5,0,,,1e-300,False\n'


def test_a_run_that_fails_before_its_first_row_leaves_the_previous_results(write_system, tmp_path):
    out = tmp_path / "results.csv"
    out.write_text("the previous results\n")
    path = write_system('[experiment]\nstop = 1.0\nstep = 0.1\n[instances.a]\nfmu = "{alltypes}"\nstart = { u_f64 = nan }\n')
    with pytest.raises(RunError) as failure:
        simulate_system(path, output=out)
    assert failure.value.results is None
    assert out.read_text() == "the previous results\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["results.csv", "system.toml"]  # no temporary file left


def test_a_run_that_fails_after_rows_replaces_the_results_with_them(write_system, tmp_path):
    out = tmp_path / "results.csv"
    out.write_text("the previous results\n")
    path = write_system('[experiment]\nstop = 2.0\nstep = 0.1\n[instances.f]\nfmu = "{failer}"\n')
    with pytest.raises(RunError) as failure:
        simulate_system(path, output=out)
    assert failure.value.results == out
    assert out.read_text().splitlines()[-1] == "0.5,0,0.5"  # the last point before the failing step
