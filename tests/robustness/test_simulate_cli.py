"""Bad command lines of ``robogen simulate``, ``plot`` and ``package-py``: each ends in its exit
status (1 the input, 2 the usage) with a message that says what is wrong; never a Python
traceback, never "internal error" (exit 3 means a bug in robogen, not a user's mistake)."""

from __future__ import annotations

import importlib.util
import os
import sys
from pathlib import Path

import pytest

from robogen.cli import main

ROOT = Path(__file__).resolve().parents[2]
TRIVIAL = '[experiment]\nstop = 1.0\nstep = 0.1\n[instances.t]\nfmu = "fmus/trivial.fmu"\n'


def _builder():
    spec = importlib.util.spec_from_file_location("robogen_test_fmus_build", ROOT / "tests" / "cosim" / "fmus" / "build.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules.setdefault(spec.name, module)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def fmus(tmp_path_factory) -> Path:
    """A folder with the test FMUs the table uses, and one that gives a value reference twice."""
    out = tmp_path_factory.mktemp("robustness-fmus")
    builder = _builder()
    for name in ("trivial", "failer", "alltypes"):
        builder.build(name, out)
    spec = {"vars": [builder.var("y", 1, "Float64", "output", "continuous"),
                     builder.var("u", 1, "Float64", "input", "continuous", start="0")]}
    (out / "dup").mkdir()
    builder.build("trivial", out / "dup", spec=spec)
    return out


FILES = {
    "ok.toml": TRIVIAL,
    "failer.toml": TRIVIAL.replace("trivial", "failer"),
    "crash.toml": '[experiment]\nstop = 1.0\nstep = 0.1\n[instances.d]\nfmu = "fmus/failer.fmu"\n'
                  "start = { crash_time = 0.5, fail_time = 9.0 }\nisolate = true\n",
    "nan.toml": TRIVIAL.replace("trivial", "alltypes") + "start = { u_f64 = nan }\n",
    "dup.toml": TRIVIAL.replace("fmus/trivial", "fmus/dup/trivial"),
    "record.toml": TRIVIAL + '[record]\nvariables = ["t.q*"]\n',
    "connect.toml": 'connections = ["t.y -> t.w"]\n' + TRIVIAL,
    "isolate.toml": TRIVIAL + 'isolate = "yes"\n',
    "nofmu.toml": TRIVIAL.replace("fmus/trivial.fmu", "nowhere.fmu"),
    "notfmu.toml": TRIVIAL.replace("fmus/trivial.fmu", "text.fmu"),
    "text.fmu": "not a zip archive\n",
    "binary.toml": bytes(range(256)) * 4,
    "results.csv": "time,superdense,t.y\n0.0,0,0.0\n0.1,0,0.1\n",
    "bad.csv": "time,superdense,t.y\n0.0,0,0.0\n0.1,0,abc\n",
    "ragged.csv": "time,superdense,t.y\n0.0,0,0.0\n0.1,0\n",
    "other.csv": "x,y\n1,2\n",
    "random.bin": bytes(range(256)) * 8,
    "a_file": "a file, not a folder\n",
    "raising.py": "raise RuntimeError('this module cannot be imported')\n",
    "limited.py": "from robogen.pyfmu import Clock, Model, Setting\n\n\nclass Timer(Model):\n"
                  "    period = Setting(0.5, 'interval [s]')\n    tick = Clock(kind='constant', interval='period')\n",
}

# (command line, exit status, what the message must say)
CASES = [
    # simulate: the system file
    (["simulate", "missing.toml"], 1, "cannot read system file: No such file or directory"),
    (["simulate", "binary.toml"], 1, "system file is not UTF-8 text"),
    (["simulate", "record.toml"], 1, "no output or input clock matches 't.q*'"),
    (["simulate", "connect.toml"], 1, "FMU instance 't' has no variable 'w'"),
    (["simulate", "isolate.toml"], 1, "'isolate' must be true or false"),
    (["simulate", "nofmu.toml"], 1, "FMU file not found"),
    (["simulate", "notfmu.toml"], 1, "while loading the FMU of instance 't'"),
    (["simulate", "dup.toml"], 1, "gives value reference 1 to both 'y' and 'u'"),
    (["simulate", "nan.toml"], 1, "instance 't' refused the start value nan of 'u_f64'"),
    # simulate: the results files
    (["simulate", "ok.toml", "-o", "ok.toml"], 1, "-o ok.toml is also an input of this command"),
    (["simulate", "ok.toml", "-o", "fmus/trivial.fmu"], 1, "is also an input of this command"),
    (["simulate", "ok.toml", "-o", "r.csv", "--events", "r.csv"], 1, "--events r.csv is also an input"),
    (["simulate", "ok.toml", "-o", "r.csv", "--events", "ok.toml"], 1, "--events ok.toml is also an input"),
    (["simulate", "ok.toml", "-o", "fmus"], 1, "-o fmus is a folder; name a file"),
    (["simulate", "ok.toml", "-o", "a_file/r.csv"], 1, "a_file is a file, not a folder"),
    # simulate: time
    (["simulate", "ok.toml", "--step", "1e-300"], 1, "the communication step 1e-300 cannot advance time"),
    (["simulate", "ok.toml", "--step", "0"], 1, "the communication step must be positive, not 0.0"),
    (["simulate", "ok.toml", "--step", "nan"], 1, "the communication step must be positive, not nan"),
    (["simulate", "ok.toml", "--stop", "-1"], 1, "the stop time -1.0 is before the start time 0.0"),
    (["simulate", "ok.toml", "--step", "fast"], 2, "argument --step: 'fast' is not a number"),
    (["simulate", "ok.toml", "--realtime", "0"], 2, "the real-time factor must be positive"),
    (["simulate", "ok.toml", "--isolated"], 2, "unrecognized arguments: --isolated"),
    # simulate: FMUs that fail
    (["simulate", "failer.toml"], 1, "fmi3DoStep returned fmi3Error at t=0.5; the results recorded so far are kept"),
    (["simulate", "crash.toml"], 1, "instance 'd' crashed (SIGSEGV) in fmi3DoStep at t=0.4"),
    # plot
    (["plot", "missing.csv"], 1, "cannot read results: No such file or directory"),
    (["plot", "random.bin"], 1, "not a results file of 'robogen simulate': it is not UTF-8 text"),
    (["plot", "bad.csv"], 1, "column 't.y' has the non-numeric value 'abc' in row 3"),
    (["plot", "ragged.csv"], 1, "row 3 has 2 cells; the header names 3 columns"),
    (["plot", "other.csv"], 1, "the header must start with time,superdense"),
    (["plot", "results.csv", "--vars", "u.*"], 1, "no column matches 'u.*'"),
    (["plot", "results.csv", "-o", "results.csv"], 1, "-o results.csv is also an input of this command"),
    (["plot", "results.csv", "-o", "figure.xyz"], 1, "no figure format 'xyz'"),
    # package-py
    (["package-py", "raising:Thing", "-o", "x.fmu"], 1, "importing 'raising' failed: RuntimeError: this module cannot be imported"),
    (["package-py", "limited:Timer", "--set", "period=0", "-o", "x.fmu"], 1, "--set period=0: 0.0 is not > 0 (the interval of clock 'tick')"),
    (["package-py", "limited:Timer", "--set", "period=-1", "-o", "x.fmu"], 1, "--set period=-1: -1.0 is not > 0"),
    (["package-py", "limited:Timer", "--set", "perio=1", "-o", "x.fmu"], 1, "has no setting 'perio' (did you mean 'period'?)"),
    (["package-py", "limited:Timer", "-o", "x.zip"], 1, "the output 'x.zip' must end in .fmu"),
    (["package-py", "limited", "-o", "x.fmu"], 1, "is not MODULE:CLASS"),
    (["package-py", "limited:Clock", "-o", "x.fmu"], 1, "is not a subclass of robogen.pyfmu.Model"),
    (["package-py", "limited:Timer"], 2, "the following arguments are required: -o/--output"),
]


@pytest.fixture
def world(tmp_path, fmus, monkeypatch):
    """tmp_path as the working directory, with FILES and the FMUs (fmus/) in it."""
    for name, content in FILES.items():
        (tmp_path / name).write_bytes(content if isinstance(content, bytes) else content.encode())
    (tmp_path / "fmus").symlink_to(fmus)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setenv("TMPDIR", str(tmp_path))
    return tmp_path


@pytest.mark.parametrize("argv, status, message", CASES, ids=[f"{c[0][0]}-{i}" for i, c in enumerate(CASES)])
def test_a_bad_command_line_gets_its_status_and_a_message_without_a_traceback(world, capsys, argv, status, message):
    before = {p: p.read_bytes() for p in world.iterdir() if p.is_file()}
    assert main(argv) == status
    err = capsys.readouterr().err
    assert message in err
    assert "Traceback" not in err and "internal error" not in err
    # no input was touched, nothing half-written was left behind
    assert {p: p.read_bytes() for p in before} == before
    assert not list(world.glob(".*.tmp")) and not list(world.glob("robogen-sim-*"))
    assert not os.path.exists(world / "x.fmu")


def test_the_table_is_large_enough():
    assert len(CASES) >= 40
