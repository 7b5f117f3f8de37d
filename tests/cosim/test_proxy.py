"""Isolated instances (robogen.cosim.proxy): the same results as in the master's process, in
the engine (through adapters), for every kind of call the master makes (clocks, FMU state, every value type)."""

from __future__ import annotations

import pytest

from robogen.cosim import RunError, simulate_system
from robogen.cosim.fmi3 import FMI3Error

G = 9.81
TYPES = ("f32", "f64", "i8", "u8", "i16", "u16", "i32", "u32", "i64", "u64", "b", "s", "bin", "e")
SYSTEMS = {
    # early returns with a rollback through fmi3GetFMUState/fmi3SetFMUState
    "rollback": f"""[experiment]
stop = 1.0
step = 0.5
order = ["b", "a"]
[instances.a]
fmu = "{{ball}}"
start = {{ h0 = {0.5 * G * 0.731**2!r} }}
[instances.b]
fmu = "{{ball}}"
start = {{ h0 = {0.5 * G * 0.9**2!r} }}
""",
    # clocks, clocked values of every type, intervals, the events log
    "alltypes": "connections = [" + ", ".join(
        [f'"a.y_{t} -> b.u_{t}"' for t in TYPES] + ['"a.out -> b.tin"'] + [f'"a.c_{t} -> b.ci_{t}"' for t in TYPES]) + "]\n"
        '[experiment]\nstop = 1.0\nstep = 0.1\n[instances.a]\nfmu = "{alltypes}"\n[instances.b]\nfmu = "{alltypes}"\n',
    # a terminate request
    "terminate": '[experiment]\nstop = 10.0\nstep = 0.5\n[instances.s]\nfmu = "{stair}"\nstart = { last = 3 }\n',
}


@pytest.mark.parametrize("name", sorted(SYSTEMS))
def test_isolated_instances_give_the_same_results(write_system, tmp_path, name):
    path = write_system(SYSTEMS[name], name=f"{name}.toml")
    here = simulate_system(path, output=tmp_path / "here.csv", events=tmp_path / "here.jsonl")
    isolated = simulate_system(path, output=tmp_path / "isolated.csv", events=tmp_path / "isolated.jsonl", isolate=True)
    assert isolated.stats.loop == "C"  # no C functions in this process: the engine calls adapters
    assert (tmp_path / "isolated.csv").read_bytes() == (tmp_path / "here.csv").read_bytes()
    assert (tmp_path / "isolated.jsonl").read_bytes() == (tmp_path / "here.jsonl").read_bytes()
    for field in ("steps", "event_iterations", "instants", "early_returns", "rollbacks", "terminated_by"):
        assert getattr(isolated.stats, field) == getattr(here.stats, field), field


def test_one_instance_may_be_isolated_and_its_trace_and_errors_come_back(write_system):
    path = write_system('[experiment]\nstop = 1.0\nstep = 0.1\n[instances.f]\nfmu = "{failer}"\nisolate = true\n'
                        '[instances.t]\nfmu = "{trivial}"\n')
    lines = []
    with pytest.raises(RunError) as failure:
        simulate_system(path, trace=lines.append)
    d = failure.value.diagnostics[0]
    assert d.message == "instance 'f': fmi3DoStep returned fmi3Error at t=0.5; the results recorded so far are kept"
    assert [n.message for n in d.notes] == ["the FMU logged: fmi3DoStep: the model failed"]
    steps = [line for line in lines if line.startswith("fmi3DoStep(")]
    assert steps[-2:] == ["fmi3DoStep(t, 0.4, 0.09999999999999998) -> fmi3OK",  # in this process
                          "fmi3DoStep(f, 0.5, 0.10000000000000009) -> fmi3Error"]  # traced in the worker


def test_a_proxy_refuses_calls_after_its_worker_stopped(fmus, tmp_path):
    from robogen.cosim.assemble import FmuCache
    from robogen.cosim.fmi3 import FMUCrashed

    cache = FmuCache()
    try:
        folder, md = cache.load(fmus["trivial"], None)
        proxy = cache.bind(folder, md, None, "t", None, None, isolate=True)
        proxy.close()
        with pytest.raises(FMUCrashed) as crash:
            proxy.fmi3DoStep(0.0, 0.1)
        assert isinstance(crash.value, FMI3Error) and crash.value.how == "it was stopped earlier"
    finally:
        cache.close()
