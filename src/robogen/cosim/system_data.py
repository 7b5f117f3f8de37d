"""A system as the data of a system file: what ``tomllib`` would read from the TOML file that
describes it (docs/system-toml.md), whatever file the system was read from.

An SSP's system (:mod:`robogen.cosim.ssp_read`) written this way runs as the SSP does: its
flattened instances, their start values, clock timings and interfaces, its connections (a converting one as
a connection table with its factor and offset), its experiment and robogen's settings. Campaigns
over an SSP derive each run's system file from it (:mod:`robogen.campaign`).
"""

from __future__ import annotations

from typing import Callable

from robogen.cosim.system import SOLVERS, InstanceSpec, System


def toml_data(system: System, fmu: Callable[[InstanceSpec], str] = lambda spec: str(spec.fmu)) -> dict:
    """The system file's data of ``system`` (``fmu``: how an instance's FMU is named in it)."""
    data: dict = {}
    data["connections"] = [f"{c.source} -> {c.target}" if c.scale is None else
                           {"from": str(c.source), "to": str(c.target), "factor": c.scale[0], "offset": c.scale[1]}
                           for c in system.connections]
    experiment = {"start": system.start, "stop": system.stop, "step": system.step, "tolerance": system.tolerance,
                  "max_event_iterations": system.max_event_iterations, "order": list(system.order) or None}
    data["experiment"] = {k: v for k, v in experiment.items() if v is not None}
    data["instances"] = {name: _instance(spec, fmu) for name, spec in system.instances.items()}
    if system.record is not None or system.record_every is not None:
        record: dict = {}
        if system.record is not None:
            record["variables"] = [name for name, _span in system.record]
        if system.record_every is not None:
            record["every"] = system.record_every
        data["record"] = record
    return data


def _instance(spec: InstanceSpec, fmu: Callable[[InstanceSpec], str]) -> dict:
    instance: dict = {"fmu": fmu(spec)}
    if spec.start:
        instance["start"] = {name: value for name, (value, _span) in spec.start.items()}
    if spec.clocks:
        instance["clocks"] = {name: dict(timing) for name, (timing, _span) in spec.clocks.items()}
    if spec.isolate:
        instance["isolate"] = True
    settings = {"interface": spec.interface, "solver": spec.solver if spec.solver != SOLVERS[0] else None,
                "solver_step": spec.solver_step}
    instance.update((k, v) for k, v in settings.items() if v is not None)
    return instance
