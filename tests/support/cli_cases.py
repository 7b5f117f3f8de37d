"""Table-driven tests of command lines: a :class:`Case` names the files a command finds in a fresh
folder, the command line, and what it must give (exit code, a part of the message on stdout or
stderr, files it must leave unchanged); :func:`run_case` runs it through ``robogen.cli.main`` as
the ``robogen`` script does and checks that no traceback, internal error or temporary file is left."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from robogen.cli import main


@dataclass
class Case:
    name: str
    argv: list[str]
    code: int
    stream: str  # where `message` appears: "out" or "err"
    message: str
    files: dict[str, str | bytes] = field(default_factory=dict)  # path -> content ("/" at the end: a folder)
    setup: Callable[[Path], None] | None = None
    unchanged: tuple[str, ...] = ()  # files the command must leave as they were


def run_case(case: Case, tmp_path: Path, monkeypatch, capsys) -> None:
    for name, content in case.files.items():
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if name.endswith("/"):
            path.mkdir(exist_ok=True)
        elif isinstance(content, bytes):
            path.write_bytes(content)
        else:
            path.write_text(content, encoding="utf-8")
    if case.setup is not None:
        case.setup(tmp_path)
    before = {name: (tmp_path / name).read_bytes() for name in case.unchanged}
    monkeypatch.chdir(tmp_path)

    code = main(case.argv)

    out, err = capsys.readouterr()
    assert code == case.code, err
    assert case.message in (out if case.stream == "out" else err), (out, err)
    for text in (out, err):
        assert "Traceback" not in text and "internal error" not in text
    assert {name: (tmp_path / name).read_bytes() for name in case.unchanged} == before
    assert not list(tmp_path.glob("**/.*.tmp")), "a temporary file was left behind"
