"""What the master reads and sets in an event iteration: one Get or Set call per FMU and type for
the values a clock carries, and no second read of a clocked output within an instant unless a
call since could have changed it (FMI 3.0: a Set or SetClock of a known it depends on, per
its <Output dependencies>, or fmi3UpdateDiscreteStates)."""

from __future__ import annotations

from pathlib import Path

from robogen.cosim import simulate_system
from robogen.cosim.fmi3 import CallNotes
from robogen.cosim.instances import FmuInstance
from robogen.diagnostics import Span
from robogen.fmu.modeldesc import CoSimulation, ModelDescription, Unknown, Variable


def _calls(path: Path) -> list[str]:
    lines: list[str] = []
    simulate_system(path, trace=lines.append)
    return lines


def test_a_forwarded_clocked_output_is_read_once_per_instant(write_system):
    # ticker.out ticks at 0, 0.25 and 0.5; r1 forwards it to r2 with x_out, which is also recorded.
    path = write_system("""
connections = ["ticker.out -> r1.u", "ticker.count -> r1.x_in", "r1.y -> r2.u", "r1.x_out -> r2.x_in"]
[experiment]
stop = 0.5
step = 0.5
[instances.ticker]
fmu = "{ticker}"
[instances.r1]
fmu = "{relay}"
[instances.r2]
fmu = "{relay}"
[record]
variables = ["r1.x_out", "r2.x_out"]
""")
    lines = _calls(path)
    # r1's only Int64 read is x_out (its n is neither recorded nor connected): read to forward it
    # to r2, then recorded from that read, as nothing set r1's inputs in between.
    assert sum(line.startswith("fmi3GetInt64(r1,") for line in lines) == 3
    # The two values r1 forwards go to r2 in one SetInt64 each instant: x_in (r2's only Int64 input).
    assert sum(line.startswith("fmi3SetInt64(r2,") for line in lines) == 3
    result = simulate_system(path)
    ticks = [row for row in result.rows if row[3] is not None]
    assert [(t, k, a, b) for t, k, a, b in ticks] == [(0.0, 0, 2, 3), (0.25, 0, 3, 4), (0.5, 0, 4, 5)]


class _Binding:
    """Records the Get calls; holds the values an FMU would return."""

    def __init__(self, values: dict[int, int]):
        self.values, self.gets, self.notes = values, [], CallNotes()

    def raw(self, function):
        return None

    def note_code(self, function):
        return 0

    def get_values(self, fmi_type, vrs):
        self.gets.append(list(vrs))
        return [self.values[vr] for vr in vrs]

    def set_values(self, fmi_type, vrs, values):
        pass

    def fmi3SetClock(self, vrs, n, values):
        pass

    def fmi3GetClock(self, vrs, n, values):
        self.gets.append(["clocks", *vrs[0:n]])
        for i in range(n):
            values[i] = self.values[vrs[i]]


def _instance() -> tuple[FmuInstance, _Binding]:
    """Input clocks a (1), b (2); output clock y (3) clocking o_a (4, depends on a), o_none (5,
    depends on nothing) and o_all (6, no dependencies attribute: on everything); an input p (7)."""
    clocks = [Variable(n, vr, "Clock", c, "discrete", interval_variability="triggered")
              for n, vr, c in (("a", 1, "input"), ("b", 2, "input"), ("y", 3, "output"))]
    outputs = [Variable(n, vr, "Int64", "output", "discrete", clocks=(3,)) for n, vr in (("o_a", 4), ("o_none", 5), ("o_all", 6))]
    outputs.append(Variable("p", 7, "Int64", "input", "discrete", start=("0",)))
    unknowns = (Unknown("Output", 3, (1, 2)), Unknown("Output", 4, (1,)), Unknown("Output", 5, ()), Unknown("Output", 6, None))
    md = ModelDescription("m", "{token}", CoSimulation("m", has_event_mode=True), tuple(clocks + outputs), unknowns)
    binding = _Binding({4: 40, 5: 50, 6: 60})
    return FmuInstance("m", md, Path("."), binding, Span.point("system.toml", 1)), binding


def test_a_clocked_output_is_read_again_only_after_a_set_it_depends_on():
    u, binding = _instance()
    o_a, o_none, o_all = (u.vars[n] for n in ("o_a", "o_none", "o_all"))
    assert u.clocked_values([o_a, o_none, o_all]) == [40, 50, 60]
    assert binding.gets == [[4, 5, 6]]  # one Get call for the three (one type)
    assert u.clocked_values([o_all, o_a]) == [60, 40]
    assert binding.gets == [[4, 5, 6]]  # nothing set since: not read again
    binding.values.update({4: 41, 6: 61})
    u.set_clocks([2])  # b: o_a does not depend on it, o_all (no dependencies given) may
    assert u.clocked_values([o_a, o_none, o_all]) == [40, 50, 61]
    assert binding.gets[1:] == [[6]]
    u.set_clocks([1])  # a: o_a and o_all may have changed, o_none cannot
    assert u.clocked_values([o_a, o_none, o_all]) == [41, 50, 61]
    assert binding.gets[2:] == [[4, 6]]
    binding.values[5] = 51
    u.new_instant()  # after fmi3UpdateDiscreteStates every output may have changed
    assert u.clocked_values([o_none]) == [51]
    assert binding.gets[3:] == [[5]]


def test_an_output_clock_is_read_again_only_after_a_set_it_depends_on():
    u, binding = _instance()
    binding.values[3] = False
    u.watch_clocks([3])  # y depends on the input clocks a and b
    assert u.read_clocks() == [] and u.read_clocks() == []
    assert binding.gets == [["clocks", 3]]
    binding.values[3] = True
    u.set_values("Int64", [7], [0])  # p: not an input y depends on
    assert u.read_clocks() == [] and len(binding.gets) == 1
    u.set_clocks([2])
    assert u.read_clocks() == [3]
    assert binding.gets == [["clocks", 3], ["clocks", 3]]
    u.new_instant()
    assert u.read_clocks() == [3] and len(binding.gets) == 3
