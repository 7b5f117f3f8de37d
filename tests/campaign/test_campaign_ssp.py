"""A campaign whose base system is an SSP archive (system = "system.ssp"): its flattened
instances are the parameters' instances, its parameter bindings the base start values, and a
second invocation finds every run already done (the runs' keys do not depend on where the
archive was unpacked)."""

from __future__ import annotations

import zipfile

import pyarrow.parquet as pq

from robogen.campaign import run_campaign
from support.campaign import run_quietly, write_campaign_folder

SSD = """<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription"
    xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon"
    xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" name="base">
  <ssd:System name="base">
    <ssd:Elements>
      <ssd:System name="plant">
        <ssd:Elements>
          <ssd:Component name="c" source="resources/crasher.fmu">
            <ssd:Connectors>
              <ssd:Connector name="y" kind="output"><ssc:Real/></ssd:Connector>
            </ssd:Connectors>
            <ssd:ParameterBindings>
              <ssd:ParameterBinding>
                <ssd:ParameterValues>
                  <ssv:ParameterSet version="1.0" name="base">
                    <ssv:Parameters>
                      <ssv:Parameter name="gain"><ssv:Real value="2"/></ssv:Parameter>
                      <ssv:Parameter name="delay"><ssv:Real value="0"/></ssv:Parameter>
                    </ssv:Parameters>
                  </ssv:ParameterSet>
                </ssd:ParameterValues>
              </ssd:ParameterBinding>
            </ssd:ParameterBindings>
          </ssd:Component>
        </ssd:Elements>
      </ssd:System>
      <ssd:Component name="ticker" source="resources/ticker.fmu"/>
    </ssd:Elements>
  </ssd:System>
  <ssd:DefaultExperiment startTime="0" stopTime="2"/>
</ssd:SystemStructureDescription>
"""

CAMPAIGN = """\
system = "system.ssp"
stop = 1.0
step = 0.25

[grid]
"plant__c.gain" = [1.0, 3.0]

[metrics]
y = { final = "plant__c.y" }
ticks = { ticks = "ticker.out" }
"""


def test_a_campaign_runs_an_ssp_like_a_system_file(tmp_path, campaign_fmus):
    campaign = write_campaign_folder(tmp_path, campaign_fmus, CAMPAIGN)
    with zipfile.ZipFile(tmp_path / "system.ssp", "w") as z:
        z.writestr("SystemStructure.ssd", SSD)
        z.write(campaign_fmus["crasher"], "resources/crasher.fmu")
        z.write(campaign_fmus["ticker"], "resources/ticker.fmu")
    run_quietly(campaign, tmp_path / "out", workers=1)
    rows = pq.read_table(tmp_path / "out" / "runs.parquet").to_pylist()
    # crasher: y = gain * t; the ticker's clock ticks at 0, 0.25, ..., 1.0
    assert [(r["status"], r["plant__c.gain"], r["y"], r["ticks"]) for r in rows] == [("ok", 1.0, 1.0, 5), ("ok", 3.0, 3.0, 5)]
    lines: list[str] = []
    run_campaign(campaign, tmp_path / "out", workers=1, progress=False, echo=lines.append)
    assert any("2 already done, 0 to run" in line for line in lines), lines
