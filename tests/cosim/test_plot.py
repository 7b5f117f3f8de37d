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
