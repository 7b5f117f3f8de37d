"""SSP archives (and unpacked .ssd files) simulated by robogen: written the way ECOS, OMSimulator
and the SSP standard's samples (read by FMPy) write theirs (tests/cosim/ssp_samples.py), and an
SSP 2.0 file with clocks by hand. Expected values come from the test FMUs' equations
(tests/cosim/fmus) and the files' units, mappings and transformations, worked out below."""

from __future__ import annotations

import math
import zipfile

import pytest
import ssp_samples

from robogen.cosim import simulate_system
from robogen.diagnostics import RobogenError

G = 9.81


def rows_of(result) -> list[dict]:
    return [dict(zip(result.columns, r)) for r in result.rows]


def test_an_ecos_style_archive_runs_with_its_parameter_files(tmp_path, fmus):
    ssp = ssp_samples.ecos(tmp_path / "bouncing.ssp", fmus)
    warnings = []
    result = simulate_system(ssp, step=0.05, warn=warnings.append)  # ECOS's step is in an OSP annotation
    rows = [r for r in rows_of(result) if r["superdense"] == 0]
    assert [r["time"] for r in rows] == pytest.approx([0.05 * k for k in range(11)])
    for r in rows:  # h0 = 2 from ssv/initialValues_ball.ssv: no bounce before sqrt(2 * 2 / g) = 0.64 s
        assert r["ball.h"] == pytest.approx(2 - G / 2 * r["time"] ** 2)
        assert r["ball.v"] == pytest.approx(-G * r["time"])
    for before, now in zip(rows, rows[1:]):  # trivial: y = u + t, u = the ball's height at the point before
        assert now["lift.y"] == pytest.approx(before["ball.h"] + now["time"])
    assert sorted(w.message for w in warnings) == [
        "parameter 'gravity' is not applied: the FMU of component 'ball' has no such variable",
        "the file uses the prefix 'ssv' without declaring its namespace (xmlns:...); read as SSP's"]
    assert str(warnings[0].span).startswith(f"{ssp}/ssv/initialValues_ball.ssv:")


def test_without_a_step_the_error_says_where_robogen_reads_it(tmp_path, fmus):
    ssp = ssp_samples.ecos(tmp_path / "bouncing.ssp", fmus)
    with pytest.raises(RobogenError) as exc:
        simulate_system(ssp)
    d = exc.value.diagnostics[0]
    assert d.message == ("no communication step: give <rg:Experiment step=...> in a robogen annotation of "
                         "<ssd:DefaultExperiment> (docs/ssp.md) or --step")
    assert (d.span.path, d.span.line) == (f"{ssp}/SystemStructure.ssd", 41)  # <ssd:DefaultExperiment>


def oms_expected(rows: list[dict]) -> None:
    """The OMSimulator-style hierarchy (ssp_samples.OMS_SSD): root.offset = 2 m from the .ssv,
    mapped by the .ssm and converted to mm (2000), goes into plant.u (mm), then into a.u (m): 2.0,
    which the root's binding sets over the subsystem's own (5); a.y = 2 + t leaves the plant in cm
    and reaches b.u in m (x 100 x 0.01), then through the LinearTransformation: b.u = 2 a.y + 1;
    the stair's period is the .ssv's 1 halved by the mapping: it counts at 0.5 and 1.0."""
    plain = [r for r in rows if r["superdense"] == 0]
    assert [r["time"] for r in plain] == pytest.approx([0.1 * k for k in range(11)])
    for r in plain:
        assert r["plant__a.y"] == pytest.approx(2 + r["time"])
    for before, now in zip(plain, plain[1:]):
        assert now["b.y"] == pytest.approx(2 * before["plant__a.y"] + 1 + now["time"])
    assert [(r["time"], r["clock.counter"]) for r in rows if r["superdense"] == 1] == [(0.0, 0), (0.5, 1), (1.0, 2)]


def test_an_omsimulator_style_hierarchy_converts_units_maps_parameters_and_flattens(tmp_path, fmus):
    ssp = ssp_samples.oms(tmp_path / "hierarchy.ssp", fmus)
    result = simulate_system(ssp)  # the step (0.1) from its robogen annotation
    assert result.columns == ["time", "superdense", "plant__a.y", "b.y", "clock.counter"]
    oms_expected(rows_of(result))


def test_an_unpacked_ssp_runs_from_its_ssd_file_alike(tmp_path, fmus):
    ssp = ssp_samples.oms(tmp_path / "hierarchy.ssp", fmus)
    folder = tmp_path / "unpacked"
    zipfile.ZipFile(ssp).extractall(folder)
    packed = simulate_system(ssp, output=tmp_path / "packed.csv")
    unpacked = simulate_system(folder / "SystemStructure.ssd", output=tmp_path / "unpacked.csv")
    assert unpacked.rows == packed.rows
    assert (tmp_path / "unpacked.csv").read_bytes() == (tmp_path / "packed.csv").read_bytes()


def test_the_ssp_standards_sample_style_binds_by_hierarchical_names_prefixes_and_mappings(tmp_path, fmus):
    ssp = ssp_samples.sample(tmp_path / "sample.ssp", fmus)
    warnings = []
    result = simulate_system(ssp, step=0.1, warn=warnings.append)
    first = rows_of(result)[0]  # (0, 0): after initialisation, alltypes' y = u (its derive by 0 steps)
    assert first["Source.y_e"] == 2  # "high" mapped to "mid": the enumeration Level's item 2
    assert first["Source.y_b"] is False  # true mapped to false
    assert first["Source.y_s"] == 'hello,"0"'
    assert first["Source.y_f64"] == 10 + 0.1  # SampleSystem.ssv's Source.u_f64 (derive adds 0.1)
    assert first["SubSystem__Sink.y_i32"] == 43  # Source.u_i32 = 42, mapped to SubSystem.Sink.u_i32 and to 43
    assert first["SubSystem__Sink.y_f32"] == -2.5
    assert first["SubSystem__Sink.y_s"] == 'sink,"0"'
    # Source.y_f64 reaches Sink.u_f64 through the subsystem's connector In1: Sink.y_f64 = derive(u, n)
    for r in rows_of(result)[2:]:
        assert r["SubSystem__Sink.y_f64"] is not None
    assert [w.message for w in warnings] == [
        "parameter 'SubSystem.Nothing.k' is not applied: system 'SampleSystem' has no parameter, connector or element "
        "variable of that name"]


CLOCKS_SSD = """<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription"
    xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" version="2.0" name="relay">
  <ssd:System name="relay">
    <ssd:Elements>
      <ssd:Component name="k" source="resources/ticker.fmu">
        <ssd:Connectors>
          <ssd:Connector name="tick" kind="input"><ssc:Clock intervalVariability="constant" intervalDecimal="0.25"/></ssd:Connector>
          <ssd:Connector name="out" kind="output"><ssc:Clock intervalVariability="triggered"/></ssd:Connector>
          <ssd:Connector name="count" kind="output"><ssc:Int64/><ssd:Clock name="out"/></ssd:Connector>
        </ssd:Connectors>
      </ssd:Component>
      <ssd:Component name="r" source="resources/relay.fmu">
        <ssd:Connectors>
          <ssd:Connector name="u" kind="input"><ssc:Clock intervalVariability="triggered"/></ssd:Connector>
          <ssd:Connector name="x_in" kind="input"><ssc:Int64/><ssd:Clock name="u"/></ssd:Connector>
          <ssd:Connector name="x_out" kind="output"><ssc:Int64/><ssd:Clock name="y"/></ssd:Connector>
        </ssd:Connectors>
      </ssd:Component>
    </ssd:Elements>
    <ssd:Connections>
      <ssd:Connection startElement="k" startConnector="out" endElement="r" endConnector="u"/>
      <ssd:Connection startElement="k" startConnector="count" endElement="r" endConnector="x_in"/>
    </ssd:Connections>
  </ssd:System>
  <ssd:DefaultExperiment startTime="0" stopTime="2">
    <ssd:Annotations>
      <ssc:Annotation type="robogen">
        <rg:Experiment xmlns:rg="urn:robogen:ssp" step="0.1">
          <rg:Record><rg:Variables><rg:Variable name="k.count"/><rg:Variable name="r.*"/></rg:Variables></rg:Record>
        </rg:Experiment>
      </ssc:Annotation>
    </ssd:Annotations>
  </ssd:DefaultExperiment>
</ssd:SystemStructureDescription>
"""

CLOCKS_TOML = """connections = ["k.out -> r.u", "k.count -> r.x_in"]
[experiment]
stop = 2.0
step = 0.1
[instances.k]
fmu = "{ticker}"
[instances.r]
fmu = "{relay}"
[record]
variables = ["k.count", "r.*"]
"""


def test_an_ssp_2_file_connects_clocks_and_clocked_values_as_a_system_file_does(tmp_path, fmus, write_system):
    ssp = ssp_samples.write_ssp(tmp_path / "relay.ssp", CLOCKS_SSD, {"ticker.fmu": fmus["ticker"], "relay.fmu": fmus["relay"]})
    from_ssp = simulate_system(ssp, output=tmp_path / "ssp.csv", events=tmp_path / "ssp.jsonl")
    from_toml = simulate_system(write_system(CLOCKS_TOML), output=tmp_path / "toml.csv", events=tmp_path / "toml.jsonl")
    assert from_ssp.columns == from_toml.columns == ["time", "superdense", "k.count", "r.u", "r.y", "r.x_out", "r.n"]
    assert from_ssp.rows == from_toml.rows
    assert (tmp_path / "ssp.jsonl").read_bytes() == (tmp_path / "toml.jsonl").read_bytes()
    fired = [(r["time"], r["r.x_out"]) for r in rows_of(from_ssp) if r["r.y"] == 1]
    assert fired == [(0.25 * k, k + 2) for k in range(9)]  # the k-th tick's count (k + 1), one more in the relay


def test_robogen_simulate_runs_an_archive_from_the_command_line(tmp_path, fmus, robogen_process):
    ssp = ssp_samples.oms(tmp_path / "hierarchy.ssp", fmus)
    done = robogen_process("simulate", ssp, "-o", "out.csv", "--stop", "0.5")
    assert done.returncode == 0, done.stderr
    assert f"simulated {ssp} to t=0.5" in done.stderr
    lines = (tmp_path / "out.csv").read_text().splitlines()
    assert lines[0] == "time,superdense,plant__a.y,b.y,clock.counter"
    assert lines[-1].startswith("0.5,1,2.5,")


def test_ecos_runs_the_ecos_style_archive_to_robogens_values(tmp_path, fmus):
    """The peer itself (the bench extra: make bench installs it): ECOS runs the ECOS-style archive
    with its parameter set, and its CSV (six decimals) holds robogen's values."""
    import csv
    import importlib.util
    import subprocess
    import sys

    from support import ROOT

    if importlib.util.find_spec("ecospy") is None:
        pytest.skip("ECOS (ecospy, the bench extra) is not installed")
    sys.path.insert(0, str(ROOT / "bench"))
    try:
        from ecos_peer import Ecos
    finally:
        sys.path.remove(str(ROOT / "bench"))
    ecos = Ecos.find(tmp_path)
    if isinstance(ecos, str):
        pytest.skip(ecos)
    ssp = ssp_samples.ecos(tmp_path / "bouncing.ssp", fmus)
    done = subprocess.run([str(ecos.program), "simulate", "--path", str(ssp), "--stopTime", "0.5", "--stepSize", "0.05",
                           "--parameterSet", "initialValues", "--logLevel", "warn"], cwd=tmp_path, env=ecos.env,
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    theirs = [{k.strip(): v.strip() for k, v in row.items()} for row in csv.DictReader(open(tmp_path / "bouncing.csv"))]
    ours = [r for r in rows_of(simulate_system(ssp, step=0.05)) if r["superdense"] == 0]
    assert len(theirs) == len(ours) == 11
    for a, b in zip(theirs, ours):
        assert float(a["time"]) == pytest.approx(b["time"])
        assert float(a["ball::h[REAL]"]) == pytest.approx(b["ball.h"], abs=1e-6)
        assert float(a["lift::y[REAL]"]) == pytest.approx(b["lift.y"], abs=1e-6)


UNITS_SSD = """<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription"
    xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" version="2.0" name="units">
  <ssd:System name="units">
    <ssd:Elements>
      <ssd:Component name="a" source="resources/m.fmu">
        <ssd:Connectors><ssd:Connector name="y" kind="output"><ssc:Float64/></ssd:Connector></ssd:Connectors>
      </ssd:Component>
      <ssd:Component name="b" source="resources/mm.fmu">
        <ssd:Connectors><ssd:Connector name="u" kind="input"><ssc:Float64/></ssd:Connector></ssd:Connectors>
      </ssd:Component>
      <ssd:Component name="c" source="resources/cm.fmu">
        <ssd:Connectors><ssd:Connector name="u" kind="input"><ssc:Float64/></ssd:Connector></ssd:Connectors>
      </ssd:Component>
    </ssd:Elements>
    <ssd:Connections>
      <ssd:Connection startElement="a" startConnector="y" endElement="b" endConnector="u"/>
      <ssd:Connection startElement="a" startConnector="y" endElement="c" endConnector="u"/>
    </ssd:Connections>
  </ssd:System>
  <ssd:Units>
    <ssc:Unit name="cm"><ssc:BaseUnit m="1" factor="0.01"/></ssc:Unit>
  </ssd:Units>
  <ssd:DefaultExperiment startTime="0" stopTime="0.5"/>
</ssd:SystemStructureDescription>
"""


def test_units_from_the_fmus_convert_connected_values(tmp_path, unit_fmus):
    """Connectors without a unit take their FMU variable's: a.y in m (defined by a's FMU) reaches
    b.u in mm (defined by b's) times 1000, and c.u in cm (which c's FMU names without defining it:
    the SSD's <ssd:Units> defines it) times 100. trivial: y(t_k) = u(t_(k-1)) + t_k, a.u = 0."""
    fmus = {f"{name}.fmu": path for name, path in unit_fmus.items()}
    ssp = ssp_samples.write_ssp(tmp_path / "units.ssp", UNITS_SSD, fmus)
    rows = [r for r in rows_of(simulate_system(ssp, step=0.1)) if r["superdense"] == 0]
    assert [r["time"] for r in rows] == pytest.approx([0.1 * k for k in range(6)])
    for before, now in zip(rows, rows[1:]):
        assert now["a.y"] == pytest.approx(now["time"])
        assert now["b.y"] == pytest.approx(1000 * before["a.y"] + now["time"])
        assert now["c.y"] == pytest.approx(100 * before["a.y"] + now["time"])
    assert rows[-1]["b.y"] == pytest.approx(400.5) and rows[-1]["c.y"] == pytest.approx(40.5)
    undefined = ssp_samples.write_ssp(tmp_path / "undefined.ssp", UNITS_SSD.replace('name="cm"', 'name="dm"'), fmus)
    with pytest.raises(RobogenError) as exc:
        simulate_system(undefined, step=0.1)
    assert [(d.span.line, d.message) for d in exc.value.diagnostics] == [  # the connection into c.u
        (18, "cannot convert 'm' (m) to 'cm' (no base unit): a unit without a base unit converts only to itself "
             "(connection 'a.y -> c.u')")]


#: SSP 1.0 as the other tools write it around FMI 2.0 FMUs: a lag (lag2me) through its Model
#: Exchange interface, feeding an FMI 2.0 Co-Simulation lag (lag2), feeding an FMI 3.0 trivial; a
#: Model Exchange ball (bounce2) integrated by explicit Euler (robogen's annotation), falling from
#: 1 m at g = 1: no bounce before sqrt(2) s
INTERFACES_SSD = f"""<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription {ssp_samples.NS} version="1.0" name="interfaces">
  <ssd:System name="interfaces">
    <ssd:Elements>
      <ssd:Component name="me" source="resources/lag2me.fmu" implementation="ModelExchange">
        <ssd:Connectors><ssd:Connector name="x" kind="output"><ssc:Real/></ssd:Connector></ssd:Connectors>
        <ssd:ParameterBindings><ssd:ParameterBinding><ssd:ParameterValues><ssv:ParameterSet version="1.0" name="p">
          <ssv:Parameters><ssv:Parameter name="tau"><ssv:Real value="0.25"/></ssv:Parameter></ssv:Parameters>
        </ssv:ParameterSet></ssd:ParameterValues></ssd:ParameterBinding></ssd:ParameterBindings>
      </ssd:Component>
      <ssd:Component name="cs" source="resources/lag2.fmu">
        <ssd:Connectors>
          <ssd:Connector name="u" kind="input"><ssc:Real/></ssd:Connector>
          <ssd:Connector name="x" kind="output"><ssc:Real/></ssd:Connector>
        </ssd:Connectors>
      </ssd:Component>
      <ssd:Component name="t" source="resources/trivial.fmu">
        <ssd:Connectors><ssd:Connector name="u" kind="input"><ssc:Real/></ssd:Connector></ssd:Connectors>
      </ssd:Component>
      <ssd:Component name="b" source="resources/bounce2.fmu">
        <ssd:ParameterBindings><ssd:ParameterBinding><ssd:ParameterValues><ssv:ParameterSet version="1.0" name="p">
          <ssv:Parameters><ssv:Parameter name="g"><ssv:Real value="1"/></ssv:Parameter></ssv:Parameters>
        </ssv:ParameterSet></ssd:ParameterValues></ssd:ParameterBinding></ssd:ParameterBindings>
        <ssd:Annotations><ssc:Annotation type="robogen">
          <rg:Instance xmlns:rg="urn:robogen:ssp" solver="euler" solverStep="0.01"/>
        </ssc:Annotation></ssd:Annotations>
      </ssd:Component>
    </ssd:Elements>
    <ssd:Connections>
      <ssd:Connection startElement="me" startConnector="x" endElement="cs" endConnector="u"/>
      <ssd:Connection startElement="cs" startConnector="x" endElement="t" endConnector="u"/>
    </ssd:Connections>
  </ssd:System>
  <ssd:DefaultExperiment startTime="0" stopTime="1"/>
</ssd:SystemStructureDescription>
"""

INTERFACES_TOML = """connections = ["me.x -> cs.u", "cs.x -> t.u"]
[experiment]
stop = 1.0
step = 0.1
[instances.me]
fmu = "{lag2me}"
interface = "model-exchange"
start = { tau = 0.25 }
[instances.cs]
fmu = "{lag2}"
[instances.t]
fmu = "{trivial}"
[instances.b]
fmu = "{bounce2}"
solver = "euler"
solver_step = 0.01
start = { g = 1.0 }
"""


def test_fmi_2_fmus_and_their_interfaces_run_from_an_ssp_1_archive_as_from_its_system_file(tmp_path, fmus, write_system):
    """A component's implementation is the instance's interface, robogen's annotation its solver:
    the same rows as the system file; the ME lag by CVode: x = 1 - exp(-t / 0.25) (u = 1)."""
    names = ("lag2me", "lag2", "trivial", "bounce2")
    ssp = ssp_samples.write_ssp(tmp_path / "interfaces.ssp", INTERFACES_SSD, {f"{n}.fmu": fmus[n] for n in names})
    from_ssp = simulate_system(ssp, step=0.1, output=tmp_path / "ssp.csv")
    simulate_system(write_system(INTERFACES_TOML), output=tmp_path / "toml.csv")
    assert (tmp_path / "ssp.csv").read_bytes() == (tmp_path / "toml.csv").read_bytes()
    for r in rows_of(from_ssp):
        assert r["me.x"] == pytest.approx(1 - math.exp(-r["time"] / 0.25), rel=1e-4, abs=1e-6)
        assert r["b.h"] == pytest.approx(1 - r["time"] ** 2 / 2, abs=0.01 * r["time"])  # Euler's error: h t / 2
    fmu_files = {f"{n}.fmu": fmus[n] for n in names}
    for case, (before, after) in {"solver": ('solver="euler"', 'solver="rk4"'), "interface": (
            'source="resources/lag2.fmu"', 'source="resources/lag2.fmu" implementation="ModelExchange"')}.items():
        bad = ssp_samples.write_ssp(tmp_path / f"{case}.ssp", INTERFACES_SSD.replace(before, after), fmu_files)
        with pytest.raises(RobogenError) as exc:
            simulate_system(bad, step=0.1)
        line = INTERFACES_SSD.count("\n", 0, INTERFACES_SSD.index(before)) + 1
        message = {"solver": "'solver' must be one of cvode, euler, not 'rk4'",
                   "interface": "the FMU does not offer FMI 2.0 model exchange"}[case]
        assert [(d.span.line, d.message) for d in exc.value.diagnostics] == [(line, message)]
