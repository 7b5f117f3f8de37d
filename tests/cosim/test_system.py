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
        (6, 3, "a connection must join two different instances"),
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
    assert (2, 3, "'ball.h' is not clocked but 'r1.x_in' is clocked") in got
    assert (3, 3, "'r1.x_in' is connected twice") in got
    got = errors(write_system, 'connections = ["ticker.count -> r1.x_in"]' + HEAD)
    assert got == [(1, 16, "clocked connection 'ticker.count -> r1.x_in' needs its clocks connected: add \"ticker.out -> r1.u\"")]


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
