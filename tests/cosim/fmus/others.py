"""Build the test FMUs of the other interfaces (mex_core.h and its models): FMI 2.0 Model Exchange
and Co-Simulation, FMI 3.0 Model Exchange (with Co-Simulation in the same binary where asked) and
Scheduled Execution. FMI 3.0 descriptions are written by robogen's writer, FMI 2.0 ones here; the
token (GUID) is passed to the compiler, so the two cannot disagree on it.

    python tests/cosim/fmus/others.py OUTDIR [NAME ...]
"""

from __future__ import annotations

import hashlib
import sys
import tempfile
from pathlib import Path

from robogen.fmu.modeldesc import (
    CoSimulation, DefaultExperiment, Dimension, ModelDescription, ModelExchange, ScheduledExecution, Unknown, Variable,
)
from robogen.fmu.modeldesc_writer import with_content_token, write_model_description

HERE = Path(__file__).resolve().parent


def real(name, vr, causality, start=None, variability="continuous"):
    return ("Real", name, vr, causality, variability, start)


def integer(name, vr, causality, start=None, fmi3="Int64"):
    return (fmi3, name, vr, causality, "fixed" if causality == "parameter" else "discrete", start)


BOUNCE = [real("h", 1, "output", "1"), real("v", 2, "output", "0"), integer("bounces", 3, "output"),
          real("g", 4, "parameter", "9.81", "fixed"), real("e", 5, "parameter", "0.7", "fixed"),
          real("kick_time", 6, "parameter", "-1", "fixed"), real("kick", 7, "parameter", "0", "fixed"),
          real("step_event_at", 8, "parameter", "-1", "fixed"), integer("step_events", 9, "output"),
          integer("max_bounces", 10, "parameter", "0")]
VDP = [real("x0", 1, "output", "2"), real("x1", 2, "output", "0"), real("mu", 3, "parameter", "1", "fixed")]
STIFF = [real("y0", 1, "output", "1"), real("y1", 2, "output", "0"), real("y2", 3, "output", "0")]
LAG = [real("x", 1, "output", "0"), real("u", 2, "input", "1"), real("tau", 3, "parameter", "0.5", "fixed"),
       integer("crossings", 4, "output", fmi3="Int32"), ("Boolean", "above", 5, "output", "discrete", None),
       ("Enumeration", "level", 6, "output", "discrete", None), integer("stop_after", 7, "parameter", "0", fmi3="Int32"),
       integer("async_polls", 8, "parameter", "0", fmi3="Int32")]
SCHED = [("Clock", "fast", 1, "input", "discrete", ("0.1", 2)), ("Clock", "slow", 2, "input", "discrete", ("0.3", 1)),
         integer("seq", 3, "output"), integer("fast_seq", 4, "output"), integer("slow_seq", 5, "output"),
         integer("fast_n", 6, "output"), integer("slow_n", 7, "output"), ("Float64", "y_fast", 8, "output", "discrete", 1),
         ("Int64", "y_slow", 9, "output", "discrete", 2), ("Clock", "kick", 10, "input", "discrete", (None, 0)),
         integer("kick_seq", 11, "output"), ("Clock", "later", 12, "input", "discrete", ("countdown", 3)),
         real("delay", 13, "parameter", "0", "fixed"), integer("later_seq", 14, "output"),
         ("Float64", "later_at", 15, "output", "discrete", None)]

ARRAYS = [real("x", 1, "output", "0"), Variable("n", 2, "UInt64", "structuralParameter", "fixed", start=("3",)),
          Variable("y", 3, "Float64", "output", "continuous", dimensions=(Dimension(value_reference=2),))]

PLANT = [real("x", 1, "output", "0"), real("u", 2, "input", "0", "discrete")]
CONTROLLER = [("Clock", "r", 1, "input", "discrete", ("0.1", None)), ("Clock", "s", 2, "input", "discrete", (None, None)),
              ("Float64", "xr", 3, "input", "discrete", 1), ("Float64", "ur", 4, "output", "discrete", 1),
              ("Float64", "as", 5, "input", "discrete", 2), real("ref", 6, "output", None, "discrete"),
              real("k", 7, "parameter", "2", "fixed")]
SUPERVISOR = [real("x", 1, "input", "0", "discrete"), ("Clock", "s", 2, "output", "discrete", (None, None)),
              ("Float64", "as", 3, "output", "discrete", 2), real("threshold", 4, "parameter", "0.5", "fixed")]

GANTRY = [real("x", 1, "output", "0"), real("y", 2, "output", "0"), real("z", 3, "output", "0"),
          integer("X", 4, "input", "0", fmi3="Int32"), integer("Y", 5, "input", "0", fmi3="Int32"),
          integer("Z", 6, "input", "0", fmi3="Int32"), real("cell", 7, "parameter", "0.05", "fixed"),
          real("tau", 8, "parameter", "0.5", "fixed")]

#: name -> (C file, FMI version, interfaces, variables, states, event indicators[, options: early
#: (the CS interface might return early; default true)])
MODELS = {
    "bounce3": ("bounce.c", 3, ("me", "cs"), BOUNCE, 2, 1),
    "bounce2": ("bounce.c", 2, ("me",), BOUNCE, 2, 1),
    "vdp2": ("vdp.c", 2, ("me",), VDP, 2, 0),
    "vdp3": ("vdp.c", 3, ("me",), VDP, 2, 0),
    "stiff3": ("stiff.c", 3, ("me",), STIFF, 3, 0),
    "lag2": ("lag.c", 2, ("cs",), LAG, 1, 1),
    "lag2me": ("lag.c", 2, ("me", "cs"), LAG, 1, 1),
    "sched3": ("sched.c", 3, ("se",), SCHED, 0, 0),
    "arrays3": ("arrays.c", 3, ("cs", "me"), ARRAYS, 1, 0),
    "plant2": ("integrator.c", 2, ("me",), PLANT, 1, 0),
    "controller3": ("controller.c", 3, ("cs",), CONTROLLER, 0, 0, {"early": False}),
    "supervisor3": ("supervisor.c", 3, ("cs",), SUPERVISOR, 0, 0, {"early": False}),
    "gantry2": ("gantry.c", 2, ("me",), GANTRY, 3, 0),
}


def _variable3(spec) -> Variable:
    if isinstance(spec, Variable):
        return spec
    kind, name, vr, causality, variability, extra = spec
    fmi_type = "Float64" if kind == "Real" else kind
    if fmi_type == "Clock":
        interval, priority = extra
        if interval is None or interval == "countdown":
            return Variable(name, vr, "Clock", causality, "discrete", interval_variability=interval or "triggered",
                            priority=priority)
        return Variable(name, vr, "Clock", causality, "discrete", interval_variability="constant", interval_decimal=interval,
                        shift_decimal="0", priority=priority)
    clocked = fmi_type != "Enumeration" and isinstance(extra, int) and variability == "discrete"
    start = () if extra is None or clocked or causality == "output" else (extra,)
    return Variable(name, vr, "Int64" if fmi_type == "Enumeration" else fmi_type, causality, variability, start=start,
                    clocks=(extra,) if clocked else ())


def description3(name: str) -> ModelDescription:
    source, _version, interfaces, variables, nx, nz, *options = MODELS[name]
    early = (options or [{}])[0].get("early", True)
    declared = [_variable3(v) for v in variables]
    outputs = [v for v in declared if v.causality == "output"]
    derivatives = [Variable(f"der({v.name})", 100 + i, "Float64", "local", "continuous") for i, v in enumerate(declared[:nx])]
    indicators = [Variable(f"z{i}", 200 + i, "Float64", "local", "continuous") for i in range(nz)]
    structure = [Unknown("Output", v.value_reference) for v in outputs]
    structure += [Unknown("ContinuousStateDerivative", v.value_reference) for v in derivatives]
    structure += [Unknown("InitialUnknown", v.value_reference) for v in outputs if not v.clocks]
    structure += [Unknown("EventIndicator", v.value_reference) for v in indicators]
    ident = name
    return with_content_token(ModelDescription(
        model_name=name, instantiation_token="",
        co_simulation=CoSimulation(ident, can_handle_variable_step=True, has_event_mode=True, might_return_early=early,
                                   can_get_and_set_state=True) if "cs" in interfaces else None,
        model_exchange=ModelExchange(ident, needs_completed_integrator_step=True, can_get_and_set_state=True)
        if "me" in interfaces else None,
        scheduled_execution=ScheduledExecution(ident) if "se" in interfaces else None,
        variables=(Variable("time", 0, "Float64", "independent", "continuous"), *declared, *derivatives, *indicators),
        unknowns=tuple(structure), default_experiment=DefaultExperiment(start_time="0", stop_time="1", tolerance="1e-6")))


_FMI2_TYPE = {"Real": "Real", "Float64": "Real", "Int64": "Integer", "Int32": "Integer", "Boolean": "Boolean",
              "Enumeration": "Enumeration"}


def description2(name: str) -> tuple[str, str]:
    """(the FMI 2.0 modelDescription.xml, its GUID)."""
    source, _version, interfaces, variables, nx, nz, *_options = MODELS[name]
    rows, outputs, derivatives = [], [], []
    for position, (kind, var, vr, causality, variability, start) in enumerate(variables, 1):
        element = _FMI2_TYPE[kind]
        has_start = start is not None and (causality != "output" or position <= nx)
        attributes = f' start="{start}"' if has_start else ""
        declared = ' declaredType="Level"' if element == "Enumeration" else ""
        initial = ' initial="exact"' if causality == "output" and position <= nx else ""
        rows.append(f'    <ScalarVariable name="{var}" valueReference="{vr}" causality="{causality}" '
                    f'variability="{variability}"{initial}><{element}{declared}{attributes}/></ScalarVariable>')
        if causality == "output":
            outputs.append(position)
    for i in range(nx):
        rows.append(f'    <ScalarVariable name="der({variables[i][1]})" valueReference="{100 + i}">'
                    f'<Real derivative="{i + 1}"/></ScalarVariable>')
        derivatives.append(len(rows))
    me = f'  <ModelExchange modelIdentifier="{name}"/>\n' if "me" in interfaces else ""
    cs = (f'  <CoSimulation modelIdentifier="{name}" canHandleVariableCommunicationStepSize="true" '
          'canGetAndSetFMUstate="true"/>\n') if "cs" in interfaces else ""
    body = (f'{me}{cs}  <TypeDefinitions><SimpleType name="Level"><Enumeration><Item name="low" value="1"/>'
            '<Item name="high" value="2"/></Enumeration></SimpleType></TypeDefinitions>\n'
            '  <DefaultExperiment startTime="0" stopTime="1" tolerance="1e-6"/>\n'
            '  <ModelVariables>\n' + "\n".join(rows) + '\n  </ModelVariables>\n  <ModelStructure>\n'
            + (f'    <Outputs>{"".join(f"<Unknown index={chr(34)}{i}{chr(34)}/>" for i in outputs)}</Outputs>\n' if outputs else "")
            + (f'    <Derivatives>{"".join(f"<Unknown index={chr(34)}{i}{chr(34)}/>" for i in derivatives)}</Derivatives>\n'
               if derivatives else "") + '  </ModelStructure>\n')
    guid = "{" + hashlib.sha256(body.encode()).hexdigest()[:32] + "}"
    head = (f'<?xml version="1.0" encoding="UTF-8"?>\n<fmiModelDescription fmiVersion="2.0" modelName="{name}" '
            f'guid="{guid}" numberOfEventIndicators="{nz}">\n')
    return head + body + "</fmiModelDescription>\n", guid


def build(name: str, outdir: Path, *, xml: str | None = None, extra: dict | None = None) -> Path:
    """Compile MODELS[name] and write OUTDIR/NAME.fmu (``xml`` replaces its description; ``extra``
    adds archive members)."""
    from robogen import toolchain
    from robogen.fmu.archive import write_fmu
    from robogen.fmu.headers import include_dir

    source, version, *_ = MODELS[name]
    if version == 2:
        text, token = description2(name)
    else:
        md = description3(name)
        text, token = write_model_description(md), md.instantiation_token
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        so = Path(tmp) / f"{name}.so"
        defines = [f'MODEL_TOKEN="{token}"'] + (["FMI2"] if version == 2 else [])
        toolchain.compile_shared([HERE / source], so, includes=[include_dir(fmi2=True), HERE], defines=defines,
                                 what=f"test FMU {name}")
        return write_fmu(outdir / f"{name}.fmu", {
            "modelDescription.xml": xml if xml is not None else text,
            f"binaries/{'linux64' if version == 2 else 'x86_64-linux'}/{name}.so": so.read_bytes(),
            f"sources/{source}": (HERE / source).read_bytes(),
            **(extra or {}),
        })


def build_all(outdir: Path, names=None) -> dict[str, Path]:
    return {n: build(n, outdir) for n in (names or MODELS)}


if __name__ == "__main__":
    for n, p in build_all(Path(sys.argv[1]), sys.argv[2:] or None).items():
        print(p)
