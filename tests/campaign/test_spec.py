"""The campaign file: schema, located errors before anything runs, expansion of the space."""

from __future__ import annotations

import pytest

from robogen.campaign.plan import make_plan
from robogen.campaign.space import expand
from robogen.campaign.spec import load_campaign
from robogen.cli import main
from robogen.diagnostics import RobogenError


def problems(path) -> list[tuple[str, int, int]]:
    """(message, line, column) of every error the campaign file gets, loading and planning."""
    with pytest.raises(RobogenError) as info:
        make_plan(load_campaign(path))
    return [(d.message, d.span.line, d.span.column) for d in info.value.diagnostics]


def test_unknown_parameter_is_located_at_its_key(campaign_dir):
    path = campaign_dir('system = "system.toml"\n[grid]\n"crasher.gian" = [1.0, 2.0]\n')
    [(message, line, column)] = problems(path)
    assert message == "unknown parameter: the FMU has no variable 'gian' (did you mean 'gain'?)"
    assert (line, column) == (3, 1)


def test_unknown_instance_and_unused_bare_name(campaign_dir):
    path = campaign_dir('system = "system.toml"\n[grid]\n"crash.gain" = [1.0]\nspeed = [1, 2]\n')
    assert problems(path) == [
        ("unknown parameter: unknown instance 'crash' (did you mean 'crasher'?) in 'crash.gain'", 3, 1),
        ("unknown parameter 'speed': not instance.variable, instance.fmu or instance.resources/PATH, "
         "and no [files] entry uses ${speed}", 4, 1),
    ]


def test_an_empty_space_is_refused(campaign_dir):
    assert problems(campaign_dir('system = "system.toml"\n')) == [
        ("the parameter space is empty: give [grid], [[case]] or [random] (docs/campaign-toml.md)", 1, 1)]
    path = campaign_dir('system = "system.toml"\n[grid]\n"crasher.gain" = []\n"crasher.delay" = { range = [3, 1] }\n')
    assert problems(path) == [
        ("'crasher.gain' has no values: the campaign would have no runs", 3, 1),
        ("range [3, 1] has no values: the campaign would have no runs", 4, 1),
    ]
    path = campaign_dir('system = "system.toml"\n[random]\nsamples = 0\n"crasher.gain" = { uniform = [0, 1] }\n')
    assert problems(path) == [("[random] needs samples = N, a positive integer (the number of draws)", 3, 1)]


def test_bad_distributions_are_located(campaign_dir):
    path = campaign_dir('system = "system.toml"\n[random]\nsamples = 4\n'
                        '"crasher.gain" = { uniforn = [0, 1] }\n'
                        '"crasher.delay" = { normal = [0.0, -1.0] }\n'
                        '"crasher.crash_time" = { uniform = [2, 1] }\n'
                        '"crasher.hang_time" = { choice = [] }\n')
    assert problems(path) == [
        ("unknown distribution 'uniforn' (did you mean 'uniform'?); one of uniform, normal, choice", 4, 20),
        ("normal = [mean, sd] needs a positive standard deviation, not -1", 5, 21),
        ("uniform = [low, high] needs low < high, not [2, 1]", 6, 26),
        ("choice = [value, ...] needs at least one value", 7, 25),
    ]
    path = campaign_dir('system = "system.toml"\n[random]\nsamples = 4\n')
    assert problems(path) == [("[random] draws nothing: add NAME = { uniform = [low, high] } (or normal, choice)", 2, 1)]


def test_a_missing_system_is_located_at_the_system_key(campaign_dir, tmp_path):
    path = campaign_dir('title = "t"\nsystem = "nowhere.toml"\n[grid]\n"crasher.gain" = [1.0]\n')
    assert problems(path) == [(f"system file not found: {tmp_path / 'nowhere.toml'}", 2, 1)]


def test_system_file_errors_are_reported_in_the_system_file(campaign_dir, tmp_path):
    path = campaign_dir('system = "system.toml"\n[grid]\n"crasher.gain" = [1.0]\n',
                        system='[experiment]\nstop = 1.0\nstep = 0.1\nsolver = "rk4"\n[instances.crasher]\nfmu = "crasher.fmu"\n')
    with pytest.raises(RobogenError) as info:
        load_campaign(path)
    [d] = info.value.diagnostics
    assert (d.message, d.span.path, d.span.line) == (
        "unknown key 'solver'", str(tmp_path / "system.toml"), 4)


def test_values_of_the_wrong_type_and_unsettable_variables(campaign_dir):
    path = campaign_dir('system = "system.toml"\n[grid]\n"crasher.gain" = ["fast"]\n"crasher.y" = [1.0]\n')
    assert problems(path) == [
        ("'gain' is a Float64: give a number, not 'fast'", 3, 1),
        ("'y' cannot be given a value (causality output, initial calculated)", 4, 1),
    ]


def test_metrics_are_checked_against_the_schema_and_the_fmus(campaign_dir):
    path = campaign_dir('system = "system.toml"\n[grid]\n"crasher.gain" = [1.0]\n[metrics]\n'
                        'a = { final = "crasher.gian" }\nb = { ticks = "crasher.y" }\nc = { mean = "crasher.y" }\n'
                        'd = { at = "crasher.y" }\ne = "metrics_module"\n')
    assert problems(path) == [
        ('a metric is { KIND = "instance.variable" } with KIND one of final, min, max, at, first_tick, ticks, '
         'or "module:function"', 7, 1),
        ("'at' needs time = SECONDS", 8, 1),
        ("a user metric is \"module:function\", not 'metrics_module'", 9, 1),
    ]
    path = campaign_dir('system = "system.toml"\n[grid]\n"crasher.gain" = [1.0]\n[metrics]\n'
                        'a = { final = "crasher.gian" }\nb = { ticks = "crasher.y" }\n')
    assert problems(path) == [
        ("FMU instance 'crasher' has no variable 'gian' (did you mean 'gain'?)", 5, 7),
        ("'ticks' counts ticks of a clock; 'crasher.y' is a Float64", 6, 7),
    ]


def test_user_metric_modules_are_checked_before_running(campaign_dir):
    path = campaign_dir('system = "system.toml"\n[grid]\n"crasher.gain" = [1.0]\n[metrics]\n'
                        'a = "mine:fiunction"\nb = "no_such_module_here:f"\n', **{"mine.py": "def function(results):\n    return {}\n"})
    assert problems(path) == [
        (f"{path.parent / 'mine.py'} defines no function 'fiunction' (did you mean 'function'?)", 5, 1),
        ("metric module 'no_such_module_here' is neither a file beside the campaign nor an installed module", 6, 1),
    ]


def test_a_placeholder_without_a_value(campaign_dir):
    path = campaign_dir('system = "system.toml"\n[grid]\nT = [1, 2]\n[files]\n'
                        '"crasher.resources/plan.txt" = { template = "plan.txt" }\n', **{"plan.txt": "at $T to $U\n"})
    assert problems(path) == [
        ("${U} has no value in this run: it is not a parameter of the campaign, or a [[case]] leaves it out", 5, 1)]


def test_the_space_is_cases_times_grid_times_samples_in_order(campaign_dir):
    path = campaign_dir('system = "system.toml"\n'
                        '[grid]\n"crasher.gain" = [1.0, 2.0]\n"crasher.delay" = { linspace = [0.0, 0.5, 3] }\n'
                        '[[case]]\n"crasher.crash_time" = -1.0\n[[case]]\n"crasher.crash_time" = 5.0\n'
                        '[random]\nsamples = 2\nseed = 7\n"crasher.hang_time" = { uniform = [10.0, 20.0] }\n')
    runs = expand(load_campaign(path))
    assert len(runs) == 2 * 2 * 3 * 2
    assert [(r["crasher.crash_time"], r["crasher.gain"], r["crasher.delay"]) for r in runs[:6]] == [
        (-1.0, 1.0, 0.0), (-1.0, 1.0, 0.0), (-1.0, 1.0, 0.25), (-1.0, 1.0, 0.25), (-1.0, 1.0, 0.5), (-1.0, 1.0, 0.5)]
    draws = [r["crasher.hang_time"] for r in runs[:2]]
    assert all(10.0 <= d < 20.0 for d in draws) and draws[0] != draws[1]
    assert [r["crasher.hang_time"] for r in runs[2:4]] == draws  # the same samples at every grid point
    assert expand(load_campaign(path)) == runs  # the seed makes it reproducible


def test_keys_hash_the_full_specification(campaign_dir, tmp_path):
    path = campaign_dir('system = "system.toml"\n[grid]\n"crasher.gain" = [1.0, 2.0, 1.0]\n')
    runs = make_plan(load_campaign(path)).runs
    assert runs[0].spec.key == runs[2].spec.key != runs[1].spec.key
    before = runs[0].spec.key
    (tmp_path / "campaign.toml").write_text('system = "system.toml"\nstop = 1.5\n[grid]\n"crasher.gain" = [1.0]\n')
    assert make_plan(load_campaign(path)).runs[0].spec.key != before  # a setting changed
    fmu = tmp_path / "ticker.fmu"
    (tmp_path / "campaign.toml").write_text('system = "system.toml"\n[grid]\n"crasher.gain" = [1.0]\n')
    assert make_plan(load_campaign(path)).runs[0].spec.key == before
    fmu.write_bytes(fmu.read_bytes() + b"\0")  # another FMU content (the archive still reads)
    assert make_plan(load_campaign(path)).runs[0].spec.key != before


def test_dry_run_lists_the_runs_and_runs_nothing(campaign_dir, tmp_path, capsys):
    path = campaign_dir('system = "system.toml"\n[grid]\n"crasher.gain" = [1.0, 2.5]\n')
    assert main(["campaign", str(path), "--dry-run"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith(f"{path}: 2 runs (2 distinct) of {tmp_path / 'system.toml'}, 2 FMU file(s)")
    assert out[1].split() == ["run", "id", "crasher.gain"]
    assert [line.split()[::2] for line in out[2:]] == [["0", "1"], ["1", "2.5"]]
    assert not (tmp_path.parent / "campaign-results").exists() and not any(tmp_path.glob("*results*"))


def test_dry_run_reports_what_simulate_would_say_about_the_base_system(campaign_dir, capsys):
    path = campaign_dir('system = "system.toml"\n[grid]\n"crasher.gain" = [1.0]\n',
                        system='connections = ["crasher.y -> ticker.tick"]\n[experiment]\nstop = 1.0\nstep = 0.1\n'
                               '[instances.crasher]\nfmu = "crasher.fmu"\n[instances.ticker]\nfmu = "ticker.fmu"\n')
    assert main(["campaign", str(path), "--dry-run"]) == 1
    err = capsys.readouterr().err
    assert "system.toml:1:" in err and "crasher.y" in err
