"""The figure of a scenario's run: the model's events as stems, its machines' states as steps."""

from __future__ import annotations

from pathlib import Path

from robogen.cosim.plot import plot, read_results
from robogen.diagnostics import RobogenError
from robogen.fmu.modeldesc import ModelDescription


def plot_trace(results: Path, output: Path, md: ModelDescription, instance: str = "model") -> Path:
    """Draw the input and output events (triggered clocks) that tick and each ``<machine>.state``
    of the model's instance in the results CSV ``results``."""
    if results.suffix == ".parquet":
        raise RobogenError.at("--plot reads the results CSV: give -o RESULTS.csv", None)
    header, rows = read_results(results)
    ticked = {name for i, name in enumerate(header) if any(r[i] == "1" for r in rows)}
    events = [f"{instance}.{v.name}" for v in md.variables
              if v.is_clock and v.interval_variability in (None, "triggered") and f"{instance}.{v.name}" in ticked]
    states = {v.name: v for v in md.variables
              if v.causality == "output" and v.type == "Enumeration" and v.name.endswith(".state")}
    labels = {}
    for name, var in states.items():
        items = next((t.items for t in md.type_definitions if t.name == var.declared_type), ())
        labels[f"{instance}.{name}"] = {i.value: i.name.rpartition(".")[2] for i in items}
    return plot(results, output, events + list(labels), labels)
