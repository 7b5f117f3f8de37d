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

from robogen.fmu.modeldesc import CoSimulation, EnumerationType, Item, ModelDescription, Unknown, Variable
from robogen.fmu.modeldesc_writer import with_content_token, write_model_description

HERE = Path(__file__).resolve().parent


def var(name: str, vr: int, type_: str, causality: str, variability: str, *, start: str | None = None,
        clock: int | None = None, declared_type: str | None = None) -> Variable:
    return Variable(name, vr, type_, causality, variability, start=() if start is None else (start,),
                    clocks=() if clock is None else (clock,), declared_type=declared_type)


def clock(name: str, vr: int, causality: str, kind: str, interval: str | None = None) -> Variable:
    """A clock; a periodic one (``interval`` given) starts at shift 0."""
    return Variable(name, vr, "Clock", causality, "discrete", interval_variability=kind, interval_decimal=interval,
                    shift_decimal=None if interval is None else "0")


#: The value types of the all-types FMU, in the order of alltypes.c's groups: (suffix, FMI type).
ALL_TYPES = (("f32", "Float32"), ("f64", "Float64"), ("i8", "Int8"), ("u8", "UInt8"), ("i16", "Int16"),
             ("u16", "UInt16"), ("i32", "Int32"), ("u32", "UInt32"), ("i64", "Int64"), ("u64", "UInt64"),
             ("b", "Boolean"), ("s", "String"), ("bin", "Binary"), ("e", "Enumeration"))
LEVEL = EnumerationType("Level", (Item("low", 1), Item("mid", 2), Item("high", 3)))


def _group(prefix: str, base: int, causality: str, clock: int | None = None, starts: dict | None = None) -> list[Variable]:
    """One variable of each type of ALL_TYPES, value references from ``base``; inputs get start values."""
    out = []
    for i, (suffix, fmi_type) in enumerate(ALL_TYPES):
        continuous = fmi_type.startswith("Float") and clock is None
        start = (starts or {}).get(suffix, "false" if fmi_type == "Boolean" else "" if fmi_type in ("String", "Binary") else "0")
        out.append(var(f"{prefix}{suffix}", base + i, fmi_type, causality, "continuous" if continuous else "discrete",
                       start=start if causality == "input" else None, clock=clock,
                       declared_type="Level" if fmi_type == "Enumeration" else None))
    return out


MODELS: dict[str, dict] = {
    "ball": dict(
        early=True, state=True,
        vars=[
            var("h", 1, "Float64", "output", "continuous"),
            var("v", 2, "Float64", "output", "continuous"),
            var("bounces", 3, "Int64", "output", "discrete"),
            var("h0", 4, "Float64", "parameter", "fixed", start="1.0"),
            var("e", 5, "Float64", "parameter", "fixed", start="0.7"),
        ]),
    "stair": dict(
        early=True,
        vars=[
            var("counter", 1, "Int64", "output", "discrete"),
            var("period", 2, "Float64", "parameter", "fixed", start="1.0"),
            var("last", 3, "Int64", "parameter", "fixed", start="0"),
        ]),
    "ticker": dict(
        vars=[
            clock("tick", 1, "input", "constant", interval="0.25"),
            clock("out", 2, "output", "triggered"),
            var("count", 3, "Int64", "output", "discrete", clock=2),
            var("ticks", 4, "Int64", "output", "discrete"),
            var("phase", 5, "Float64", "output", "continuous"),
        ],
        deps={2: (1,), 3: (2,)}),
    "relay": dict(
        vars=[
            clock("u", 1, "input", "triggered"),
            var("x_in", 2, "Int64", "input", "discrete", clock=1, start="0"),
            clock("y", 3, "output", "triggered"),
            var("x_out", 4, "Int64", "output", "discrete", clock=3),
            var("stepwise", 5, "Boolean", "parameter", "fixed", start="false"),
            var("n", 6, "Int64", "output", "discrete"),
        ],
        deps={3: (1,), 4: (3,)}),
    "zeno": dict(
        early=True,
        vars=[
            clock("z", 1, "output", "triggered"),
            var("start", 2, "Float64", "parameter", "fixed", start="0.5"),
            var("k", 3, "Int64", "output", "discrete"),
        ],
        deps={1: ()}),
    "failer": dict(
        vars=[
            var("y", 1, "Float64", "output", "continuous"),
            var("fail_time", 2, "Float64", "parameter", "fixed", start="0.5"),
            var("crash_time", 3, "Float64", "parameter", "fixed", start="-1"),
        ]),
    "trivial": dict(
        vars=[
            var("u", 1, "Float64", "input", "continuous", start="0"),
            var("y", 2, "Float64", "output", "continuous"),
            var("stop_at", 3, "Float64", "parameter", "fixed", start="0"),
        ]),
    "setcount": dict(
        vars=[
            var("u", 1, "Int64", "input", "discrete", start="0"),
            var("y", 2, "Int64", "output", "discrete"),
            var("sets", 3, "Int64", "output", "discrete"),
        ]),
    "alltypes": dict(
        vars=[
            clock("tick", 1, "input", "constant", interval="0.3"),
            clock("out", 2, "output", "triggered"),
            clock("tin", 3, "input", "triggered"),
            var("echo", 4, "Boolean", "parameter", "fixed", start="false"),
            *_group("y_", 10, "output"),
            *_group("u_", 30, "input", starts={"f64": "1.5", "i8": "-3", "u64": "7", "s": "a b", "e": "2"}),
            *_group("c_", 50, "output", clock=2),
            *_group("ci_", 70, "input", clock=3, starts={"e": "1"}),
        ],
        deps={2: (1,), **{50 + i: (2,) for i in range(len(ALL_TYPES))}},
        types=(LEVEL,)),
}


def model_description(name: str, spec: dict) -> ModelDescription:
    """Every output under <Output>, the unclocked ones also as <InitialUnknown>; the token hashes the rest."""
    deps = spec.get("deps", {})
    outputs = [v for v in spec["vars"] if v.causality == "output"]
    structure = [Unknown("Output", v.value_reference, deps.get(v.value_reference)) for v in outputs]
    structure += [Unknown("InitialUnknown", v.value_reference, deps.get(v.value_reference))
                  for v in outputs if not v.clocks]
    return with_content_token(ModelDescription(
        model_name=name, instantiation_token="",
        co_simulation=CoSimulation(name, has_event_mode=spec.get("event_mode", True), can_handle_variable_step=True,
                                   might_return_early=spec.get("early", False),
                                   can_get_and_set_state=spec.get("state", False)),
        variables=(Variable("time", 0, "Float64", "independent", "continuous"), *spec["vars"]),
        unknowns=tuple(structure), type_definitions=spec.get("types", ()), unit_definitions=spec.get("units", ())))


def build(name: str, outdir: Path, *, xml: str | None = None, spec: dict | None = None,
          source: Path | None = None) -> Path:
    """Compile MODELS[name] (or ``spec``, from the C file ``source``) and write OUTDIR/NAME.fmu
    (``xml`` overrides the model description). The C file includes this folder's framework.h."""
    from robogen import toolchain
    from robogen.fmu.archive import write_fmu
    from robogen.fmu.headers import include_dir

    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    description = model_description(name, spec if spec is not None else MODELS[name])
    source = source if source is not None else HERE / f"{name}.c"
    with tempfile.TemporaryDirectory() as tmp:
        so = Path(tmp) / f"{name}.so"
        toolchain.compile_shared([source], so, includes=[include_dir(), HERE],
                                 defines=[f'MODEL_TOKEN="{description.instantiation_token}"'], what=f"test FMU {name}")
        return write_fmu(outdir / f"{name}.fmu", {
            "modelDescription.xml": xml if xml is not None else write_model_description(description),
            f"binaries/x86_64-linux/{name}.so": so.read_bytes(),
            f"sources/{name}.c": source.read_bytes(),
            "documentation/externalDependencies.txt": "none beyond libc and libm\n",
        })


def build_all(outdir: Path, names=None) -> dict[str, Path]:
    return {n: build(n, outdir) for n in (names or MODELS)}


if __name__ == "__main__":
    out = Path(sys.argv[1])
    for n, p in build_all(out, sys.argv[2:] or None).items():
        print(p)
