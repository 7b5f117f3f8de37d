"""robogen export-ssp: every system file of the master's tests (tests/cosim: test_cosim_engine.py's
scenarios: clocks, clocked values, every FMI type, early return, roll-back, termination,
isolation, decimation; test_proxy.py's, test_master.py's relay chain, test_system.py's recording
patterns, test_large_results.py's, test_crash.py's C and Python FMU systems without their crash,
test_recorder.py's two failing runs), and a few more here (converting connections, robogen's
settings, start values of every type), written as SSP 2.0, valid against the SSP 2.0 schemas
(../shared), read back as the same system, and simulated from the archive with byte-identical
results (a failing run: the same error); the archive is the same bytes each time. SSP 1.0
archives re-exported as SSP 2.0 run alike too. (test_signals.py's system is test_crash.py's
Python one with a sleeping step; the campaign tests' base system is exported by
tests/campaign/test_campaign_ssp.py's archive the other way round.)"""

from __future__ import annotations

import importlib.util
import sys
import zipfile
from pathlib import Path

import pytest
import ssp_samples

from robogen.cosim import simulate_system
from robogen.cosim.assemble import FmuCache, read_system
from robogen.cosim.ssp_write import export_ssp
from robogen.diagnostics import RobogenError
from support import ROOT
from support.ssp import SCHEMAS, validate

HERE = Path(__file__).resolve().parent


def _module(name: str, path: Path):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


ENGINE = _module("ssp_export_engine_scenarios", HERE / "test_cosim_engine.py")
SCALE = _module("ssp_export_scale_scenarios", HERE / "test_connection_scale.py")
PROXY = _module("ssp_export_proxy_scenarios", HERE / "test_proxy.py")
MASTER = _module("ssp_export_master_scenarios", HERE / "test_master.py")
CHECKS = _module("ssp_export_system_scenarios", HERE / "test_system.py")
LARGE = _module("ssp_export_large_scenarios", HERE / "test_large_results.py")
CRASH = _module("ssp_export_crash_scenarios", HERE / "test_crash.py")

#: every value type as a start value; robogen's settings
SETTINGS = """connections = ["k.out -> r.u", "k.count -> r.x_in", "a.y_f64 -> t.u"]
[experiment]
start = 0.0
stop = 2.0
step = 0.1
tolerance = 1e-6
max_event_iterations = 50
order = ["t", "r", "k", "a"]
[instances.k]
fmu = "{ticker}"
[instances.r]
fmu = "{relay}"
start = { stepwise = true }
[instances.t]
fmu = "{trivial}"
isolate = true
[instances.a]
fmu = "{alltypes}"
start = { u_f32 = 0.1, u_f64 = -1e-300, u_i8 = -128, u_u8 = 255, u_i16 = -32768, u_u16 = 65535, u_i32 = -2147483648, u_u32 = 4294967295, u_i64 = -9223372036854775808, u_u64 = 18446744073709551615, u_b = true, u_s = "quote \\" and <tag> & new\\nline", u_e = 3, echo = false }
[record]
variables = ["a.y_*", "r.*", "t.y", "k.count"]
every = 0.2
"""

SYSTEMS = {**{f"engine-{k}": v for k, v in ENGINE.SYSTEMS.items()},
           **{f"stretch-{k}": v for k, v in ENGINE.STRETCH_SYSTEMS.items()},
           "alltypes": ENGINE.alltypes(0.1, connected=False), "alltypes-connected": ENGINE.alltypes(0.7, connected=True),
           "scaled": SCALE.SCALED, "settings": SETTINGS,
           **{f"proxy-{k}": v for k, v in PROXY.SYSTEMS.items()},
           "master-relay-chain": MASTER._chain(3, stepwise=True),
           "system-record-patterns": CHECKS.HEAD + '[record]\nvariables = ["ball.h0", "*.?", "ticker.[ot]*", "r1.x_*"]\n',
           "large-alltypes": LARGE.ALLTYPES,
           "crash-c-none": CRASH.C_SYSTEM.replace("CRASH", "-1.0"),
           "crash-python-none": CRASH.PY_SYSTEM.replace("CRASH", "-1.0"),
           # test_recorder.py's: a start value NaN refused by the FMU, an FMU failing in its sixth step
           "fails-nan-start": '[experiment]\nstop = 1.0\nstep = 0.1\n[instances.a]\nfmu = "{alltypes}"\nstart = { u_f64 = nan }\n',
           "fails-mid-run": '[experiment]\nstop = 2.0\nstep = 0.1\n[instances.f]\nfmu = "{failer}"\n'}
#: the systems whose run fails: the SSP's must fail alike
FAILING = {"fails-nan-start", "fails-mid-run"}


def outcome(path: Path, folder: Path, tag: str):
    """(rows, CSV bytes, events bytes, statistics) of a run, or (the error's messages, the CSV
    bytes it left, if any)."""
    csv, events = folder / f"{tag}.csv", folder / f"{tag}.jsonl"
    try:
        result = simulate_system(path, output=csv, events=events)
    except RobogenError as exc:
        return [d.message for d in exc.diagnostics], csv.read_bytes() if csv.exists() else None
    stats = (result.stats.steps, result.stats.event_iterations, result.stats.instants, result.stats.terminated_by)
    return result.rows, csv.read_bytes(), events.read_bytes(), stats


def model(path: Path):
    """What a system says, whatever file it came from (paths to FMUs by file content)."""
    cache = FmuCache()
    try:
        s = read_system(path, cache, lambda d: None)
        instances = {n: (i.fmu.read_bytes(), {k: "NaN" if v != v else v for k, (v, _s) in i.start.items()},  # NaN != NaN
                         {k: t for k, (t, _s) in i.clocks.items()}, i.isolate, i.interface, i.solver, i.solver_step)
                     for n, i in s.instances.items()}
        connections = [(str(c.source), str(c.target), c.scale) for c in s.connections]
        record = [n for n, _s in s.record] if s.record is not None else None
        return (s.start, s.stop, s.step, s.tolerance, s.max_event_iterations, s.order, instances, connections, record, s.record_every)
    finally:
        cache.close()


@pytest.mark.parametrize("name", sorted(SYSTEMS))
def test_a_system_exported_to_ssp_2_runs_byte_for_byte_alike(name, write_system, tmp_path, request):
    text = SYSTEMS[name]
    if "MISBEHAVING" in text:  # test_crash.py's Python FMU (a session fixture, built only for it)
        text = text.replace("MISBEHAVING", str(request.getfixturevalue("misbehaving")))
    toml = write_system(text, name=f"{name}.toml")
    ssp = export_ssp(toml, tmp_path / f"{name}.ssp")
    again = export_ssp(toml, tmp_path / f"{name}-again.ssp")
    assert ssp.read_bytes() == again.read_bytes()  # deterministic
    if SCHEMAS.is_dir():
        validate(ssp)
    assert model(ssp) == model(toml)  # nothing lost
    expected = outcome(toml, tmp_path, "toml")
    assert (len(expected) == 2) == (name in FAILING), expected
    assert outcome(ssp, tmp_path, "ssp") == expected


def test_the_settings_system_carries_every_setting_into_the_archive(write_system, tmp_path):
    ssp = export_ssp(write_system(SETTINGS), tmp_path / "settings.ssp")
    text = zipfile.ZipFile(ssp).read("SystemStructure.ssd").decode()
    assert '<ssd:DefaultExperiment startTime="0.0" stopTime="2.0">' in text
    assert ('<rg:Experiment xmlns:rg="urn:robogen:ssp" step="0.1" tolerance="1e-06" maxEventIterations="50" '
            'order="t r k a">') in text
    assert '<rg:Instance xmlns:rg="urn:robogen:ssp" isolate="true"/>' in text
    assert '<ssv:Enumeration value="high" name="Level"/>' in text  # the start value 3 by its item's name
    assert '<ssv:String value="quote &quot; and &lt;tag&gt; &amp; new&#10;line"/>' in text
    assert '<ssv:UInt64 value="18446744073709551615"/>' in text
    assert '<ssd:Connector name="count" kind="output">\n            <ssc:Int64/>\n            <ssd:Clock name="out"/>' in text
    assert '<ssc:Clock intervalVariability="constant" intervalDecimal="0.25" shiftDecimal="0"/>' in text


def test_a_converting_connection_becomes_a_linear_transformation_without_unit_conversion(write_system, tmp_path):
    ssp = export_ssp(write_system(SCALE.SCALED), tmp_path / "scaled.ssp")
    text = zipfile.ZipFile(ssp).read("SystemStructure.ssd").decode()
    assert ('<ssd:Connection startElement="a" startConnector="y" endElement="b" endConnector="u" suppressUnitConversion="true">\n'
            '        <ssc:LinearTransformation factor="1000.0" offset="2.5"/>') in text


@pytest.mark.parametrize("style", ["ecos", "oms", "sample"])
def test_an_ssp_1_archive_exported_as_ssp_2_runs_alike(style, fmus, tmp_path):
    original = getattr(ssp_samples, style)(tmp_path / f"{style}.ssp", fmus)
    exported = export_ssp(original, tmp_path / f"{style}-2.ssp")
    if SCHEMAS.is_dir():
        validate(exported)
    assert model(exported) == model(original)
    first = simulate_system(original, step=0.05, output=tmp_path / "a.csv")
    second = simulate_system(exported, step=0.05, output=tmp_path / "b.csv")
    assert second.rows == first.rows
    assert (tmp_path / "a.csv").read_bytes() == (tmp_path / "b.csv").read_bytes()


def test_the_chain_benchmarks_ssp_file_runs_as_its_toml_twin(fmus, tmp_path):
    sys.path.insert(0, str(ROOT / "bench"))
    try:
        ecos_peer = _module("ssp_export_ecos_peer", ROOT / "bench" / "ecos_peer.py")
    finally:
        sys.path.remove(str(ROOT / "bench"))
    ssp = ecos_peer.chain_ssp(fmus["trivial"], 100, tmp_path / "chain.ssp")  # what ECOS runs in bench_master.py
    toml = tmp_path / "chain.toml"
    toml.write_text(ecos_peer.chain_system(fmus["trivial"], 100, 0.5, 0.01))
    from_ssp = simulate_system(ssp, stop=0.5, step=0.01, output=tmp_path / "ssp.csv")
    from_toml = simulate_system(toml, output=tmp_path / "toml.csv")
    assert from_ssp.columns == from_toml.columns == ["time", "superdense", *(f"t{i}.y" for i in range(100))]
    assert (tmp_path / "ssp.csv").read_bytes() == (tmp_path / "toml.csv").read_bytes()
    assert from_ssp.rows[-1][2:5] == pytest.approx([0.5, 0.99, 1.47])  # t_k.y = sum over the chain of delayed times


def test_export_refuses_to_overwrite_an_input(write_system, tmp_path):
    toml = write_system(ENGINE.SYSTEMS["ball"])
    with pytest.raises(RobogenError) as exc:
        export_ssp(toml, toml)
    assert "is also an input of this command" in exc.value.diagnostics[0].message


def test_robogen_export_ssp_writes_the_archive(write_system, tmp_path, robogen_process):
    toml = write_system(ENGINE.SYSTEMS["ticker"])
    done = robogen_process("export-ssp", toml, "-o", "out/ticker.ssp")
    assert done.returncode == 0, done.stderr
    assert done.stderr == "wrote out/ticker.ssp\n"
    assert sorted(zipfile.ZipFile(tmp_path / "out" / "ticker.ssp").namelist()) == [
        "SystemStructure.ssd", "resources/ticker.fmu", "resources/trivial.fmu"]


def test_a_tunable_clocks_timing_travels_both_ways(fmu_builder, tmp_path, write_system):
    """A fixed or tunable input clock's interval and shift ([instances.X] clocks) become the
    Clock connector's intervalDecimal and shiftDecimal, and come back (the system only: the test
    FMUs cannot be given an interval, fmi3SetIntervalDecimal)."""
    spec = dict(fmu_builder.MODELS["ticker"])
    spec["vars"] = [fmu_builder.clock("tick", 1, "input", "tunable", interval="0.25"), *spec["vars"][1:]]
    fmu = fmu_builder.build("ticker", tmp_path / "tunable", spec=spec)
    toml = tmp_path / "tunable.toml"
    toml.write_text(f'[experiment]\nstop = 1.0\nstep = 0.1\n[instances.k]\nfmu = "{fmu}"\n'
                    'clocks = { tick = { interval = 0.5, shift = 0.125 } }\n')
    ssp = export_ssp(toml, tmp_path / "tunable.ssp")
    text = zipfile.ZipFile(ssp).read("SystemStructure.ssd").decode()
    assert '<ssc:Clock intervalVariability="tunable" intervalDecimal="0.5" shiftDecimal="0.125"/>' in text
    assert model(ssp) == model(toml)
    assert model(ssp)[6]["k"][2] == {"tick": {"interval": 0.5, "shift": 0.125}}


def test_a_system_that_would_not_run_is_not_written(write_system, tmp_path):
    toml = write_system('connections = ["a.y -> b.v"]\n[experiment]\nstop = 1.0\nstep = 0.1\n'
                        '[instances.a]\nfmu = "{trivial}"\n[instances.b]\nfmu = "{trivial}"\nstart = { w = 1 }\n')
    with pytest.raises(RobogenError) as exc:
        export_ssp(toml, tmp_path / "bad.ssp")
    assert sorted((d.span.line, d.message.split(" (")[0]) for d in exc.value.diagnostics) == [
        (1, "FMU instance 'b' has no variable 'v'"), (9, "FMU instance 'b' has no variable 'w'")]
    assert not (tmp_path / "bad.ssp").exists()


def test_the_fmus_units_are_written_and_a_system_files_connections_stay_unconverted(unit_fmus, tmp_path):
    """An FMU's units (defined with a base unit) go into <ssd:Units> and onto its connectors; a
    system file converts only what it asks for, so its connections between different units say
    suppressUnitConversion, and the SSP runs as the file: b.u = a.y (m into mm, unconverted), c.u
    = 100 a.y (asked for), and c's unit 'cm', which its FMU does not define, is left off."""
    toml = tmp_path / "units.toml"
    toml.write_text('connections = ["a.y -> b.u", { from = "a.y", to = "c.u", factor = 100.0, offset = 0.0 }]\n'
                    '[experiment]\nstop = 0.5\nstep = 0.1\n' + "".join(
                        f'[instances.{i}]\nfmu = "{unit_fmus[u]}"\n' for i, u in (("a", "m"), ("b", "mm"), ("c", "cm"))))
    ssp = export_ssp(toml, tmp_path / "units.ssp")
    if SCHEMAS.is_dir():
        validate(ssp)
    text = zipfile.ZipFile(ssp).read("SystemStructure.ssd").decode()
    units = [line.strip() for line in text.splitlines() if "<ssc:Float64" in line]
    assert units == ['<ssc:Float64 unit="m"/>'] * 2 + ["<ssc:Float64/>"] + ['<ssc:Float64 unit="mm"/>'] * 2 + [
        "<ssc:Float64/>"] * 4  # a's u, y and stop_at; b's; c's ('cm' is not defined)
    assert '<ssc:Unit name="mm">\n      <ssc:BaseUnit m="1" factor="0.001"/>' in text
    assert text.count('suppressUnitConversion="true"') == 2
    assert model(ssp) == model(toml)
    expected = outcome(toml, tmp_path, "toml")
    assert outcome(ssp, tmp_path, "ssp") == expected
    last = dict(zip(["time", "superdense", "a.y", "b.y", "c.y"], expected[0][-1]))
    assert last == pytest.approx({"time": 0.5, "superdense": 0, "a.y": 0.5, "b.y": 0.4 + 0.5, "c.y": 40 + 0.5})


def test_an_instance_driven_by_a_scenario_is_not_exported(write_system, tmp_path):
    toml = write_system('[experiment]\nstop = 1.0\nstep = 0.1\n[instances.t]\nfmu = "{trivial}"\nscenario = "s.toml"\n')
    with pytest.raises(RobogenError) as exc:
        export_ssp(toml, tmp_path / "player.ssp")
    assert [(d.span.line, d.span.column, d.message) for d in exc.value.diagnostics] == [
        (6, 1, "instance 't' is driven by a scenario (docs/scenarios.md), which an SSP cannot hold: export the system "
                "without it")]
    assert not (tmp_path / "player.ssp").exists()
