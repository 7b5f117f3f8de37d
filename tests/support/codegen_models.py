"""The code generator's test models and how the tests drive them (imported by name: the
conftest modules of several test folders cannot be imported by name in one session)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

HERE = Path(__file__).resolve().parent.parent / "codegen"  # the code generator's tests and their models
ROOT = HERE.parent.parent
MODELS = HERE / "models"
UR5E = ROOT / "models" / "ur5e" / "ur5e.rst"


@dataclass(frozen=True)
class ModelCase:
    name: str
    path: Path
    max_steps: int = 1000
    capacity: int = 32  # of sets and sequences (--capacity)
    capacities: tuple[int, ...] = ()  # one per nesting level, outermost first (--capacity 4,3,2)
    settings: dict[str, str] = field(default_factory=dict)  # constants without a value (--set)
    # payload choices for the random scenarios (FMI name -> values), to keep run-time errors rare
    choices: dict[str, list] = field(default_factory=dict)


NONZERO = [-7, -3, -2, -1, 1, 2, 3, 5, 9]
# nesting.rct (capacities 6, 3, 2): small sizes, so that flattening rarely overflows, now and then
# one beyond the capacity (clipped); few distinct texts (the FMU keeps at most 6 of the importer's)
_SIZES = [0, 1, 1, 2, 2, 1, 0, 9]
NESTING = {
    **{f"{p}.size": _SIZES for p in ("cube.value", "cube.value.elements", "cube.value.elements.elements", "words.value",
                                      "words.value.elements", "frames.value", "frames.value.elements.img", "names.value",
                                      "cmds.value")},
    "cube.value.elements.elements.elements": [-1, 0, 1, 2, 7], "words.value.elements.elements": [0, 1, 2, 3],
    "frames.value.elements.name": ["", "a", "cam"], "frames.value.elements.v": [-1.0, 0.0, 0.5],
    "frames.value.elements.img.elements._1": [0, 1, 2], "frames.value.elements.img.elements._2": [0, 3],
    "frames.value.elements.img.elements._3": [1, 2], "names.value.elements": ["a", "b", "m"],
    "cmds.value.elements.tag": [0, 1, 2], "cmds.value.elements.Move_1": [1.5, 0.0],
    "cmds.value.elements.Turn_1": [0, 2], "power.value": [-4, -3, -1, 0, 1, 2, 3, 5, 6],
}

TEST_MODELS = {
    m.name: m
    for m in (
        ModelCase("ur5e", UR5E),
        ModelCase("composite", MODELS / "composite.rst"),
        ModelCase("data", MODELS / "data.rst", choices={
            "divisor.value": NONZERO * 4 + [0],
            "pick.value": [1, 2, 3, 1, 2, 3, 1, 2, 3, 0, 7, 4],
        }),
        ModelCase("ops", MODELS / "ops.rst"),
        ModelCase("pipeline", MODELS / "pipeline.rst"),
        ModelCase("arith", MODELS / "arith.rst", max_steps=40, choices={
            "b.value": NONZERO * 3 + [0, 2**63 - 1, -(2**63)],
            "n.value": [0, 1, 2, 3, 4, 5, 6, 2**64 - 1, 7, 7],
            "x.value": [-2.5, -1.0, -0.5, 0.0, 0.25, 0.5, 1.0, 1.5, 3.0] * 2 + [1e19],
        }),
        ModelCase("beacon", MODELS / "beacon.rst", settings={"step": "0.25"}),
        ModelCase("timers", MODELS / "timers.rct"),
        ModelCase("inputs", MODELS / "inputs.rct"),
        ModelCase("binding", MODELS / "binding.rct"),
        ModelCase("relay", MODELS / "relay.rct"),
        ModelCase("nested", MODELS / "nested.rct"),
        ModelCase("functions", MODELS / "functions.rct", choices={
            "set.value": [0, 1, 2, 3], "use.value": [0, 1, 2, 3, 4, 2**63],
        }),
        ModelCase("collections", MODELS / "collections.rct", capacity=5, choices={
            "add.value": [-1, 0, 1, 2, 3, 4, 5],
            "drop.value": [0, 1, 2, 3, 4, 5, -1, 9, 9, 9],
            "pick.value": [0] + [1, 2, 3, 4, 5, 9] * 6,
            "load.value.elements": [-1, 0, 1, 2, 3, 3, 3, 9],
            "load.value.size": [0, 1, 2, 3, 5, 6, 2**64 - 1],
        }),
        ModelCase("ur5e_rct", ROOT / "models" / "ur5e" / "ur5e.rct"),
        ModelCase("gripper", MODELS / "gripper.rst"),
        ModelCase("twins", MODELS / "twins.rct"),
        ModelCase("clashes", MODELS / "clashes.rct"),
        ModelCase("opconsts", MODELS / "opconsts.rct"),
        ModelCase("linear", MODELS / "linear.rst", choices={"y.value": [-2.5, -1.0, 0.5, 1.5, 3.0, 1e300, 0.0]}),
        ModelCase("control", MODELS / "control.rct", choices={"value.value": [-5, 0, 2, 3, 4, 5, 7, 99, 100, 150]}),
        ModelCase("matrixport", MODELS / "matrixport.rst"),
        ModelCase("taggedsim", MODELS / "taggedsim.rst", choices={
            "cmd.tag": [0, 1, 2], "cmd.Move_1": [1.5, 2.5, 0.0], "cmd.Turn_1": [2, 0, 2], "cmd.Turn_2": [True, False],
        }),
        ModelCase("records", MODELS / "records.rct", capacity=4, choices={
            "gas.value.size": [0, 1, 2, 3, 4, 5], "seen.value.size": [0, 1, 2, 3, 4, 9],
            "gas.value.elements.i": [0, 1, 2, 7], "seen.value.elements.i": [0, 1, 1, 2],
            "seen.value.elements.at.x": [0.0, 0.5, 0.5], "seen.value.elements.at.y": [0.0, -1.0],
        }),
        ModelCase("nesting", MODELS / "nesting.rct", capacity=6, capacities=(6, 3, 2), choices=NESTING),
        ModelCase("strings", MODELS / "strings.rct", choices={"name.value": ["hello", "bye", "", "bob", "amy", "\u00e9lan"]}),
        ModelCase("fmaps", MODELS / "fmaps.rct", choices={
            # 1 is never dropped: asking for it never leaves the domain (test_function_maps.py does)
            "ask.value": [1], "put.value": [1, 2, 3, 4], "drop.value": [2, 3, 5], "bump.value": [0, 1, 2],
            "turn.value": [0, 3],
        }),
        ModelCase("typeuses", MODELS / "typeuses.rct"),
        ModelCase("abstract", MODELS / "abstract.rct"),
        ModelCase("abstractsim", MODELS / "abstractsim.rst"),
        ModelCase("senders", MODELS / "senders.rct"),
        ModelCase("widen", MODELS / "widen.rct", choices={"r.value": [-2.75, 0.5, 2.75, 1e10]}),
        ModelCase("typeusessim", MODELS / "typeusessim.rst"),
        ModelCase("tagged", MODELS / "tagged.rct", choices={
            "cmd.tag": [0, 1, 2], "cmd.Move_1": [1.5, 2.5, 0.0], "cmd.Turn_1": [2, 0, 2], "cmd.Turn_2": [True, False],
        }),
    )
}
OWN_MODELS = [n for n in TEST_MODELS if n != "ur5e"]
SEMANTICS = ("exhaustive", "stepwise")
