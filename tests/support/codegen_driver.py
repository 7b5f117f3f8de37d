"""The differential driver of the code generator's tests: :mod:`robogen.differential` (scenarios,
the FMU runner, the interpreter's side, building), re-exported, and two helpers that assert."""

from __future__ import annotations

from pathlib import Path

from robogen.differential import (COUNTERS, Built, Description, Error, FmuRunner, Instant, Scenario, Step, Tick, Trace, Var,  # noqa: F401
                                  build, canonical, first_difference, interpret, random_scenario, random_value)
from robogen.ir.lower import LoweringOptions


def run_checked(built: Built, scenario: Scenario, parameters: dict[str, object] | None = None,
                functions: dict | None = None) -> Trace:
    """The FMU's trace of ``scenario`` (``parameters`` set in Initialization Mode), after checking
    that the interpreter's is the same (``functions``: its user functions)."""
    runner = FmuRunner(built.folder)
    try:
        got = runner.run(scenario, parameters=parameters)
    finally:
        runner.close()
    expected = interpret(built.fmu, scenario, runner.desc, parameters=parameters, functions=functions)
    assert got.comparable() == expected.comparable()
    return got


def outputs_by_instant(built: Built, inputs: dict[int, Tick], instants: int, parameters: dict[str, object] | None = None,
                       functions: dict | None = None) -> tuple[dict[int, dict], Trace]:
    """One tock per instant, the input ``inputs[t]`` at instant t: the outputs of each instant (all
    its super-dense steps together) and the trace, which ran without error and which the
    interpreter's equals."""
    scenario = Scenario([Instant(True, (inputs[t],) if t in inputs else ()) for t in range(instants)], half=False)
    trace = run_checked(built, scenario, parameters, functions)
    assert trace.error is None, trace.error
    outputs: dict[int, dict] = {}
    for s in trace.steps:
        outputs.setdefault(s.instant, {}).update(s.outputs)
    return outputs, trace


def build_text(work: Path, name: str, text: str, options: LoweringOptions | None = None,
               c_functions: str | None = None) -> Built:
    """:func:`build` of a model written to ``work/<name>.rct`` (and its user functions' C, if
    given, to ``work/<name>.c``)."""
    path = work / f"{name}.rct"
    path.write_text(text)
    c_file = None
    if c_functions is not None:
        c_file = work / f"{name}.c"
        c_file.write_text(c_functions)
    return build([path], work / name, options=options, functions=c_file)


__all__ = ["Tick", "Instant", "Scenario", "canonical", "Step", "Trace", "Description", "FmuRunner", "interpret", "run_checked",
           "outputs_by_instant", "random_scenario", "build", "build_text", "Built"]
