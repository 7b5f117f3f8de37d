"""FMUs of other interfaces behind the adapters (robogen.cosim.interfaces): FMI 2.0 Co-Simulation,
Model Exchange (FMI 2.0 and 3.0, CVode and explicit Euler) and FMI 3.0 Scheduled Execution.

Each single-FMU run is compared with ``fmpy.simulate_fmu`` under the same settings (the tolerance
of each comparison is stated where it is made: CVode's global error is not bounded by its local
tolerance; at the same rtol, robogen's CVode takes the steps fmpy's takes (CVode's own step sizes,
the results interpolated at the communication points) as long as fmpy's cap on the step size
((stop - start) / 50) does not bind, so the Van der Pol runs agree within 1e-9, and both stay within
1e-3 of a run at rtol = 1e-10; a fixed-step method or an FMU's own
fmi2DoStep computes the same numbers, compared within 1e-12). Events, terminate requests and the
Scheduled Execution activation trace are checked against hand calculations."""

from __future__ import annotations

import math

import fmpy
import pytest

from robogen.cosim import simulate_system
from robogen.diagnostics import RobogenError


def system(fmu: str, stop: float, step: float, *, tolerance: float | None = 1e-6, extra: str = "", record: str = "") -> str:
    tol = f"tolerance = {tolerance}\n" if tolerance is not None else ""
    return (f'[experiment]\nstop = {stop}\nstep = {step}\n{tol}[instances.p]\nfmu = "{{{fmu}}}"\n{extra}'
            + (f"[record]\nvariables = {record}\n" if record else ""))


def by_time(result) -> dict[float, dict]:
    """The last row at each time (after its event iteration), by time rounded to 1e-9."""
    rows = {}
    for row in result.rows:
        rows[round(row[0], 9)] = dict(zip(result.columns, row))
    return rows


def peer(fmus, name: str, **settings):
    """fmpy.simulate_fmu of the FMU, its rows by time rounded to 1e-9."""
    out = fmpy.simulate_fmu(str(fmus[name]), validate=False, **settings)
    return {round(float(r["time"]), 9): r for r in out}


def compare(ours: dict, theirs: dict, names: list[str], tolerance: float) -> int:
    """The largest difference over the common times must stay within ``tolerance``; the count of
    times compared."""
    common = sorted(set(ours) & set(theirs))
    worst = max(abs(ours[t][f"p.{n}"] - float(theirs[t][n])) for t in common for n in names)
    assert worst <= tolerance, f"differs by {worst} (> {tolerance})"
    return len(common)


@pytest.mark.parametrize("name", ["vdp2", "vdp3"])
def test_model_exchange_with_cvode_agrees_with_fmpy(write_system, fmus, name):
    result = simulate_system(write_system(system(name, 10.0, 0.1)))
    assert result.stats.loop == "C"
    theirs = peer(fmus, name, stop_time=10.0, output_interval=0.1, relative_tolerance=1e-6, solver="CVode")
    ours = by_time(result)
    assert compare(ours, theirs, ["x0", "x1"], 1e-9) == 101  # the same CVode steps as fmpy's: within 1e-9
    exact = by_time(simulate_system(write_system(system(name, 10.0, 0.1, tolerance=1e-10), name="tight.toml")))
    error = lambda rows: max(abs(rows[t][f"p.{n}"] - exact[t][f"p.{n}"]) for t in exact for n in ("x0", "x1"))  # noqa: E731
    fmpy_error = max(abs(float(theirs[t][n]) - exact[t][f"p.{n}"]) for t in exact for n in ("x0", "x1"))
    assert error(ours) <= 1e-3 and fmpy_error <= 1e-3  # both near the solution at rtol 1e-10


def test_model_exchange_with_euler_computes_what_fmpys_euler_computes(write_system, fmus):
    text = system("vdp3", 2.0, 0.01, extra='solver = "euler"\nsolver_step = 0.001\n')
    ours = by_time(simulate_system(write_system(text)))
    theirs = peer(fmus, "vdp3", stop_time=2.0, output_interval=0.001, step_size=0.001, solver="Euler")
    assert compare(ours, theirs, ["x0", "x1"], 1e-12) == 201  # the same Euler steps: within 1e-12


def test_a_stiff_system_integrates_as_fmpys_cvode(write_system, fmus):
    result = simulate_system(write_system(system("stiff3", 40.0, 0.4)))
    ours = by_time(result)
    theirs = peer(fmus, "stiff3", stop_time=40.0, output_interval=0.4, relative_tolerance=1e-6)
    # fmpy caps CVode's step at (stop - start) / 50, robogen does not: y0, y2 ~ 1 within 1e-4, y1 ~ 1e-5 within 1e-8
    assert compare(ours, theirs, ["y0", "y2"], 1e-4) == 101
    assert compare(ours, theirs, ["y1"], 1e-8) == 101
    assert ours[40.0]["p.y0"] + ours[40.0]["p.y1"] + ours[40.0]["p.y2"] == pytest.approx(1.0, abs=1e-6)  # mass is kept


@pytest.mark.parametrize("name", ["bounce3", "bounce2"])
def test_a_bouncing_ball_in_model_exchange_locates_its_bounces_as_fmpy(write_system, fmus, name):
    extra = 'interface = "model-exchange"\n' if name == "bounce3" else ""
    result = simulate_system(write_system(system(name, 3.0, 0.1, extra=extra)))
    ours = by_time(result)
    theirs = peer(fmus, name, stop_time=3.0, output_interval=0.1, relative_tolerance=1e-6, fmi_type="ModelExchange")
    # fmpy caps CVode's step at (stop - start) / 50 and restarts it at each bounce as robogen does: within 1e-4
    assert compare(ours, theirs, ["h", "v"], 1e-4) > 30
    assert ours[3.0]["p.bounces"] == int(theirs[3.0]["bounces"]) == 17
    # the first bounce by hand: h = 1 - g t^2 / 2 reaches 0 at t = sqrt(2 / g); the ball returns early there
    events = sorted({r[0] for r in result.rows if r[1] == 1 and r[0] > 0})
    assert events[0] == pytest.approx(math.sqrt(2 / 9.81), abs=1e-6)
    assert result.stats.early_returns == 17


def test_time_events_step_events_and_a_terminate_request_of_a_model_exchange_fmu(write_system):
    # Euler at 0.01: the step event asked for by the first completed step at or after t = 0.5 is at
    # t = 0.5 (a step of the Euler grid, within the communication step (0.4, 0.5]); the kick at
    # t = 0.25 (a time event between communication points) adds 1 m/s to v.
    text = system("bounce3", 0.5, 0.1, extra='interface = "model-exchange"\nsolver = "euler"\nsolver_step = 0.01\n'
                  'start = { kick_time = 0.25, kick = 1.0, step_event_at = 0.5 }\n', tolerance=None)
    result = simulate_system(write_system(text))
    events = [r for r in result.rows if r[1] == 1]
    assert [round(r[0], 9) for r in events] == [0.0, 0.25, 0.5]
    kick = by_time(result)[0.25]
    assert kick["p.v"] == pytest.approx(-9.81 * 0.25 + 1.0, abs=1e-12)  # Euler is exact for v' = -g
    assert by_time(result)[0.5]["p.step_events"] == 1
    # terminate after the second bounce: at sqrt(2/g) + 2 (0.7 sqrt(2 g)) / g, by hand
    second = math.sqrt(2 / 9.81) + 2 * 0.7 * math.sqrt(2 * 9.81) / 9.81
    stopped = simulate_system(write_system(system("bounce3", 3.0, 0.1, extra='interface = "model-exchange"\n'
                                                  "start = { max_bounces = 2 }\n")))
    assert stopped.stats.terminated_by.startswith("instance 'p' asked to terminate in fmi3UpdateDiscreteStates at t=1.08")
    assert stopped.rows[-1][0] == pytest.approx(second, abs=1e-6)


def test_fmi2_co_simulation_is_the_fmus_own_steps(write_system, fmus):
    result = simulate_system(write_system(system("lag2", 3.0, 0.1)))
    ours = by_time(result)
    theirs = peer(fmus, "lag2", stop_time=3.0, output_interval=0.1, relative_tolerance=1e-6)
    assert compare(ours, theirs, ["x", "crossings", "level"], 1e-12) == 31  # the same fmi2DoStep calls
    # FMI 2.0's types as FMI 3.0's: Integer as Int32, Boolean as bool, Enumeration as Int64
    assert ours[3.0]["p.crossings"] == 1 and ours[3.0]["p.above"] is True and ours[3.0]["p.level"] == 2
    # x = 1 - exp(-t / 0.5) crosses 0.5 at t = 0.5 ln 2 = 0.347 (in the step (0.3, 0.4]): a request to
    # terminate (fmi2Discard, fmi2Terminated) ends the run at that step
    stopped = simulate_system(write_system(system("lag2", 3.0, 0.1, extra="start = { stop_after = 1 }\n")))
    assert stopped.stats.terminated_by == "instance 'p' asked to terminate in fmi3DoStep at t=0.4"
    # asynchronous steps (fmi2DoStep returns fmi2Pending; fmi2GetStatus says pending three times
    # more, then the step's status): waited for, the same results
    pending = simulate_system(write_system(system("lag2", 3.0, 0.1, extra="start = { async_polls = 3 }\n"), name="a.toml"))
    assert pending.rows == result.rows


def test_scheduled_execution_activates_partitions_at_their_ticks_in_priority_order(write_system):
    result = simulate_system(write_system(system("sched3", 0.9, 0.1, tolerance=None)))
    rows = by_time(result)
    # by hand: fast ticks every 0.1 s, slow every 0.3 s; where both tick, slow (priority 1) runs
    # before fast (priority 2): at t = 0 slow is activation 1 and fast 2; then fast alone 3, 4; at
    # 0.3 slow 5, fast 6; ... slow sees the fast count before fast's activation of the same instant
    expected = {0.0: (2, 1), 0.1: (3, 1), 0.2: (4, 1), 0.3: (6, 5), 0.4: (7, 5), 0.5: (8, 5), 0.6: (10, 9), 0.7: (11, 9),
                0.8: (12, 9), 0.9: (14, 13)}
    assert {t: (r["p.fast_seq"], r["p.slow_seq"]) for t, r in rows.items()} == expected
    y_slow = [r[result.columns.index("p.y_slow")] for r in result.rows if r[result.columns.index("p.slow")] == 1]
    assert y_slow == [0, 3, 6, 9]
    y_fast = [r[result.columns.index("p.y_fast")] for r in result.rows if r[result.columns.index("p.fast")] == 1]
    assert y_fast == pytest.approx([10 * 0.1 * k for k in range(10)])


def test_both_interfaces_in_one_fmu_the_system_file_chooses(write_system):
    cs = simulate_system(write_system(system("bounce3", 1.0, 0.1), name="cs.toml"))
    me = simulate_system(write_system(system("bounce3", 1.0, 0.1, extra='interface = "model-exchange"\n'), name="me.toml"))
    # co-simulation by default (the FMU's own RK4 at 1e-3, early return at the internal step past
    # the bounce); model exchange when chosen (CVode, the bounce located): the same bounce
    first_cs = min(r[0] for r in cs.rows if r[1] == 1 and r[0] > 0)
    first_me = min(r[0] for r in me.rows if r[1] == 1 and r[0] > 0)
    assert first_me == pytest.approx(math.sqrt(2 / 9.81), abs=1e-6)
    assert first_cs == pytest.approx(math.sqrt(2 / 9.81), abs=1e-3) and first_cs != first_me


def test_an_interface_the_fmu_lacks_is_a_located_error(write_system):
    path = write_system(system("vdp2", 1.0, 0.1, extra='interface = "scheduled-execution"\n'))
    with pytest.raises(RobogenError) as exc:
        simulate_system(path)
    d = exc.value.diagnostics[0]
    assert d.message == "the FMU does not offer FMI 2.0 scheduled execution"
    assert d.span.line == 7 and [n.message for n in d.notes] == ["it offers: model-exchange"]
    path = write_system(system("vdp2", 1.0, 0.1, extra='interface = "model exchange"\n'))
    with pytest.raises(RobogenError) as exc:
        simulate_system(path)
    assert exc.value.diagnostics[0].message.startswith("'interface' must be one of 'co-simulation', 'model-exchange'")


def test_a_pre_release_fmi_version_is_imported_with_a_warning(write_system, other_builder, tmp_path):
    md = other_builder.description3("vdp3")
    from robogen.fmu.modeldesc_writer import write_model_description

    xml = write_model_description(md).replace('fmiVersion="3.0"', 'fmiVersion="3.0-rc.1"')
    fmu = other_builder.build("vdp3", tmp_path / "rc", xml=xml)
    path = tmp_path / "rc.toml"
    path.write_text(f'[experiment]\nstop = 1.0\nstep = 0.1\n[instances.p]\nfmu = "{fmu}"\n')
    warnings = []
    result = simulate_system(path, warn=warnings.append)
    assert [w.message for w in warnings] == ["the FMU of instance 'p' declares fmiVersion=\"3.0-rc.1\", a pre-release "
                                             "of FMI 3.0: it is imported as FMI 3.0"]
    assert result.rows[-1][0] == 1.0


@pytest.mark.parametrize("loop", ["Python", "C"])
def test_values_are_converted_between_fmi_2_and_3_and_narrowing_overflow_names_the_connection(write_system, monkeypatch,
                                                                                           loop):
    if loop == "Python":
        monkeypatch.setenv("ROBOGEN_REFERENCE_LOOP", "1")
    # an FMI 2.0 Integer (Int32) into an FMI 3.0 Int64 input: widened
    widened = simulate_system(write_system('connections = ["l.crossings -> s.u"]\n[experiment]\nstop = 1.0\nstep = 0.1\n'
                                           '[instances.l]\nfmu = "{lag2}"\n[instances.s]\nfmu = "{setcount}"\n', name="w.toml"))
    assert widened.stats.loop == loop and widened.rows[-1][widened.columns.index("s.y")] == 1  # one crossing, at 0.35
    # an Int64 into an Int32 input: the all-types FMU's y_i64 is -n 1000000007 after n steps, which
    # fits an Int32 at n = 1, 2 and not at n = 3 (t = 0.3)
    path = write_system('connections = ["a.y_i64 -> b.u_i32"]\n[experiment]\nstop = 1.0\nstep = 0.1\n'
                        '[instances.a]\nfmu = "{alltypes}"\n[instances.b]\nfmu = "{alltypes}"\n', name="n.toml")
    with pytest.raises(RobogenError) as exc:
        simulate_system(path)
    d = exc.value.diagnostics[0]
    assert d.message == ("connection 'a.y_i64 -> b.u_i32': the value -3000000021 of Int64 'a.y_i64' does not fit the "
                         "input's type Int32 at t=0.3; the results recorded so far are kept")
    assert d.span.line == 1


@pytest.mark.parametrize("loop", ["Python", "C"])
def test_an_array_whose_dimension_is_a_structural_parameter_is_read_whole(write_system, monkeypatch, loop):
    # y has n = 3 elements (n: a structural parameter, start 3); y[i] = i x, x = t. Read as a
    # scalar, the FMU refuses the call ("Expected nValues >= 3 but was 1", as the Reference FMUs do).
    if loop == "Python":
        monkeypatch.setenv("ROBOGEN_REFERENCE_LOOP", "1")
    result = simulate_system(write_system(system("arrays3", 1.0, 0.25, tolerance=None)))
    assert result.columns == ["time", "superdense", "p.x", "p.y[1]", "p.y[2]", "p.y[3]"]
    assert [r[2:] for r in result.rows if r[1] == 0 and r[0] > 0] == [[t, t, 2 * t, 3 * t] for t in (0.25, 0.5, 0.75, 1.0)]
    path = write_system('connections = ["p.y -> q.u"]\n' + system("arrays3", 1.0, 0.25, tolerance=None)
                        + '[instances.q]\nfmu = "{trivial}"\n', name="connected.toml")
    with pytest.raises(RobogenError) as exc:
        simulate_system(path)
    assert exc.value.diagnostics[0].message == ("'p.y' is an array: the master records arrays, element by element, but "
                                                "does not connect them")


def test_an_fmu_whose_archive_lists_a_member_twice_runs_when_both_copies_agree(write_system, fmus, tmp_path):
    import shutil
    import warnings
    import zipfile

    for name, second in (("same", None), ("different", b"<changed/>")):
        copy = tmp_path / f"{name}.fmu"
        shutil.copy(fmus["vdp3"], copy)
        with zipfile.ZipFile(copy) as z:
            text = z.read("modelDescription.xml")
        with warnings.catch_warnings(), zipfile.ZipFile(copy, "a") as z:  # as CMake's zip writes it
            warnings.simplefilter("ignore")
            z.writestr("modelDescription.xml", second or text)
        path = tmp_path / f"{name}.toml"
        path.write_text(f'[experiment]\nstop = 1.0\nstep = 0.1\n[instances.p]\nfmu = "{copy}"\n')
        if second is None:
            assert simulate_system(path).rows[-1][0] == 1.0
            continue
        with pytest.raises(RobogenError) as exc:
            simulate_system(path)
        assert exc.value.diagnostics[0].message == "archive member 'modelDescription.xml' appears twice with different contents"


@pytest.mark.parametrize("loop", ["Python", "C"])
def test_a_triggered_partition_runs_at_its_clocks_tick_first_by_priority(write_system, monkeypatch, loop):
    # the ticker's output clock out ticks with its periodic input clock (every 0.25 s) and drives
    # the SE FMU's triggered clock kick (priority 0). By hand: at t = 0 kick, slow and fast tick
    # together: kick 1, slow 2, fast 3; at 0.1, 0.2 fast alone (4, 5); at 0.25 kick alone (6); at 0.3
    # slow 7, fast 8; at 0.4 fast 9; at 0.5 kick 10, fast 11.
    if loop == "Python":
        monkeypatch.setenv("ROBOGEN_REFERENCE_LOOP", "1")
    result = simulate_system(write_system('connections = ["k.out -> s.kick"]\n[experiment]\nstop = 0.5\nstep = 0.1\n'
                                          '[instances.k]\nfmu = "{ticker}"\n[instances.s]\nfmu = "{sched3}"\n'
                                          '[record]\nvariables = ["s.kick_seq", "s.slow_seq", "s.fast_seq"]\n'))
    rows = by_time(result)
    seqs = {t: (r["s.kick_seq"], r["s.slow_seq"], r["s.fast_seq"]) for t, r in rows.items()}
    assert seqs == {0.0: (1, 2, 3), 0.1: (1, 2, 4), 0.2: (1, 2, 5), 0.25: (6, 2, 5), 0.3: (6, 7, 8), 0.4: (6, 7, 9),
                    0.5: (10, 7, 11)}


@pytest.mark.parametrize("loop", ["Python", "C"])
def test_a_countdown_partition_runs_when_its_interval_runs_out(write_system, monkeypatch, loop):
    # delay = 0.05: each activation of slow (t = 0, 0.3, 0.6) announces later's interval (clockUpdate,
    # then fmi3GetIntervalDecimal: 0.05), so later ticks at 0.05 and 0.35 (0.65 is past the stop),
    # between the communication points. By hand: at 0 slow 1, fast 2; at 0.05 later 3; at 0.1, 0.2
    # fast 4, 5; at 0.3 slow 6, fast 7; at 0.35 later 8; at 0.4, 0.5 fast 9, 10; at 0.6 slow 11, fast 12.
    if loop == "Python":
        monkeypatch.setenv("ROBOGEN_REFERENCE_LOOP", "1")
    result = simulate_system(write_system(system("sched3", 0.6, 0.1, tolerance=None, extra="start = { delay = 0.05 }\n",
                                                 record='["p.slow_seq", "p.fast_seq", "p.later_seq", "p.later_at"]')))
    assert result.stats.loop == loop
    rows = by_time(result)
    seqs = {t: (r["p.slow_seq"], r["p.fast_seq"], r["p.later_seq"]) for t, r in rows.items()}
    assert seqs == {0.0: (1, 2, 0), 0.05: (1, 2, 3), 0.1: (1, 4, 3), 0.2: (1, 5, 3), 0.3: (6, 7, 3), 0.35: (6, 7, 8),
                    0.4: (6, 9, 8), 0.5: (6, 10, 8), 0.6: (11, 12, 8)}
    later = sorted({r["p.later_at"] for r in rows.values() if r["p.later_at"] > 0})
    assert later == pytest.approx([0.05, 0.35], abs=1e-12)
