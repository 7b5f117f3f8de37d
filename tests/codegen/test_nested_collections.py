"""Collections of collections through the FMU and the reference interpreter, with hand-calculated
results: tests/codegen/models/nesting.rct at one capacity per nesting level (6, 3, 2). The FMI
layout of a nested value (robogen.ir.layout): a collection's ``size`` and, under ``elements``,
its elements' variables with one more array dimension of the collection's capacity."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path
from xml.etree import ElementTree

import pytest

from support.codegen_driver import Instant, Scenario, Tick, build, run_checked
from support.codegen_models import MODELS
from robogen import toolchain
from robogen.codegen import binary
from robogen.fmu.headers import PLATFORM_TUPLE
from robogen.ir.lower import LoweringOptions

CAPACITIES = (6, 3, 2)


@pytest.fixture(scope="module")
def nesting(tmp_path_factory):
    work = tmp_path_factory.mktemp("nesting")
    return build([MODELS / "nesting.rct"], work, options=LoweringOptions(capacity=6, capacities=CAPACITIES))


def _run(built, ticks: list[Tick]):
    """One tick per instant (each with a tock); the FMU's trace, checked against the interpreter's."""
    got = run_checked(built, Scenario([Instant(True, early=(t,)) for t in ticks], half=False))
    assert got.error is None, got.error
    return got


def _outputs(trace, clock: str) -> list[dict]:
    return [s.outputs[clock] for s in trace.steps if clock in s.outputs]


def _pad(values: list, n: int, zero=0) -> list:
    return values + [zero] * (n - len(values))


# c = < <<1, 2>, <3>>, <<>, <4, 5>>, <<6>> >: three layers of at most 3 sequences of at most 2
CUBE = {
    "cube.value.size": 3,
    "cube.value.elements.size": _pad([2, 2, 1], 6),
    "cube.value.elements.elements.size": _pad([2, 1, 0, 0, 2, 0, 1, 0, 0], 18),
    # 99: past the size of <3> (ignored); row-major [layer][sequence][number]
    "cube.value.elements.elements.elements": _pad([1, 2, 3, 99, 0, 0, 0, 0, 4, 5, 0, 0, 6], 36),
}


def test_a_three_level_sequence_is_three_dimensional_fmi_arrays_with_a_size_array_per_level(nesting):
    root = ElementTree.parse(nesting.folder / "modelDescription.xml").getroot()
    dims = {v.get("name"): [int(d.get("start")) for d in v.iter("Dimension")] for v in root.iter()
            if v.get("name", "").startswith("cube.value")}
    assert dims == {"cube.value.elements.elements.elements": [6, 3, 2], "cube.value.elements.elements.size": [6, 3],
                    "cube.value.elements.size": [6], "cube.value.size": []}
    assert {v.tag for v in root.iter() if v.get("name") == "cube.value.elements.elements.elements"} == {"Int64"}


def test_a_three_level_sequence_goes_in_and_out(nesting):
    got = _run(nesting, [Tick("cube", CUBE), Tick("cube", {
        "cube.value.size": 1, "cube.value.elements.size": _pad([2], 6),
        "cube.value.elements.elements.size": _pad([1, 2], 18), "cube.value.elements.elements.elements": _pad([7, 0, 8, 9], 36)})])
    flat, shape, every = _outputs(got, "flat"), _outputs(got, "shape"), _outputs(got, "every")
    # three layers: the first layer flattened, <1, 2, 3>; one layer <<7>, <8, 9>>: all of it, <7, 8, 9>
    assert [(f["flat.value.size"], f["flat.value.elements"]) for f in flat] == [(3, _pad([1, 2, 3], 6)), (3, _pad([7, 8, 9], 6))]
    # tail(c) ^ <head(c)> = < <<>, <4, 5>>, <<6>>, <<1, 2>, <3>> >
    assert shape[0] == {"shape.value.size": 3, "shape.value.elements.size": _pad([2, 1, 2], 6),
                        "shape.value.elements.elements.size": _pad([0, 2, 0, 1, 0, 0, 2, 1, 0], 18),
                        "shape.value.elements.elements.elements": _pad([0, 0, 4, 5, 0, 0, 6, 0, 0, 0, 0, 0, 1, 2, 3], 36)}
    assert [e["every.value"] for e in every] == [True, True]
    # the machine variable as a local: the same layout (after the second input)
    v = got.steps[-1].variables
    assert v["Shapes.c.size"] == 1 and v["Shapes.c.elements.size"] == _pad([2], 6)
    assert v["Shapes.c.elements.elements.elements"] == _pad([7, 0, 8, 9], 36)


def _words(words: list[list[int]], sizes: list[int] | None = None) -> dict:
    elements = []
    for w in words:
        elements += _pad(w[:3], 3)
    return {"words.value.size": len(words), "words.value.elements.size": _pad(sizes or [len(w) for w in words], 6),
            "words.value.elements.elements": _pad(elements, 18)}


def test_a_set_of_sequences_is_in_lexicographic_order_whatever_order_the_importer_gives(nesting):
    # {<2, 1>, <1>, <>, <1>} is {<>, <1>, <2, 1>}: a sequence comes after the ones it extends; the
    # second: a size of 5 for an inner sequence is its capacity, 3
    got = _run(nesting, [Tick("words", _words([[2, 1], [1], [], [1]])),
                         Tick("words", _words([[2, 3, 1], [1, 2], [2], [2, 9]], sizes=[5, 2, 1, 2]))])
    sorted_ = _outputs(got, "sorted")
    assert sorted_[0] == {"sorted.value.size": 3, "sorted.value.elements.size": _pad([0, 1, 2], 6),
                          "sorted.value.elements.elements": _pad([0, 0, 0, 1, 0, 0, 2, 1], 18)}
    # four words: no <1> added; <1, 2> < <2> < <2, 3, 1> < <2, 9>
    assert sorted_[1] == {"sorted.value.size": 4, "sorted.value.elements.size": _pad([2, 1, 3, 2], 6),
                          "sorted.value.elements.elements": _pad([1, 2, 0, 2, 0, 0, 2, 3, 1, 2, 9], 18)}
    # the numbers in every word: none (<> is one), then {2}; exactly one empty word, then none
    assert [(c["common.value.size"], c["common.value.elements"][:1]) for c in _outputs(got, "common")] == [(0, [0]), (1, [2])]
    assert [s["some.value"] for s in _outputs(got, "some")] == [True, False]


def _frames(frames: list[tuple[list[tuple[int, int, int]], str, tuple[float, float]]]) -> dict:
    payload: dict = {"frames.value.size": len(frames), "frames.value.elements.img.size": _pad([len(f[0]) for f in frames], 6),
                     "frames.value.elements.name": _pad([f[1] for f in frames], 6, ""),
                     "frames.value.elements.v": _pad([x for f in frames for x in f[2]], 12, 0.0)}
    for k in (1, 2, 3):
        column = []
        for img, _, _ in frames:
            column += _pad([p[k - 1] for p in img], 3)
        payload[f"frames.value.elements.img.elements._{k}"] = _pad(column, 18)
    return payload


def test_frames_hold_images_as_sequences_of_triples_a_name_and_a_vector(nesting):
    cam = ([(1, 2, 3), (0, 0, 1)], "cam", (0.5, 1.0))
    got = _run(nesting, [Tick("frames", _frames([cam, ([(1, 2, 3)], "", (-1.0, 2.0))]))])
    # two distinct pixels; the named frame's brightnesses 1 + 2 + 3 and 0 + 0 + 1
    assert _outputs(got, "pixels") == [{"pixels.value": 2}]
    assert _outputs(got, "bright") == [{"bright.value.elements": _pad([1, 6], 6), "bright.value.size": 2}]
    # the frame whose vector starts with a number not negative, its image in its own order
    (kept,) = _outputs(got, "kept")
    assert kept == {"kept.value.size": 1, "kept.value.elements.img.size": _pad([2], 6),
                    "kept.value.elements.img.elements._1": _pad([1], 18), "kept.value.elements.img.elements._2": _pad([2], 18),
                    "kept.value.elements.img.elements._3": _pad([3, 1], 18), "kept.value.elements.name": _pad(["cam"], 6, ""),
                    "kept.value.elements.v": _pad([0.5, 1.0], 12, 0.0)}


def test_strings_in_a_set_are_in_the_order_of_their_text(nesting):
    names = {"names.value.size": 4, "names.value.elements": _pad(["b", "Z", "\u00e9", "b"], 6, "")}
    got = _run(nesting, [Tick("names", names)])
    # byte by byte in UTF-8: Z (0x5a) < b (0x62) < m (0x6d) < é (0xc3 0xa9)
    assert _outputs(got, "known") == [{"known.value.elements": _pad(["Z", "b", "m", "\u00e9"], 6, ""), "known.value.size": 4}]


def test_enumerations_with_arguments_in_a_set_take_the_arguments_of_their_own_literal(nesting):
    # Turn(2, true), Stop (with a Move argument the importer left at 7.0: not Stop's), Move(1.5), Stop
    cmds = {"cmds.value.size": 4, "cmds.value.elements.tag": _pad([2, 0, 1, 0], 6),
            "cmds.value.elements.Move_1": _pad([0.0, 7.0, 1.5, 0.0], 6, 0.0),
            "cmds.value.elements.Turn_1": _pad([2], 6), "cmds.value.elements.Turn_2": _pad([True], 6, False)}
    only_stop = {"cmds.value.size": 1, "cmds.value.elements.tag": _pad([0], 6)}
    got = _run(nesting, [Tick("cmds", cmds), Tick("cmds", only_stop)])
    assert [m["moving.value"] for m in _outputs(got, "moving")] == [True, False]
    # after the first: {Stop, Move(1.5), Turn(2, true)}, in the order of the literals
    first = next(s for s in got.steps if "moving" in s.outputs).variables
    assert first["Shapes.cs.size"] == 3
    assert first["Shapes.cs.elements.tag"] == _pad([0, 1, 2], 6)
    assert first["Shapes.cs.elements.Move_1"] == _pad([0.0, 1.5], 6, 0.0)
    assert first["Shapes.cs.elements.Turn_1"] == _pad([0, 0, 2], 6)


def test_iter_composes_a_relation_with_itself(nesting):
    # r = {1 -> 2, 2 -> 3, 3 -> 1}: r^1 = r, r^2 = {1 -> 3, 2 -> 1, 3 -> 2}, r^-1 = rinv(r) = r^2,
    # r^3 the identity on {1, 2, 3}; 0 is left out by the model's guard (steps!{})
    got = _run(nesting, [Tick("power", {"power.value": n}) for n in (1, 2, -1, 3, 0)])
    pairs = [list(zip(s["steps.value.elements._1"][:s["steps.value.size"]], s["steps.value.elements._2"]))
             for s in _outputs(got, "steps")]
    assert pairs == [[(1, 2), (2, 3), (3, 1)], [(1, 3), (2, 1), (3, 2)], [(1, 3), (2, 1), (3, 2)],
                     [(1, 1), (2, 2), (3, 3)], []]


SANITIZED_DRIVER = """
import random, sys
from pathlib import Path
from support.codegen_driver import FmuRunner, random_scenario
from support.codegen_models import NESTING
runner = FmuRunner(Path(sys.argv[1]))
rng = random.Random(5)
steps = 0
for n in range(30):
    # the test model's choices (sizes mostly within the capacities), then any value (sizes up to 2^64 - 1)
    steps += len(runner.run(random_scenario(rng, runner.desc, 20, choices=NESTING if n % 2 else None)).steps)
runner.close()
print("ok", steps)
"""


@pytest.mark.slow
def test_the_loops_of_every_nesting_level_run_clean_under_the_sanitizers(nesting, tmp_path):
    """The C that reads and writes nested values, their views and the quantifiers' loops, under
    AddressSanitizer and UndefinedBehaviorSanitizer, driven by random inputs in a process of its own."""
    found = subprocess.run([*toolchain.compiler(), "-print-file-name=libasan.so"], capture_output=True, text=True).stdout.strip()
    if not (os.path.isabs(found) and os.path.exists(found)):
        pytest.skip("no AddressSanitizer runtime for this compiler")
    folder = tmp_path / "sanitized"
    shutil.copytree(nesting.folder, folder)
    ident = nesting.fmu.model_identifier
    binary.compile_fmu_binary(folder / "sources", ident, folder / "binaries" / PLATFORM_TUPLE / f"{ident}.so", sanitize=True)
    env = {**os.environ, "LD_PRELOAD": found, "ASAN_OPTIONS": "detect_leaks=0:halt_on_error=1", "PYTHONMALLOC": "malloc",
           "UBSAN_OPTIONS": "halt_on_error=1:print_stacktrace=1", "PYTHONPATH": str(Path(__file__).resolve().parent.parent)}
    proc = subprocess.run([sys.executable, "-c", SANITIZED_DRIVER, str(folder)], capture_output=True, text=True, timeout=900,
                          env=env)
    assert proc.returncode == 0, proc.stderr[-4000:]
    assert proc.stdout.startswith("ok ") and int(proc.stdout.split()[1]) > 0
    assert "runtime error" not in proc.stderr and "AddressSanitizer" not in proc.stderr
