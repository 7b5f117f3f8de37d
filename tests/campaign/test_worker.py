"""A worker's runs: each in a child of the zygote, which is warmed only by a run that succeeded."""

from __future__ import annotations

import pytest

from robogen.campaign import worker
from robogen.campaign.plan import make_plan
from robogen.campaign.spec import load_campaign

#: y = gain * t over [0, 2] s; crash_time 0.25: a segfault in the first step.
CAMPAIGN = """\
system = "system.toml"
timeout = 30.0

[grid]
"crasher.crash_time" = [0.25, -1.0]
"crasher.gain" = [1.0, 2.0]

[metrics]
y = { final = "crasher.y" }
"""


@pytest.fixture
def state(monkeypatch):
    here = worker._WorkerState()
    monkeypatch.setattr(worker, "_state", here)
    yield here
    here.close()


def test_the_zygote_is_warmed_only_after_a_run_succeeded(campaign_dir, campaign_fmus, state):
    plan = make_plan(load_campaign(campaign_dir(CAMPAIGN)))
    fmus = {digest: path.read_bytes() for digest, path in plan.fmu_files.items()}
    crash_1, crash_2, ok_1, ok_2 = plan.runs
    assert [r.values for r in plan.runs][::3] == [{"crasher.crash_time": 0.25, "crasher.gain": 1.0},
                                                  {"crasher.crash_time": -1.0, "crasher.gain": 2.0}]

    def execute(run):
        return worker.execute_run(plan.context, run.spec, fmus)

    row = execute(crash_1)
    assert (row["status"], row["error"]) == ("failed", "crashed: the run's process was killed by SIGSEGV (Segmentation fault)")
    zygote = state.zygote.process.pid
    assert not state.proven and not state.rehearsed  # a crashed run is never repeated in the zygote
    row = execute(ok_1)
    assert (row["status"], row["end_time"], row["metrics"]) == ("ok", 2.0, {"y": 2.0})
    assert list(state.proven.values()) == [ok_1.spec] and not state.rehearsed  # warmed when another run comes
    row = execute(crash_2)  # warmed with ok_1 first; the warmed zygote still isolates a crash
    assert row["error"].startswith("crashed: the run's process was killed by SIGSEGV")
    assert not state.proven and len(state.rehearsed) == 1
    row = execute(ok_2)
    assert (row["status"], row["metrics"]) == ("ok", {"y": 4.0})
    assert state.zygote.process.pid == zygote and state.zygote.process.poll() is None


RAMP_SYSTEM = """\
[experiment]
stop = 2.0
step = 0.25

[instances.ramp]
fmu = "ramp.fmu"
"""
RAMP_CAMPAIGN = """\
system = "system.toml"
timeout = 30.0

[grid]
"ramp.gain" = [1.0, 2.0, 3.0]

[metrics]
y = { final = "ramp.y" }
"""


def test_a_warmed_zygote_keeps_the_python_fmus_for_its_children(tmp_path, state):
    # the zygote extracts and loads a Python FMU once, in the worker's folder, and its children
    # (the later runs) use that copy: robogen.cosim.shared
    from support.campaign import write_campaign_folder

    from robogen.pyfmu.build import package

    ramp = package("pyfmu_ramp:Ramp", tmp_path / "built" / "ramp.fmu").path
    plan = make_plan(load_campaign(write_campaign_folder(tmp_path, {"ramp": ramp}, RAMP_CAMPAIGN, RAMP_SYSTEM)))
    fmus = {digest: path.read_bytes() for digest, path in plan.fmu_files.items()}
    rows = []
    for run in plan.runs:
        rows.append(worker.execute_run(plan.context, run.spec, fmus))
        if run is plan.runs[0]:
            assert not list(state.folder.glob("robogen-pyfmus-*"))  # the zygote is warmed by the next run
    assert [(r["status"], r["metrics"]) for r in rows] == [("ok", {"y": 2.0}), ("ok", {"y": 4.0}), ("ok", {"y": 6.0})]
    assert len(state.rehearsed) == 1
    kept = list(state.folder.glob("robogen-pyfmus-*/*/resources/pyfmu.json"))
    assert len(kept) == 1  # extracted once, in the zygote, and still there for its children
