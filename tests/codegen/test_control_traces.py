"""tests/codegen/models/control.rct against traces written by hand from RoboChart's semantics
(docs/robosim-robochart.md §4.1, §7) and robogen's seeded generator (robogen.ir.model.Draw).

Gate takes ``value[| x > 3 |]?x`` only when the value offered exceeds 3, and then (if x < 100)
counts it (n = n + 1, through an applied lambda) and sends ``big.(x * 2 + n)`` (let) to Sink.
Sink waits ``wait([1, 3])`` time units, then its probabilistic junction sends heads (1/4) or
tails!got (3/4). Each value Gate takes also sends ``ping`` to Echo over a bidirectional
connection declared from Echo to Gate, and Echo answers ``pong`` in the same instant (it runs
after Gate). The generator is SplitMix64; its outputs from state 0 are the published test
vector 0xe220a8397b1dcdaf, 0x6e789e6aa1b965f4, 0x06c45d188009454f, 0xf88bb8a8724c81ec (state
s gives mix(s + k * 0x9E3779B97F4A7C15) for k = 1, 2, ...; mix(0) = 0). A wait draws
1 + x mod 3, the junction (x >> 11) / 2^53 and takes heads when that is below 0.25.
"""

from __future__ import annotations

import pytest

from support.codegen_driver import Tick, outputs_by_instant
from robogen.ir.interp import random_next

VECTOR = [0xE220A8397B1DCDAF, 0x6E789E6AA1B965F4, 0x06C45D188009454F, 0xF88BB8A8724C81EC]
GAMMA = 0x9E3779B97F4A7C15


def value(v: int) -> Tick:
    return Tick("value", {"value.value": v})


def test_the_generator_is_splitmix64():
    state, out = 0, []
    for _ in VECTOR:
        state, x = random_next(state)
        out.append(x)
    assert out == VECTOR
    assert random_next((-GAMMA) % 2**64) == (0, 0)  # mix(0) = 0: the seed one step before 0


def run(built_fmu, inputs: dict[int, Tick], instants: int, seed: int | None = None):
    """Outputs of every instant (all its super-dense steps), the FMU's trace checked equal to the
    interpreter's, with one tock per instant."""
    return outputs_by_instant(built_fmu, inputs, instants, {"random_seed": seed} if seed is not None else None)


INPUTS = {1: value(2), 2: value(5), 5: value(7)}


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_filter_let_sync_wait_and_junction_with_the_default_seed(builds, semantics):
    outputs, trace = run(builds.get("control", semantics), INPUTS, 9)
    # t=1: 2 fails the filter and waits in the buffer; t=2: 5 replaces it (one dropped event),
    # passes: n = 1, big.(10 + 1); Sink binds got = 11 and waits 1 + x1 mod 3 = 2 units
    # (x1 = 0xe220a8397b1dcdaf, x1 mod 3 = 1); t=4: the wait is over, the junction draws
    # x2 >> 11 / 2^53 = 0.4315 >= 0.25: tails!11. t=5: 7 passes, n = 2, big.16; wait
    # 1 + x3 mod 3 = 2 (x3 mod 3 = 1); t=7: x4 gives 0.9709: tails!16.
    assert outputs == {0: {}, 1: {}, 2: {"pong": {}}, 3: {}, 4: {"tails": {"tails.value": 11}}, 5: {"pong": {}}, 6: {},
                       7: {"tails": {"tails.value": 16}}, 8: {}}
    last = trace.steps[-1]
    assert last.variables["Gate.n"] == 2 and last.variables["Gate.x"] == 7 and last.variables["Sink.got"] == 16
    assert last.dropped == 1


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_another_seed_gives_another_reproducible_run(builds, semantics):
    # seed -GAMMA: the draws are mix(0) = 0, x1, x2, x3: wait 1 + 0 = 1 (t=3), 0.883: tails!11;
    # then wait 1 + x2 mod 3 = 1 (x2 mod 3 = 0) from t=5 (t=6), x3 >> 11 / 2^53 = 0.0264: heads
    seed = (-GAMMA) % 2**64
    outputs, _ = run(builds.get("control", semantics), INPUTS, 8, seed=seed)
    assert outputs == {0: {}, 1: {}, 2: {"pong": {}}, 3: {"tails": {"tails.value": 11}}, 4: {}, 5: {"pong": {}},
                       6: {"heads": {}}, 7: {}}


def test_values_the_filter_or_the_condition_refuse_are_not_taken(builds):
    # The filter reads the value offered; x is bound only when t1 is taken, so the condition
    # x < 100 reads x as it was. 3 fails x > 3 (nothing bound: x stays 0); 150 passes the filter
    # and the condition (x is still 0): t1 is taken, x = 150, n = 1; 20 passes the filter but the
    # condition reads x = 150: not taken, and x stays 150 (it is never bound to 20).
    outputs, trace = run(builds.get("control", "exhaustive"), {1: value(3), 3: value(150), 5: value(20)}, 8)
    assert all(outputs[i] == {} for i in range(3))
    xs = [s.variables["Gate.x"] for s in trace.steps]
    assert xs[:3] == [0, 0, 0] and set(xs[3:]) == {150}
    ns = [s.variables["Gate.n"] for s in trace.steps]
    assert ns[:3] == [0, 0, 0] and set(ns[3:]) == {1}


@pytest.mark.parametrize("semantics", ["exhaustive", "stepwise"])
def test_events_carry_matrices_as_fmi_arrays(builds, semantics):
    """matrixport.rst: rot carries a 2x3 matrix (an FMI array of 6, row by row); the machine
    sends its transpose (3x2) on flipped and its first row on row, in the cycle rot arrives."""
    rot = Tick("rot", {"rot.value": [1, 2, 3, 4, 5, 6]})  # [[1, 2, 3], [4, 5, 6]]
    outputs, _ = run(builds.get("matrixport", semantics), {1: rot}, 3)
    assert outputs == {0: {}, 1: {"flipped": {"flipped.value": [1, 4, 2, 5, 3, 6]}, "row": {"row.value": [1, 2, 3]}}, 2: {}}
