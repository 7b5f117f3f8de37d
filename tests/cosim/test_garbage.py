"""A co-simulation frees what it made when it ends: it leaves no reference cycles behind for
Python's cyclic collector. A full collection walks every object of the process, and it runs when
allocations trigger it: in the middle of a later run (a campaign's next run, a benchmark's next
repetition), where it cost up to 25 ms of a 0.8 s UR5e run before the bindings and the engine's
callback held their owners weakly."""

from __future__ import annotations

import collections
import gc

import pytest

from robogen.cosim import simulate_system

SYSTEMS = {
    # C FMUs: a periodic clock and its clocked outputs through a relay, recorded as CSV
    "clocks": 'connections = ["k.out -> r.u", "k.count -> r.x_in"]\n[experiment]\nstop = 1.0\nstep = 0.1\n'
              '[instances.k]\nfmu = "{ticker}"\n[instances.r]\nfmu = "{relay}"\n'
              '[record]\nvariables = ["k.out", "k.count", "r.y", "r.x_out"]\n',
    # a time event announced by nextEventTime, an early return
    "events": '[experiment]\nstop = 1.0\nstep = 0.1\n[instances.s]\nfmu = "{stair}"\nstart = { period = 0.25 }\n'
              '[instances.b]\nfmu = "{ball}"\n',
}


def cycles_left_by(run) -> collections.Counter:
    """The objects ``run()`` left in reference cycles, by type (the collector off meanwhile)."""
    gc.collect()
    gc.disable()
    flags = gc.get_debug()
    try:
        gc.set_debug(gc.DEBUG_SAVEALL)  # keep what the collection finds, to name it
        run()
        gc.collect()
        return collections.Counter(type(o).__name__ for o in gc.garbage)
    finally:
        gc.garbage.clear()
        gc.set_debug(flags)
        gc.enable()


@pytest.mark.parametrize("name", sorted(SYSTEMS))
@pytest.mark.parametrize("output", ["rows", "csv"])
def test_a_run_leaves_no_reference_cycles(write_system, tmp_path, name, output):
    path = write_system(SYSTEMS[name], name=f"{name}.toml")
    kwargs = {"output": tmp_path / "results.csv", "keep_rows": False} if output == "csv" else {}
    simulate_system(path, **kwargs)  # the first run compiles and loads what later runs reuse
    assert cycles_left_by(lambda: simulate_system(path, **kwargs)) == collections.Counter()


def test_a_python_fmus_run_leaves_no_reference_cycles(tmp_path, misbehaving):
    system = tmp_path / "system.toml"
    system.write_text(f'[experiment]\nstop = 1.0\nstep = 0.25\n[instances.p]\nfmu = "{misbehaving}"\n')
    simulate_system(system)
    assert cycles_left_by(lambda: simulate_system(system)) == collections.Counter()


def test_the_check_finds_a_cycle_when_there_is_one(write_system):
    class Node:
        pass

    def leaky():
        node = Node()
        node.me = node

    assert cycles_left_by(leaky)["Node"] == 1
