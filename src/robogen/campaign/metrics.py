"""Metrics: numbers (or booleans, or names) computed from one run's results.

Built-ins read the recorded table of :class:`robogen.cosim.SimulationResult` (one row per
communication point and per super-dense instant, clocks 0/1, ``None`` where a clocked variable
is inactive):

- ``final``: the last value the variable had; ``min`` / ``max``: over the whole run;
- ``at`` (with ``time``): the value held at that time (the last row at or before it);
- ``first_tick``: the time of the clock's first tick; with ``since = "instance.clock"``, the
  time from the first tick of that clock to the first tick of this one at or after it;
- ``ticks``: how many instants the clock ticked in;
- ``equals = VALUE`` turns ``final`` or ``at`` into a boolean.

An Enumeration's value is given by its item name (``"Idle"``), read from the FMU's model
description. A user metric ``"module:function"`` is called with the result and returns a dict
of name -> number, boolean, string or None; each name becomes a column.
"""

from __future__ import annotations

import math
import zipfile
from pathlib import Path
from typing import Callable

from robogen.campaign.spec import Metric, Value
from robogen.fmu.fmi import same_time
from robogen.fmu.modeldesc import parse_xml

Scalar = int | float | bool | str | None


class MetricError(Exception):
    """A metric that cannot be computed from this run (the run is recorded as failed)."""


def enumeration_names(fmus: dict[str, Path]) -> dict[str, dict[int, str]]:
    """"instance.variable" -> {value: item name} for every Enumeration variable of the FMUs."""
    names = {}
    for instance, fmu in fmus.items():
        with zipfile.ZipFile(fmu) as z:
            root = parse_xml(z.read("modelDescription.xml"), f"{fmu}/modelDescription.xml").getroot()
        types = {t.get("name"): {int(i.get("value")): i.get("name") for i in t.iter("Item")}
                 for t in root.iter("EnumerationType")}
        for var in root.iter("Enumeration"):
            if var.get("declaredType") in types:
                names[f"{instance}.{var.get('name')}"] = types[var.get("declaredType")]
    return names


class Table:
    """Column access over a result's rows (or its columns: :meth:`of`), with clear errors for
    what was not recorded."""

    def __init__(self, columns: list[str], rows: list[list]) -> None:
        self.index = {name: i for i, name in enumerate(columns)}
        self._column: Callable[[int], list] = lambda i: [row[i] for row in rows]
        self.time = self._column(0)

    @classmethod
    def of(cls, result) -> "Table":
        """The table of a :class:`robogen.cosim.SimulationResult`, read column by column (its
        rows are never made)."""
        table = cls(result.columns, [])
        table._column = lambda i: result.column(result.columns[i])
        table.time = table._column(0)
        return table

    def values(self, name: str) -> list:
        if name not in self.index:
            raise MetricError(f"'{name}' is not recorded in the results (see [record] in the system file)")
        return self._column(self.index[name])

    def tick_times(self, clock: str) -> list[float]:
        return [t for t, v in zip(self.time, self.values(clock)) if v == 1]


def builtin(metric: Metric, table: Table, enums: dict[str, dict[int, str]]) -> Scalar:
    kind, source = metric.kind, metric.source
    if kind in ("first_tick", "ticks"):
        ticks = table.tick_times(source)
        if kind == "ticks":
            return len(ticks)
        if "since" not in metric.options:
            return ticks[0] if ticks else None
        origin = table.tick_times(metric.options["since"])
        after = [t for t in ticks if origin and (t >= origin[0] or same_time(t, origin[0]))]
        return after[0] - origin[0] if after else None
    present = [(t, v) for t, v in zip(table.time, table.values(source)) if v is not None]
    if kind in ("min", "max"):
        values = [v for _, v in present]
        return (min if kind == "min" else max)(values) if values else None
    if kind == "at":
        at = float(metric.options["time"])
        held = [v for t, v in present if t <= at or same_time(t, at)]
        value = held[-1] if held else None
    else:
        value = present[-1][1] if present else None
    if value is not None and source in enums:
        value = enums[source].get(value, value)
    if "equals" in metric.options:
        return None if value is None else value == metric.options["equals"]
    return value


def user_metrics(function: Callable, result, where: str) -> dict[str, Scalar]:
    """Call a user metric and check what it returns."""
    try:
        values = function(result)
    except Exception as exc:  # the user's code: its failure is this run's failure
        raise MetricError(f"{where} raised {type(exc).__name__}: {exc}") from None
    if not isinstance(values, dict) or not all(isinstance(k, str) for k in values):
        raise MetricError(f"{where} must return a dict of name -> value, not {type(values).__name__}")
    checked = {}
    for name, value in values.items():
        if hasattr(value, "item") and callable(value.item):  # a numpy scalar
            value = value.item()
        if value is not None and not isinstance(value, (bool, int, float, str)):
            raise MetricError(f"{where} returned {name} = {value!r}: give a number, a boolean, a string or None")
        checked[name] = None if isinstance(value, float) and math.isnan(value) else value
    return checked


def compute(metrics: tuple[Metric, ...], result, enums: dict[str, dict[int, str]],
            functions: dict[str, Callable]) -> dict[str, Value | None]:
    """Every metric of the campaign over one result, in declaration order."""
    table = Table.of(result)
    out: dict[str, Value | None] = {}
    for metric in metrics:
        if metric.kind != "function":
            out[metric.name] = builtin(metric, table, enums)
            continue
        for name, value in user_metrics(functions[metric.source], result, metric.source).items():
            if name in out or any(m.name == name and m is not metric for m in metrics):
                raise MetricError(f"{metric.source} returned '{name}', which is also the name of another metric")
            out[name] = value
    return out
