"""Build robogen's own test FMUs (C, written in this repository) into a folder.

Each model is one C file here plus a variable list below; the modelDescription.xml is written
from that list, and the instantiation token is passed to the compiler, so the two cannot
disagree on it. Used by tests/cosim/conftest.py, tests/fmu/ and bench/bench_master.py.

    python tests/cosim/fmus/build.py OUTDIR [MODEL ...]
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path
from xml.sax.saxutils import quoteattr

HERE = Path(__file__).resolve().parent

# name, vr, type, causality, variability, extra attributes
V = tuple
MODELS: dict[str, dict] = {
    "ball": dict(
        early=True, state=True,
        vars=[
            V(("h", 1, "Float64", "output", "continuous", {})),
            V(("v", 2, "Float64", "output", "continuous", {})),
            V(("bounces", 3, "Int64", "output", "discrete", {})),
            V(("h0", 4, "Float64", "parameter", "fixed", {"start": "1.0"})),
            V(("e", 5, "Float64", "parameter", "fixed", {"start": "0.7"})),
        ]),
    "stair": dict(
        early=True,
        vars=[
            V(("counter", 1, "Int64", "output", "discrete", {})),
            V(("period", 2, "Float64", "parameter", "fixed", {"start": "1.0"})),
            V(("last", 3, "Int64", "parameter", "fixed", {"start": "0"})),
        ]),
    "ticker": dict(
        vars=[
            V(("tick", 1, "Clock", "input", "discrete", {"intervalVariability": "constant", "intervalDecimal": "0.25", "shiftDecimal": "0"})),
            V(("out", 2, "Clock", "output", "discrete", {"intervalVariability": "triggered"})),
            V(("count", 3, "Int64", "output", "discrete", {"clocks": "2"})),
            V(("ticks", 4, "Int64", "output", "discrete", {})),
            V(("phase", 5, "Float64", "output", "continuous", {})),
        ],
        deps={2: "1", 3: "2"}),
    "relay": dict(
        vars=[
            V(("u", 1, "Clock", "input", "discrete", {"intervalVariability": "triggered"})),
            V(("x_in", 2, "Int64", "input", "discrete", {"clocks": "1", "start": "0"})),
            V(("y", 3, "Clock", "output", "discrete", {"intervalVariability": "triggered"})),
            V(("x_out", 4, "Int64", "output", "discrete", {"clocks": "3"})),
            V(("stepwise", 5, "Boolean", "parameter", "fixed", {"start": "false"})),
            V(("n", 6, "Int64", "output", "discrete", {})),
        ],
        deps={3: "1", 4: "3"}),
    "zeno": dict(
        early=True,
        vars=[
            V(("z", 1, "Clock", "output", "discrete", {"intervalVariability": "triggered"})),
            V(("start", 2, "Float64", "parameter", "fixed", {"start": "0.5"})),
            V(("k", 3, "Int64", "output", "discrete", {})),
        ],
        deps={1: ""}),
    "failer": dict(
        vars=[
            V(("y", 1, "Float64", "output", "continuous", {})),
            V(("fail_time", 2, "Float64", "parameter", "fixed", {"start": "0.5"})),
        ]),
    "trivial": dict(
        vars=[
            V(("u", 1, "Float64", "input", "continuous", {"start": "0"})),
            V(("y", 2, "Float64", "output", "continuous", {})),
            V(("stop_at", 3, "Float64", "parameter", "fixed", {"start": "0"})),
        ]),
}


def token(name: str) -> str:
    return "{robogen-test-" + name + "}"


def model_description(name: str, spec: dict) -> str:
    early = "true" if spec.get("early") else "false"
    state = "true" if spec.get("state") else "false"
    lines = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<fmiModelDescription fmiVersion="3.0" modelName="{name}" instantiationToken="{token(name)}">',
        f'  <CoSimulation modelIdentifier="{name}" hasEventMode="true" canHandleVariableCommunicationStepSize="true"'
        f' mightReturnEarlyFromDoStep="{early}" canGetAndSetFMUState="{state}"/>',
        "  <ModelVariables>",
        '    <Float64 name="time" valueReference="0" causality="independent" variability="continuous"/>',
    ]
    for vname, vr, typ, causality, variability, extra in spec["vars"]:
        attrs = f'name="{vname}" valueReference="{vr}" causality="{causality}" variability="{variability}"'
        attrs += "".join(f" {k}={quoteattr(v)}" for k, v in extra.items())
        lines.append(f"    <{typ} {attrs}/>")
    lines += ["  </ModelVariables>", "  <ModelStructure>"]
    deps = spec.get("deps", {})
    outputs = [v for v in spec["vars"] if v[3] == "output"]
    for vname, vr, *_ in outputs:
        d = f' dependencies="{deps[vr]}"' if vr in deps else ""
        lines.append(f'    <Output valueReference="{vr}"{d}/>')
    for vname, vr, typ, causality, variability, extra in outputs:
        if "clocks" not in extra:
            d = f' dependencies="{deps[vr]}"' if vr in deps else ""
            lines.append(f'    <InitialUnknown valueReference="{vr}"{d}/>')
    lines += ["  </ModelStructure>", "</fmiModelDescription>", ""]
    return "\n".join(lines)


def build(name: str, outdir: Path, *, xml: str | None = None) -> Path:
    """Compile MODELS[name] and write OUTDIR/NAME.fmu (``xml`` overrides the model description)."""
    from robogen import toolchain
    from robogen.fmu.archive import write_fmu
    from robogen.fmu.headers import include_dir

    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        so = Path(tmp) / f"{name}.so"
        toolchain.compile_shared([HERE / f"{name}.c"], so, includes=[include_dir(), HERE],
                                 defines=[f'MODEL_TOKEN="{token(name)}"'], what=f"test FMU {name}")
        return write_fmu(outdir / f"{name}.fmu", {
            "modelDescription.xml": xml if xml is not None else model_description(name, MODELS[name]),
            f"binaries/x86_64-linux/{name}.so": so.read_bytes(),
            f"sources/{name}.c": (HERE / f"{name}.c").read_bytes(),
            "documentation/externalDependencies.txt": "none beyond libc and libm\n",
        })


def build_all(outdir: Path, names=None) -> dict[str, Path]:
    return {n: build(n, outdir) for n in (names or MODELS)}


if __name__ == "__main__":
    out = Path(sys.argv[1])
    for n, p in build_all(out, sys.argv[2:] or None).items():
        print(p)
