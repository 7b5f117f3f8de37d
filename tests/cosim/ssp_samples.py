"""SSP archives written the way other tools write theirs, around robogen's own test FMUs
(tests/cosim/fmus): ECOS (flat systems, a component's parameters in ssv/ files, its algorithm
in an annotation of the default experiment), OMSimulator (systems in systems, system connectors
of kind parameter and input, a root binding with an .ssv and an .ssm file, its own annotations
everywhere, units at the end) and the SSP standard's sample systems that FMPy reads (a
subsystem behind its connectors, a binding with a prefix and an inline mapping). Each is written
here, for these tests; the expected values are worked out in test_ssp_import.py.
"""

from __future__ import annotations

import zipfile
from pathlib import Path

NS = ('xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" '
      'xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" '
      'xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" '
      'xmlns:ssm="http://ssp-standard.org/SSP1/SystemStructureParameterMapping"')


def write_ssp(target: Path, ssd: str, fmus: dict[str, Path], extra: dict[str, str | bytes] | None = None) -> Path:
    """An archive: SystemStructure.ssd, the FMUs under resources/, any other files."""
    with zipfile.ZipFile(target, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("SystemStructure.ssd", ssd)
        for name, path in fmus.items():
            z.write(path, f"resources/{name}")
        for name, data in (extra or {}).items():
            z.writestr(name, data)
    return target


# -- ECOS: a flat system, parameters in ssv/ (the ssv file declaring no namespace, as ECOS's
# quarter-truck example does), the step in an OSP annotation robogen does not read

ECOS_SSD = f"""<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription {NS}
                                xmlns:osp="http://opensimulationplatform.com/SSP/OSPAnnotations"
                                name="Bouncing"
                                version="1.0">

    <ssd:System name="BouncingSystem" description="a bouncing ball lifted by a trivial FMU">

        <ssd:Elements>
            <ssd:Component name="ball" source="resources/ball.fmu">
                <ssd:Connectors>
                    <ssd:Connector name="h" kind="output">
                        <ssc:Real/>
                    </ssd:Connector>
                    <ssd:Connector name="v" kind="output">
                        <ssc:Real/>
                    </ssd:Connector>
                </ssd:Connectors>
                <ssd:ParameterBindings>
                    <ssd:ParameterBinding source="ssv/initialValues_ball.ssv"/>
                </ssd:ParameterBindings>
            </ssd:Component>
            <ssd:Component name="lift" source="resources/trivial.fmu">
                <ssd:Connectors>
                    <ssd:Connector name="u" kind="input">
                        <ssc:Real/>
                    </ssd:Connector>
                    <ssd:Connector name="y" kind="output">
                        <ssc:Real/>
                    </ssd:Connector>
                </ssd:Connectors>
            </ssd:Component>
        </ssd:Elements>

        <ssd:Connections>
            <ssd:Connection startElement="ball" startConnector="h" endElement="lift" endConnector="u"/>
        </ssd:Connections>

    </ssd:System>

    <ssd:DefaultExperiment startTime="0" stopTime="0.5">
        <ssd:Annotations>
            <ssc:Annotation type="com.opensimulationplatform">
                <osp:Algorithm>
                    <osp:FixedStepAlgorithm baseStepSize="0.05"/>
                </osp:Algorithm>
            </ssc:Annotation>
        </ssd:Annotations>
    </ssd:DefaultExperiment>

</ssd:SystemStructureDescription>
"""

ECOS_SSV = """<?xml version="1.0" encoding="UTF-8"?>
<ssv:ParameterSet version="1.0" name="initialValues">
    <ssv:Parameters>
        <ssv:Parameter name="h0">
            <ssv:Real value="2"/>
        </ssv:Parameter>
        <ssv:Parameter name="e">
            <ssv:Real value="0.5"/>
        </ssv:Parameter>
        <ssv:Parameter name="gravity">
            <ssv:Real value="9.81"/>
        </ssv:Parameter>
    </ssv:Parameters>
</ssv:ParameterSet>"""


def ecos(target: Path, fmus: dict[str, Path]) -> Path:
    return write_ssp(target, ECOS_SSD, {"ball.fmu": fmus["ball"], "trivial.fmu": fmus["trivial"]},
                     {"ssv/initialValues_ball.ssv": ECOS_SSV})


# -- OMSimulator: a root system with connectors (a parameter in mm, an output in m) bound by an
# .ssv and an .ssm; a subsystem whose input in mm feeds a trivial FMU in m and whose output is in
# cm; a connection with a LinearTransformation; a clock FMU whose period the mapping halves; an
# inline binding in the subsystem that the root's binding overrides

OMS_SSD = f"""<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription {NS} xmlns:ssb="http://ssp-standard.org/SSP1/SystemStructureSignalDictionary" xmlns:oms="https://raw.githubusercontent.com/OpenModelica/OMSimulator/master/schema/oms.xsd" name="hierarchy" version="1.0" generationTool="a hand that writes like OMSimulator">
  <ssd:System name="root">
    <ssd:Connectors>
      <ssd:Connector name="offset" kind="parameter">
        <ssc:Real unit="mm" />
      </ssd:Connector>
      <ssd:Connector name="result" kind="output">
        <ssc:Real unit="m" />
      </ssd:Connector>
    </ssd:Connectors>
    <ssd:ParameterBindings>
      <ssd:ParameterBinding source="resources/hierarchy.ssv">
        <ssd:ParameterMapping source="resources/hierarchy.ssm" />
      </ssd:ParameterBinding>
    </ssd:ParameterBindings>
    <ssd:Elements>
      <ssd:System name="plant">
        <ssd:Connectors>
          <ssd:Connector name="u" kind="input">
            <ssc:Real unit="mm" />
          </ssd:Connector>
          <ssd:Connector name="y" kind="output">
            <ssc:Real unit="cm" />
          </ssd:Connector>
        </ssd:Connectors>
        <ssd:ParameterBindings>
          <ssd:ParameterBinding>
            <ssd:ParameterValues>
              <ssv:ParameterSet version="1.0" name="parameters">
                <ssv:Parameters>
                  <ssv:Parameter name="a.u">
                    <ssv:Real value="5" />
                  </ssv:Parameter>
                </ssv:Parameters>
              </ssv:ParameterSet>
            </ssd:ParameterValues>
          </ssd:ParameterBinding>
        </ssd:ParameterBindings>
        <ssd:Elements>
          <ssd:Component name="a" type="application/x-fmu-sharedlibrary" source="resources/trivial.fmu">
            <ssd:Connectors>
              <ssd:Connector name="u" kind="input">
                <ssc:Real unit="m" />
              </ssd:Connector>
              <ssd:Connector name="y" kind="output">
                <ssc:Real unit="m" />
              </ssd:Connector>
            </ssd:Connectors>
          </ssd:Component>
        </ssd:Elements>
        <ssd:Connections>
          <ssd:Connection startConnector="u" endElement="a" endConnector="u" />
          <ssd:Connection startElement="a" startConnector="y" endConnector="y" />
        </ssd:Connections>
        <ssd:Annotations>
          <ssc:Annotation type="org.openmodelica">
            <oms:Annotations>
              <oms:SimulationInformation>
                <oms:FixedStepMaster description="oms-ma" stepSize="0.100000" absoluteTolerance="0.000100" relativeTolerance="0.000100" />
              </oms:SimulationInformation>
            </oms:Annotations>
          </ssc:Annotation>
        </ssd:Annotations>
      </ssd:System>
      <ssd:Component name="b" type="application/x-fmu-sharedlibrary" source="resources/trivial.fmu">
        <ssd:Connectors>
          <ssd:Connector name="u" kind="input">
            <ssc:Real unit="m" />
          </ssd:Connector>
          <ssd:Connector name="y" kind="output">
            <ssc:Real unit="m" />
          </ssd:Connector>
        </ssd:Connectors>
      </ssd:Component>
      <ssd:Component name="clock" type="application/x-fmu-sharedlibrary" source="resources/stair.fmu">
        <ssd:Connectors>
          <ssd:Connector name="counter" kind="output">
            <ssc:Integer />
          </ssd:Connector>
          <ssd:Connector name="period" kind="parameter">
            <ssc:Real />
          </ssd:Connector>
        </ssd:Connectors>
      </ssd:Component>
    </ssd:Elements>
    <ssd:Connections>
      <ssd:Connection startConnector="offset" endElement="plant" endConnector="u" />
      <ssd:Connection startElement="plant" startConnector="y" endElement="b" endConnector="u">
        <ssc:LinearTransformation factor="2" offset="1" />
      </ssd:Connection>
      <ssd:Connection startElement="b" startConnector="y" endConnector="result" />
    </ssd:Connections>
    <ssd:Annotations>
      <ssc:Annotation type="org.openmodelica">
        <oms:Annotations>
          <oms:SimulationInformation>
            <oms:FixedStepMaster description="oms-ma" stepSize="0.100000" absoluteTolerance="0.000100" relativeTolerance="0.000100" />
          </oms:SimulationInformation>
        </oms:Annotations>
      </ssc:Annotation>
    </ssd:Annotations>
  </ssd:System>
  <ssd:Units>
    <ssc:Unit name="m">
      <ssc:BaseUnit m="1" />
    </ssc:Unit>
    <ssc:Unit name="cm">
      <ssc:BaseUnit m="1" factor="0.01" />
    </ssc:Unit>
    <ssc:Unit name="mm">
      <ssc:BaseUnit m="1" factor="0.001" />
    </ssc:Unit>
  </ssd:Units>
  <ssd:DefaultExperiment startTime="0.000000" stopTime="1.000000">
    <ssd:Annotations>
      <ssc:Annotation type="org.openmodelica">
        <oms:Annotations>
          <oms:SimulationInformation resultFile="hierarchy_res.mat" loggingInterval="0.000000" bufferSize="10" signalFilter=".*" />
        </oms:Annotations>
      </ssc:Annotation>
      <ssc:Annotation type="robogen">
        <rg:Experiment xmlns:rg="urn:robogen:ssp" step="0.1" />
      </ssc:Annotation>
    </ssd:Annotations>
  </ssd:DefaultExperiment>
</ssd:SystemStructureDescription>
"""

OMS_SSV = f"""<?xml version="1.0" encoding="UTF-8"?>
<ssv:ParameterSet {NS} version="1.0" name="parameters">
  <ssv:Parameters>
    <ssv:Parameter name="start_offset">
      <ssv:Real value="2" unit="m" />
    </ssv:Parameter>
    <ssv:Parameter name="clock_period">
      <ssv:Real value="1" />
    </ssv:Parameter>
    <ssv:Parameter name="not_mapped">
      <ssv:Real value="7" />
    </ssv:Parameter>
  </ssv:Parameters>
  <ssv:Units>
    <ssc:Unit name="m">
      <ssc:BaseUnit m="1" />
    </ssc:Unit>
  </ssv:Units>
</ssv:ParameterSet>
"""

OMS_SSM = """<?xml version="1.0" encoding="UTF-8"?>
<ssm:ParameterMapping xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" xmlns:ssm="http://ssp-standard.org/SSP1/SystemStructureParameterMapping" version="1.0">
  <ssm:MappingEntry source="start_offset" target="offset" />
  <ssm:MappingEntry source="clock_period" target="clock.period">
    <ssc:LinearTransformation factor="0.5" offset="0" />
  </ssm:MappingEntry>
</ssm:ParameterMapping>
"""


def oms(target: Path, fmus: dict[str, Path]) -> Path:
    return write_ssp(target, OMS_SSD, {"trivial.fmu": fmus["trivial"], "stair.fmu": fmus["stair"]},
                     {"resources/hierarchy.ssv": OMS_SSV, "resources/hierarchy.ssm": OMS_SSM})


# -- the SSP standard's sample systems, which FMPy reads: a subsystem behind its connectors, the
# root's parameters in a file (hierarchical names), and an inline binding with a prefix and an
# inline mapping (enumeration, boolean and integer mapping transformations)

SAMPLE_SSD = f"""<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription {NS} version="1.0" name="SampleSystem">
    <ssd:System name="SampleSystem">
        <ssd:Connectors>
            <ssd:Connector name="Out1" kind="output"><ssc:Real/></ssd:Connector>
        </ssd:Connectors>
        <ssd:ParameterBindings>
            <ssd:ParameterBinding source="SampleSystem.ssv"/>
            <ssd:ParameterBinding prefix="Source.">
                <ssd:ParameterValues>
                    <ssv:ParameterSet version="1.0" name="Source">
                        <ssv:Parameters>
                            <ssv:Parameter name="u_e"><ssv:Enumeration value="high"/></ssv:Parameter>
                            <ssv:Parameter name="u_b"><ssv:Boolean value="true"/></ssv:Parameter>
                            <ssv:Parameter name="u_i32"><ssv:Integer value="42"/></ssv:Parameter>
                            <ssv:Parameter name="u_s"><ssv:String value="hello"/></ssv:Parameter>
                        </ssv:Parameters>
                    </ssv:ParameterSet>
                </ssd:ParameterValues>
                <ssd:ParameterMapping>
                    <ssm:ParameterMapping version="1.0">
                        <ssm:MappingEntry source="Source.u_e" target="Source.u_e">
                            <ssc:EnumerationMappingTransformation>
                                <ssc:MapEntry source="high" target="mid"/>
                            </ssc:EnumerationMappingTransformation>
                        </ssm:MappingEntry>
                        <ssm:MappingEntry source="Source.u_b" target="Source.u_b">
                            <ssc:BooleanMappingTransformation>
                                <ssc:MapEntry source="true" target="false"/>
                                <ssc:MapEntry source="false" target="true"/>
                            </ssc:BooleanMappingTransformation>
                        </ssm:MappingEntry>
                        <ssm:MappingEntry source="Source.u_i32" target="SubSystem.Sink.u_i32">
                            <ssc:IntegerMappingTransformation>
                                <ssc:MapEntry source="42" target="43"/>
                            </ssc:IntegerMappingTransformation>
                        </ssm:MappingEntry>
                        <ssm:MappingEntry source="Source.u_s" target="Source.u_s"/>
                    </ssm:ParameterMapping>
                </ssd:ParameterMapping>
            </ssd:ParameterBinding>
        </ssd:ParameterBindings>
        <ssd:Elements>
            <ssd:Component name="Source" source="resources/alltypes.fmu">
                <ssd:Connectors>
                    <ssd:Connector name="y_f64" kind="output"><ssc:Real/></ssd:Connector>
                </ssd:Connectors>
            </ssd:Component>
            <ssd:System name="SubSystem">
                <ssd:Connectors>
                    <ssd:Connector name="In1" kind="input"><ssc:Real/></ssd:Connector>
                    <ssd:Connector name="Out1" kind="output"><ssc:Real/></ssd:Connector>
                </ssd:Connectors>
                <ssd:Elements>
                    <ssd:Component name="Sink" source="resources/alltypes.fmu">
                        <ssd:Connectors>
                            <ssd:Connector name="u_f64" kind="input"><ssc:Real/></ssd:Connector>
                            <ssd:Connector name="y_f64" kind="output"><ssc:Real/></ssd:Connector>
                        </ssd:Connectors>
                    </ssd:Component>
                </ssd:Elements>
                <ssd:Connections>
                    <ssd:Connection startConnector="In1" endElement="Sink" endConnector="u_f64"/>
                    <ssd:Connection startElement="Sink" startConnector="y_f64" endConnector="Out1"/>
                </ssd:Connections>
            </ssd:System>
        </ssd:Elements>
        <ssd:Connections>
            <ssd:Connection startElement="Source" startConnector="y_f64" endElement="SubSystem" endConnector="In1"/>
            <ssd:Connection startElement="SubSystem" startConnector="Out1" endConnector="Out1"/>
        </ssd:Connections>
    </ssd:System>
    <ssd:DefaultExperiment startTime="0" stopTime="0.5"/>
</ssd:SystemStructureDescription>
"""

SAMPLE_SSV = f"""<?xml version="1.0" encoding="UTF-8"?>
<ssv:ParameterSet {NS} version="1.0" name="SampleSystem">
    <ssv:Parameters>
        <ssv:Parameter name="Source.u_f64"><ssv:Real value="10"/></ssv:Parameter>
        <ssv:Parameter name="SubSystem.Sink.u_f32"><ssv:Real value="-2.5"/></ssv:Parameter>
        <ssv:Parameter name="SubSystem.Sink.u_s"><ssv:String value="sink"/></ssv:Parameter>
        <ssv:Parameter name="SubSystem.Nothing.k"><ssv:Real value="1"/></ssv:Parameter>
    </ssv:Parameters>
</ssv:ParameterSet>
"""


def sample(target: Path, fmus: dict[str, Path]) -> Path:
    return write_ssp(target, SAMPLE_SSD, {"alltypes.fmu": fmus["alltypes"]}, {"SampleSystem.ssv": SAMPLE_SSV})
