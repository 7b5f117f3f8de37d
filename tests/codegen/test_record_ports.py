"""Sets and sequences of records at the FMU boundary (tests/codegen/models/records.rct, capacity
4): one FMI array per scalar field of the records, nested records included, and the size; the
FMU and the reference interpreter give the same trace, and the values are the hand-calculated
ones. (The 200 random scenarios per semantics are in test_differential.py.)"""

from __future__ import annotations

import pytest

from support.codegen_driver import FmuRunner, Instant, Scenario, Tick, build, interpret
from support.codegen_models import MODELS
from robogen.ir.lower import LoweringOptions

CO2, NH3 = 0, 1  # the items of the FMI EnumerationType records.Chem, in the order written


def _readings(name: str, rows: list[tuple[int, int, float, float]], size: int | None = None) -> dict[str, object]:
    """The payload of an event carrying readings: each field's array, padded to the capacity."""
    pad = rows + [(0, 0, 0.0, 0.0)] * (4 - len(rows))
    return {f"{name}.value.elements.c": [r[0] for r in pad], f"{name}.value.elements.i": [r[1] for r in pad],
            f"{name}.value.elements.at.x": [r[2] for r in pad], f"{name}.value.elements.at.y": [r[3] for r in pad],
            f"{name}.value.size": len(rows) if size is None else size}


def _outputs(trace, clock: str) -> list[dict[str, object]]:
    return [s.outputs[clock] for s in trace.steps if clock in s.outputs]


@pytest.fixture(scope="module")
def records(tmp_path_factory):
    built = build([MODELS / "records.rct"], tmp_path_factory.mktemp("records"), options=LoweringOptions(capacity=4))
    runner = FmuRunner(built.folder)
    yield built, runner
    runner.close()


def _run(records, ticks: list[Tick]):
    built, runner = records
    scenario = Scenario([Instant(True)] + [Instant(True, early=(t,)) for t in ticks], half=False)
    got = runner.run(scenario)
    assert got.comparable() == interpret(built.fmu, scenario, runner.desc).comparable()
    return got


def test_a_sequence_of_records_arrives_field_by_field_and_leaves_reversed(records):
    rows = [(NH3, 5, 1.0, 2.0), (CO2, 7, 0.5, -1.0), (CO2, 2, 3.0, 3.0)]
    got = _run(records, [Tick("gas", _readings("gas", rows))])
    assert [o["strongest.value"] for o in _outputs(got, "strongest")] == [5]  # gs[1].i
    (kept,) = _outputs(got, "kept")
    assert kept == _readings("kept", list(reversed(rows)))  # zeros after the third element


def test_a_size_beyond_the_capacity_takes_the_whole_array_and_an_empty_sequence_none(records):
    rows = [(CO2, 1, 0.0, 0.0), (NH3, 2, 0.0, 0.0), (CO2, 3, 0.0, 0.0), (NH3, 4, 0.25, 0.0)]
    got = _run(records, [Tick("gas", _readings("gas", rows, size=9)), Tick("gas", _readings("gas", rows, size=0))])
    assert [o["strongest.value"] for o in _outputs(got, "strongest")] == [1, 0]
    assert [o["kept.value.size"] for o in _outputs(got, "kept")] == [4, 0]
    assert _outputs(got, "kept")[0]["kept.value.elements.i"] == [4, 3, 2, 1]
    assert _outputs(got, "kept")[1] == _readings("kept", [])  # nothing but zeros


def test_a_set_of_records_is_taken_in_canonical_order_without_duplicates(records):
    # canonical order compares the fields in the order declared: c, then i, then at.x, at.y
    rows = [(NH3, 1, 0.0, 0.0), (CO2, 9, 1.5, 0.0), (NH3, 1, 0.0, 0.0), (CO2, 9, -1.5, 0.0)]
    got = _run(records, [Tick("seen", _readings("seen", rows))])
    assert [o["distinct.value"] for o in _outputs(got, "distinct")] == [3]
    (members,) = _outputs(got, "members")
    assert members == _readings("members", [(CO2, 9, -1.5, 0.0), (CO2, 9, 1.5, 0.0), (NH3, 1, 0.0, 0.0)])
