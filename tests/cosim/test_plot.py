"""robogen plot: a PNG from a results CSV; bad input gets a located error."""

from __future__ import annotations

from robogen.cli import main


def test_plot_writes_a_png_and_rejects_unknown_columns(tmp_path, capsys):
    csv = tmp_path / "r.csv"
    csv.write_text("time,superdense,a.tick,a.count,a.x\n0.0,0,1,1,0.0\n0.0,1,0,,0.5\n0.5,0,0,,1.0\n")
    png = tmp_path / "r.png"
    assert main(["plot", str(csv), "-o", str(png)]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert main(["plot", str(csv), "--vars", "b.*", "-o", str(png)]) == 1
    assert "error: no column matches 'b.*'" in capsys.readouterr().err
    (tmp_path / "bad.csv").write_text("x,y\n1,2\n")
    assert main(["plot", str(tmp_path / "bad.csv"), "-o", str(png)]) == 1


def test_text_columns_are_left_out_and_patterns_follow_the_record_rule(tmp_path, capsys):
    csv = tmp_path / "r.csv"
    csv.write_text('time,superdense,a.s,a.bin,a.x,a.x[1]\n0.0,0,"p,q",0x01,0.0,1\n0.5,0,"",0x,1.0,2\n')
    png = tmp_path / "r.png"
    assert main(["plot", str(csv), "-o", str(png)]) == 0
    assert "left out the text columns (String or Binary values): a.s, a.bin" in capsys.readouterr().err
    assert main(["plot", str(csv), "--vars", "a.x[1]", "-o", str(png)]) == 0  # a name, though it looks like a pattern
    assert main(["plot", str(csv), "--vars", "a.s", "-o", str(png)]) == 1  # only text: nothing to plot
    assert "error: nothing to plot" in capsys.readouterr().err
