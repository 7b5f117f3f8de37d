"""Bad SSP files: each problem a located error (the line and column of the element or attribute
that causes it, in the archive's file), all problems of a file together, no traceback, nothing
run; a hostile archive refused before anything is written."""

from __future__ import annotations

import zipfile

import pytest
import ssp_samples
from test_ssp_import import CLOCKS_SSD

from robogen.cosim import simulate_system
from robogen.diagnostics import RobogenError


def where(text: str, needle: str, nth: int = 0) -> tuple[int, int]:
    """(line, column) of the nth occurrence of ``needle`` in ``text``."""
    at = -1
    for _ in range(nth + 1):
        at = text.index(needle, at + 1)
    return text.count("\n", 0, at) + 1, at - (text.rfind("\n", 0, at) + 1) + 1


def clocks(tmp_path, fmus, ssd: str, name: str = "bad.ssp", **extra):
    return ssp_samples.write_ssp(tmp_path / name, ssd, {"ticker.fmu": fmus["ticker"], "relay.fmu": fmus["relay"]}, extra)


def errors(path, **kwargs) -> list[tuple[str, int, int, str]]:
    with pytest.raises(RobogenError) as exc:
        simulate_system(path, **kwargs)
    return [(d.span.path if d.span else "", d.span.line if d.span else 0, d.span.column if d.span else 0, d.message)
            for d in exc.value.diagnostics if d.is_error]


# -- the five of the issue, through the command line: exit 1, located, no traceback ------------

MISSING = CLOCKS_SSD.replace('source="resources/relay.fmu"', 'source="resources/relays.fmu"')
UNKNOWN = CLOCKS_SSD.replace('endElement="r" endConnector="x_in"', 'endElement="r" endConnector="x_inn"')
CLOCK_TO_VALUE = CLOCKS_SSD.replace('startElement="k" startConnector="count"', 'startElement="k" startConnector="out"')
SCHEMA = CLOCKS_SSD.replace('<ssd:Connector name="x_out" kind="output">', '<ssd:Connector name="x_out" kind="out">')

CASES = {
    "missing component file": (MISSING, 'source="', 1, "component file not found in {ssp}: resources/relays.fmu"),
    "unknown connector": (UNKNOWN, 'endConnector="x_inn"', 0, "component 'r' has no connector 'x_inn' (did you mean 'x_in'?)"),
    "clock wired to a value": (CLOCK_TO_VALUE, '<ssd:Connection startElement="k" startConnector="out" endElement="r" endConnector="x_in"', 0,
                               "a clock connects only to a clock: 'k.out' is a clock, 'r.x_in' is a variable of type Int64"),
    "schema violation": (SCHEMA, 'kind="out"', 0, "<ssd:Connector>: kind=\"out\" is not one of 'input', 'output', 'parameter', "
                         "'calculatedParameter', 'inout', 'constant', 'local', 'structuralParameter', 'unspecified'"),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_a_bad_file_is_a_located_error_at_the_command_line(case, tmp_path, fmus, robogen_process):
    ssd, needle, nth, message = CASES[case]
    ssp = clocks(tmp_path, fmus, ssd)
    line, column = where(ssd, needle, nth)
    done = robogen_process("simulate", ssp, "-o", "out.csv")
    assert done.returncode == 1
    assert "Traceback" not in done.stderr and "internal error" not in done.stderr
    head = done.stderr.splitlines()[0]
    assert head == f"bad.ssp/SystemStructure.ssd:{line}:{column}: error: {message.format(ssp=ssp)}"  # relative to the working folder
    assert not (tmp_path / "out.csv").exists()


def test_a_hostile_archive_is_refused_before_anything_is_written(tmp_path, fmus, robogen_process):
    ssp = tmp_path / "work" / "slip.ssp"
    ssp.parent.mkdir()
    with zipfile.ZipFile(ssp, "w") as z:
        z.writestr("SystemStructure.ssd", CLOCKS_SSD)
        z.write(fmus["ticker"], "resources/ticker.fmu")
        z.writestr("../escaped.txt", "outside")
        z.writestr("resources/../../also-escaped.txt", "outside")
    done = robogen_process("simulate", ssp)
    assert done.returncode == 1 and "Traceback" not in done.stderr
    assert done.stderr.splitlines()[:2] == [
        "work/slip.ssp:1:1: error: unsafe archive member '../escaped.txt': member path contains '..'",
        "work/slip.ssp:1:1: error: unsafe archive member 'resources/../../also-escaped.txt': member path contains '..'"]
    assert not (tmp_path / "escaped.txt").exists() and not (tmp_path / "also-escaped.txt").exists()
    assert list((tmp_path / "tmp").iterdir()) == []  # nothing unpacked left behind


# -- more: each at its place, all of a file together ----------------------------------------------

def test_every_problem_of_a_file_is_reported_together(tmp_path, fmus):
    ssd = (CLOCKS_SSD.replace('endElement="r" endConnector="x_in"', 'endElement="q" endConnector="x_in"')
           .replace('<ssd:Connector name="u" kind="input">', '<ssd:Connector name="uu" kind="input">')
           .replace('step="0.1"', 'step="-1" pace="2"'))
    ssp = clocks(tmp_path, fmus, ssd)
    path = f"{ssp}/SystemStructure.ssd"
    got = errors(ssp)
    assert got == sorted(got)
    assert (path, *where(ssd, 'name="uu"'), "the FMU of component 'r' has no variable 'uu' (did you mean 'u'?)") in got
    assert (path, *where(ssd, 'endElement="q"'), "system 'relay' has no element 'q'") in got
    assert (path, *where(ssd, 'endConnector="u"'), "component 'r' has no connector 'u' (did you mean 'uu'?)") in got
    assert (path, *where(ssd, 'step="-1"'), "'step' must be a positive number, not '-1'") in got
    assert (path, *where(ssd, 'pace="2"'), "<rg:Experiment> has no attribute 'pace'") in got


BAD = {
    # a connection between two inputs
    "two inputs": (CLOCKS_SSD.replace('startElement="k" startConnector="count"', 'startElement="r" startConnector="x_in"')
                   .replace('endElement="r" endConnector="x_in"', 'endElement="k" endConnector="tick"'),
                   "<ssd:Connection startElement=\"r\"", "a connection needs one end that produces a value and one that "
                   "consumes it; both consume one: 'r.x_in' (input) and 'k.tick' (input)"),
    # a connector of the wrong kind, and of the wrong type
    "kind": (CLOCKS_SSD.replace('<ssd:Connector name="x_out" kind="output">', '<ssd:Connector name="x_out" kind="input">'),
             'kind="input"><ssc:Int64/><ssd:Clock name="y"', "connector 'x_out' of component 'r' is of kind input, but the "
             "FMU's variable is output"),
    "type": (CLOCKS_SSD.replace('name="count" kind="output"><ssc:Int64/>', 'name="count" kind="output"><ssc:Float64/>'),
             '<ssd:Connector name="count"', "connector 'count' of component 'k' is typed Float64, but the FMU's variable is Int64"),
    # a clock association that is not the variable's clock, and a clock of another variability
    "association": (CLOCKS_SSD.replace('<ssd:Clock name="u"/>', '<ssd:Clock name="y"/>'), 'name="y"/></ssd:Connector>\n',
                    "connector 'x_in' is associated to the clock 'y', but the FMU's variable is clocked by: u"),
    "variability": (CLOCKS_SSD.replace('<ssc:Clock intervalVariability="constant" intervalDecimal="0.25"/>',
                                       '<ssc:Clock intervalVariability="fixed" intervalDecimal="0.25"/>'),
                    'intervalVariability="fixed"', "clock connector 'tick' of component 'k' says intervalVariability \"fixed\", "
                    "but the FMU's clock is constant"),
    "interval": (CLOCKS_SSD.replace('intervalDecimal="0.25"', 'intervalDecimal="0.5"'), 'intervalDecimal="0.5"',
                 "clock 'tick' is constant: its interval is its FMU's (0.25), not 0.5"),
    # a source that leaves the package, a component that is not an FMU, a signal dictionary
    "escape": (CLOCKS_SSD.replace('source="resources/relay.fmu"', 'source="../relay.fmu"'), 'source="../relay.fmu"',
               "'../relay.fmu' leads out of the SSP: a source must stay inside it"),
    "absolute": (CLOCKS_SSD.replace('source="resources/relay.fmu"', 'source="file:///etc/relay.fmu"'), 'source="file:',
                 "'file:///etc/relay.fmu' is not a relative reference: robogen resolves sources inside the SSP only "
                 "(e.g. resources/model.fmu)"),
    "nested ssp": (CLOCKS_SSD.replace('<ssd:Component name="r" source="resources/relay.fmu">',
                                      '<ssd:Component name="r" source="resources/relay.ssp" type="application/x-ssp-package">'),
                   'type="application/x-ssp-package"', "component 'r' is an SSP archive: robogen runs components of type "
                   "application/x-fmu-sharedlibrary (FMUs) and nested <ssd:System> elements"),
    # XML that is not well formed, a document type declaration, a file of SSP 1.0 using SSP 2.0
    "xml": (CLOCKS_SSD.replace("</ssd:Elements>", "</ssd:Element>"), "</ssd:Element>", "not well-formed XML: mismatched tag"),
    "doctype": (CLOCKS_SSD.replace("<ssd:SystemStructureDescription", '<!DOCTYPE x [<!ENTITY a "b">]>\n<ssd:SystemStructureDescription'),
                "<!DOCTYPE", "a document type declaration (<!DOCTYPE ...>) is not allowed in an SSP file"),
    "version": (CLOCKS_SSD.replace('version="2.0"', 'version="1.0"'), '<ssc:Clock intervalVariability="constant"',
                "<ssc:Clock> is SSP 2.0; this file says version=\"1.0\" (SSP 1.0)"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_a_bad_file_is_refused_at_the_element_that_is_wrong(case, tmp_path, fmus):
    ssd, needle, message = BAD[case]
    ssp = clocks(tmp_path, fmus, ssd)
    got = errors(ssp)
    line, column = where(ssd, needle)
    if case == "xml":
        column += 2  # expat points after '</'
    assert got[0] == (f"{ssp}/SystemStructure.ssd", line, column, message)


def test_parameter_problems_are_located_in_their_parameter_files(tmp_path, fmus):
    ssv = ssp_samples.SAMPLE_SSV.replace('<ssv:Real value="-2.5"/>', '<ssv:Boolean value="true"/>')
    ssd = ssp_samples.SAMPLE_SSD.replace('<ssv:Enumeration value="high"/>', '<ssv:Enumeration value="highest"/>').replace(
        '<ssc:MapEntry source="high" target="mid"/>', '<ssc:MapEntry source="highest" target="top"/>')
    ssp = ssp_samples.write_ssp(tmp_path / "sample.ssp", ssd, {"alltypes.fmu": fmus["alltypes"]}, {"SampleSystem.ssv": ssv})
    got = errors(ssp, step=0.1)
    assert got == sorted(got)
    assert (f"{ssp}/SampleSystem.ssv", *where(ssv, '<ssv:Parameter name="SubSystem.Sink.u_f32">'),
            "parameter 'SubSystem.Sink.u_f32' is Boolean, but 'SubSystem__Sink.u_f32' is Float32") in got
    assert (f"{ssp}/SystemStructure.ssd", *where(ssd, '<ssm:MappingEntry source="Source.u_e"'),
            "'top' is not an item of the enumeration type Level of 'Source.u_e'") in got


def test_an_archive_without_a_system_structure_says_so(tmp_path, fmus):
    ssp = tmp_path / "variants.ssp"
    with zipfile.ZipFile(ssp, "w") as z:
        z.writestr("VariantA.ssd", CLOCKS_SSD)
    assert errors(ssp) == [(str(ssp), 1, 1, "the archive has no SystemStructure.ssd at its root")]


def test_a_folder_ssd_names_files_where_they_are(tmp_path, fmus):
    folder = tmp_path / "unpacked"
    (folder / "resources").mkdir(parents=True)
    (folder / "SystemStructure.ssd").write_text(MISSING)
    (folder / "resources" / "ticker.fmu").write_bytes(fmus["ticker"].read_bytes())
    got = errors(folder / "SystemStructure.ssd")
    assert got == [(str(folder / "SystemStructure.ssd"), *where(MISSING, 'source="', 1),
                    "component file not found: resources/relays.fmu")]
