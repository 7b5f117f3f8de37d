"""robogen.outputs: outputs never destroy inputs, and files are replaced only when complete."""

from __future__ import annotations

import os
import threading

import pytest

from robogen.diagnostics import RobogenError
from robogen.outputs import MARKER, output_file, output_folder, replacing, write_text


def test_an_output_that_is_an_input_is_refused_by_any_path(tmp_path, monkeypatch):
    model = tmp_path / "m.rst"
    model.write_text("model")
    monkeypatch.chdir(tmp_path)
    for spelling in ("m.rst", "./m.rst", str(model), "../" + tmp_path.name + "/m.rst"):
        with pytest.raises(RobogenError, match="is also an input of this command"):
            output_file(spelling, inputs=[model])
    os.link(model, tmp_path / "hard.rst")
    with pytest.raises(RobogenError, match="is also an input"):
        output_file(tmp_path / "hard.rst", inputs=[model])
    assert model.read_text() == "model"


def test_a_folder_or_a_path_under_a_file_is_refused(tmp_path):
    (tmp_path / "d").mkdir()
    (tmp_path / "f").write_text("x")
    with pytest.raises(RobogenError, match="is a folder; name a file"):
        output_file(tmp_path / "d")
    with pytest.raises(RobogenError, match="is a file, not a folder"):
        output_file(tmp_path / "f" / "x.csv")
    assert output_file(tmp_path / "new" / "deep" / "x.csv").parent.is_dir()


def test_replacing_keeps_the_old_file_when_writing_fails(tmp_path):
    target = tmp_path / "out.fmu"
    target.write_text("good")
    with pytest.raises(ZeroDivisionError):
        with replacing(target) as tmp:
            tmp.write_text("half")
            1 / 0
    assert target.read_text() == "good"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.fmu"]  # no temporary left
    write_text(target, "new")
    assert target.read_text() == "new"


def test_parallel_writers_do_not_share_a_temporary_file(tmp_path):
    target = tmp_path / "same.fmu"
    errors = []

    def write(i):
        try:
            for _ in range(20):
                write_text(target, f"writer {i}\n" * 1000)
        except Exception as exc:  # pragma: no cover - the failure this test is about
            errors.append(exc)

    threads = [threading.Thread(target=write, args=(i,)) for i in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    lines = set(target.read_text().splitlines())
    assert len(lines) == 1  # one writer's complete content, never a mix


def test_a_written_file_has_ordinary_permissions(tmp_path):
    mask = os.umask(0o022)
    try:
        write_text(tmp_path / "x.txt", "x")
    finally:
        os.umask(mask)
    assert (tmp_path / "x.txt").stat().st_mode & 0o777 == 0o644


def test_an_output_folder_must_be_new_empty_or_robogens(tmp_path):
    user = tmp_path / "user"
    user.mkdir()
    (user / "notes.txt").write_text("mine")
    with pytest.raises(RobogenError, match="robogen did not write and it is not empty"):
        output_folder(user, command="compile")
    assert (user / "notes.txt").read_text() == "mine" and not (user / MARKER).exists()
    fresh = output_folder(tmp_path / "fresh", command="compile")
    assert (fresh / MARKER).is_file()
    (fresh / "sources").mkdir()
    assert output_folder(fresh, command="compile") == fresh  # robogen's own folder: allowed again
    empty = tmp_path / "empty"
    empty.mkdir()
    assert (output_folder(empty, command="compile") / MARKER).is_file()


def test_an_output_folder_holding_an_input_or_being_a_file_is_refused(tmp_path):
    models = tmp_path / "models"
    models.mkdir()
    (models / MARKER).write_text("")  # even a marked folder may not swallow an input
    (models / "m.rst").write_text("x")
    with pytest.raises(RobogenError, match="holds the input"):
        output_folder(models, command="compile", inputs=[models / "m.rst"])
    (tmp_path / "file").write_text("x")
    with pytest.raises(RobogenError, match="is a file; name a folder"):
        output_folder(tmp_path / "file", command="compile")
