"""System file checks: every problem is reported at its line and column in the TOML file."""

from __future__ import annotations

import pytest

from robogen.cli import main
from robogen.cosim import simulate_system
from robogen.cosim.system import split_name
from robogen.diagnostics import RobogenError

HEAD = """
[experiment]
stop = 1.0
step = 0.1
[instances.ticker]
fmu = "{ticker}"
[instances.r1]
fmu = "{relay}"
[instances.ball]
fmu = "{ball}"
"""


def errors(write_system, text):
    path = write_system(text)
    with pytest.raises(RobogenError) as exc:
        simulate_system(path)
    return [(d.span.line, d.span.column, d.message) for d in exc.value.diagnostics]


def test_split_name_uses_only_the_first_dot():
    assert split_name("dmodel.moveDiscreteCommand.target_X") == ("dmodel", "moveDiscreteCommand.target_X")
    assert split_name("nodot") is None and split_name(".x") is None


def test_toml_syntax_error_is_located(write_system):
    assert errors(write_system, "[experiment]\nstop = = 1\n") == [(2, 8, "invalid TOML: Invalid value")]


def test_schema_errors_are_collected_and_located(write_system):
    got = errors(write_system, """
[experiment]
stopp = 1.0
step = -0.1
[instances.a]
fmu = 3
[instances."b.c"]
fmu = "x.fmu"
[record]
variables = "a.x"
""")
    assert got == [
        (3, 1, "unknown key 'stopp' (did you mean 'stop'?)"),
        (4, 1, "'step' must be positive"),
        (6, 1, "instance 'a' needs fmu = \"PATH.fmu\""),
        (7, 1, "instance name 'b.c' must be an identifier (letters, digits, '_'; no dots)"),
        (10, 1, "'variables' must be a list of \"instance.variable\" (or \"instance.*\")"),
    ]


def test_connection_errors_name_the_problem(write_system):
    got = errors(write_system, """connections = [
  "tickr.out -> r1.u",
  "ticker.outt -> r1.u",
  "ticker.out -> r1.x_in",
  "r1.u -> ball.h0",
  "ball.h -> ball.e",
  "r1.y -> ticker.tick",
]""" + HEAD)
    assert got == [
        (2, 3, "unknown instance 'tickr' (did you mean 'ticker'?)"),
        (3, 3, "FMU instance 'ticker' has no variable 'outt' (did you mean 'out'?)"),
        (4, 3, "a clock connects only to a clock: 'ticker.out' is a clock, 'r1.x_in' is a variable of type Int64"),
        (5, 3, "'ball.h0' is not an input (causality parameter)"),
        (5, 3, "'r1.u' is not an output (causality input)"),
        (5, 3, "a clock connects only to a clock: 'r1.u' is a clock, 'ball.h0' is a variable of type Float64"),
        # an instance may feed itself (FMI allows it); this one fails only because e is a parameter
        (6, 3, "'ball.e' is not an input (causality parameter)"),
    ]
    # r1.y -> ticker.tick is fine: a triggered output clock may drive a periodic input clock's port


def test_malformed_connection_is_a_schema_error(write_system):
    got = errors(write_system, 'connections = ["a.b -> c.d", "nonsense", 3]' + HEAD)
    assert got == [(1, 30, 'a connection is written "instance.variable -> instance.variable"'),
                   (1, 42, 'a connection is written "instance.variable -> instance.variable"')]


def test_type_and_clocked_consistency(write_system):
    got = errors(write_system, """connections = [
  "ball.h -> r1.x_in",
  "ticker.count -> r1.x_in",
]""" + HEAD)
    assert (2, 3, "type mismatch: 'ball.h' is Float64, 'r1.x_in' is Int64") in got
    assert not any("clocked" in message for _line, _column, message in got)  # sampled: a value crosses clock domains
    assert (3, 3, "'r1.x_in' is connected twice") in got
    got = errors(write_system, 'connections = ["ticker.count -> r1.x_in"]' + HEAD)
    assert got == [(1, 16, "'ticker.count' is clocked by ticker.out and 'r1.x_in' by r1.u: a clocked value crosses only to "
                           "a clock it drives")]


def test_start_values_are_checked(write_system):
    got = errors(write_system, HEAD + 'start = { h0 = "high", hh = 1, h = 2.0 }\n')
    assert got == [
        (11, 11, "start value for 'h0': Float64 needs a number"),
        (11, 24, "FMU instance 'ball' has no variable 'hh' (did you mean 'h'?)"),
        (11, 32, "cannot set a start value for 'h' (causality output, initial calculated)"),
    ]


def test_missing_fmu_and_missing_stop(write_system):
    got = errors(write_system, "[experiment]\nstop = 1\nstep = 0.1\n[instances.x]\nfmu = \"nowhere.fmu\"\n")
    assert got[0][:2] == (5, 1) and got[0][2].startswith("FMU file not found")
    got = errors(write_system, "[instances.x]\nfmu = \"{trivial}\"\n")
    assert got == [(1, 1, "no stop time: give [experiment] stop = ... or --stop")]


def test_cli_reports_located_errors_without_traceback(write_system, capsys):
    path = write_system('connections = ["ticker.outt -> r1.u"]' + HEAD)
    assert main(["simulate", str(path), "-o", str(path.with_suffix(".csv"))]) == 1
    err = capsys.readouterr().err
    assert ":1:16: error: FMU instance 'ticker' has no variable 'outt' (did you mean 'out'?)" in err
    assert "Traceback" not in err


# ----------------------------------------------------------------------------------------
# [record]: names and patterns (the rule `robogen plot --vars` follows too)


def test_record_takes_names_and_the_patterns_plot_accepts(write_system):
    path = write_system(HEAD + '[record]\nvariables = ["ball.h0", "*.?", "ticker.[ot]*", "r1.x_*"]\n')
    columns = simulate_system(path).columns[2:]
    # a name selects any variable (ball.h0 is a parameter); a pattern selects among the outputs and
    # input clocks, in declaration order, each once
    assert columns == ["ball.h0", "r1.u", "r1.y", "r1.n", "ball.h", "ball.v", "ticker.tick", "ticker.out",
                       "ticker.ticks", "r1.x_out"]


def test_record_patterns_that_match_nothing_are_located(write_system):
    got = errors(write_system, HEAD + '[record]\nvariables = ["ball.q*", "bal.*", "r1.x_in"]\n')
    assert got == [(12, 14, "no output or input clock matches 'ball.q*'"),
                   (12, 25, "unknown instance 'bal' (did you mean 'ball'?)")]


# ----------------------------------------------------------------------------------------
# What the master refuses before it runs


def test_duplicate_value_references_are_refused_at_the_second_variable(fmu_builder, tmp_path):
    spec = {"vars": [fmu_builder.var("y", 1, "Float64", "output", "continuous"),
                     fmu_builder.var("u", 1, "Float64", "input", "continuous", start="0"),
                     fmu_builder.var("stop_at", 3, "Float64", "parameter", "fixed", start="0")]}
    fmu = fmu_builder.build("trivial", tmp_path, spec=spec)
    path = tmp_path / "dup.toml"
    path.write_text(f'[experiment]\nstop = 1.0\nstep = 0.1\n[instances.t]\nfmu = "{fmu}"\n')
    with pytest.raises(RobogenError) as exc:
        simulate_system(path)
    d = exc.value.diagnostics[0]
    assert d.message == ("the FMU of instance 't' gives value reference 1 to both 'y' and 'u' "
                         "(value references must be unique)")
    assert d.span.path == f"{fmu}/modelDescription.xml" and d.span.line > 1
    assert d.notes[0].span.line == 5  # fmu = ...


@pytest.mark.parametrize("output, events, message", [
    ("{system}", None, "-o {system} is also an input of this command; refusing to overwrite it"),
    ("{trivial}", None, "-o {trivial} is also an input of this command; refusing to overwrite it"),
    ("r.csv", "{system}", "--events {system} is also an input of this command; refusing to overwrite it"),
    ("r.csv", "r.csv", "--events r.csv is also an input of this command; refusing to overwrite it"),
    ("{folder}", None, "-o {folder} is a folder; name a file"),
])
def test_results_files_never_overwrite_an_input_or_each_other(write_system, fmus, tmp_path, monkeypatch, output, events, message):
    path = write_system('[experiment]\nstop = 1.0\nstep = 0.1\n[instances.t]\nfmu = "{trivial}"\n')
    before = path.read_bytes(), fmus["trivial"].read_bytes()
    names = {"system": path, "trivial": fmus["trivial"], "folder": tmp_path}
    monkeypatch.chdir(tmp_path)
    with pytest.raises(RobogenError) as exc:
        simulate_system(path, output=output.format(**names), events=events and events.format(**names))
    assert exc.value.diagnostics[0].message == message.format(**names)
    assert (path.read_bytes(), fmus["trivial"].read_bytes()) == before


def test_isolate_must_be_a_boolean(write_system):
    got = errors(write_system, '[experiment]\nstop = 1.0\nstep = 0.1\n[instances.t]\nfmu = "{trivial}"\nisolate = "yes"\n')
    assert got == [(6, 1, "'isolate' must be true or false")]
