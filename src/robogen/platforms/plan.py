"""The controller's plan: grid move commands at given times, kept as data (TOML).

::

    repeat_period = 25.0    # s; optional: play the commands again every period
    end_time = 100.0        # s; optional: no command after this time

    [[command]]
    time = 5.0              # s, >= 0 (and < repeat_period when repeating)
    target = [0, 23, 1]     # grid X, Y, Z (integers)

Command k of round r happens at ``time_k + r * repeat_period``, computed from the integers k
and r (no running sum, so no drift). Problems are reported as located diagnostics.
"""

from __future__ import annotations

import math
import re
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator

from robogen.diagnostics import DiagnosticSink, RobogenError, Span, did_you_mean

TOP_KEYS = ("repeat_period", "end_time", "command")
COMMAND_KEYS = ("time", "target")


@dataclass(frozen=True)
class Command:
    time: float
    target: tuple[int, int, int]


@dataclass(frozen=True)
class CommandPlan:
    commands: tuple[Command, ...]
    repeat_period: float | None = None
    end_time: float | None = None

    def events(self, until: float | None = None) -> Iterator[Command]:
        """The planned commands in time order, up to ``end_time`` and ``until`` (inclusive)."""
        bounds = [b for b in (self.end_time, until) if b is not None]
        limit = min(bounds) if bounds else math.inf
        rounds = range(1) if not self.repeat_period else _count()
        for r in rounds:
            offset = r * self.repeat_period if self.repeat_period else 0.0
            for command in self.commands:
                t = command.time + offset
                if t > limit:
                    return
                yield Command(t, command.target)
            if not self.commands:
                return


def _count() -> Iterator[int]:
    r = 0
    while True:
        yield r
        r += 1


def _line_of(text: str, pattern: str, start_line: int = 1) -> int | None:
    regex = re.compile(pattern)
    for number, line in enumerate(text.splitlines()[start_line - 1:], start=start_line):
        if regex.search(line):
            return number
    return None


class _Locator:
    def __init__(self, path: str, text: str) -> None:
        self.path, self.text = path, text
        self.headers = [n for n, line in enumerate(text.splitlines(), start=1)
                        if re.match(r"\s*\[\[\s*command\s*\]\]", line)]

    def key(self, key: str, command: int | None = None) -> Span:
        start = self.headers[command] if command is not None and command < len(self.headers) else 1
        line = _line_of(self.text, rf"^\s*{re.escape(key)}\s*=", start)
        if line is None:
            line = start
        column = (self.text.splitlines()[line - 1].find(key) + 1) if self.text else 1
        column = max(column, 1)
        return Span(self.path, line, column, line, column + len(key))

    def command(self, index: int) -> Span:
        if index < len(self.headers):
            line = self.headers[index]
            return Span(self.path, line, 1, line, len(self.text.splitlines()[line - 1]) + 1)
        return Span.whole_file(self.path)


def _number(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def parse_plan(text: str, path: str = "<plan>") -> CommandPlan:
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        match = re.search(r"\(at line (\d+), column (\d+)\)", str(exc))
        span = Span.point(path, int(match.group(1)), int(match.group(2))) if match else Span.whole_file(path)
        message = re.sub(r"\s*\(at line \d+, column \d+\)", "", str(exc))
        raise RobogenError.at(f"invalid TOML: {message}", span) from None
    where = _Locator(path, text)
    sink = DiagnosticSink()
    for key in data:
        if key not in TOP_KEYS:
            sink.error(f"unknown key '{key}'{did_you_mean(key, TOP_KEYS)}", where.key(key))
    period = data.get("repeat_period")
    if period is not None and not (_number(period) and period > 0):
        sink.error("repeat_period must be a number of seconds > 0", where.key("repeat_period"))
        period = None
    end = data.get("end_time")
    if end is not None and not (_number(end) and end >= 0):
        sink.error("end_time must be a number of seconds >= 0", where.key("end_time"))
        end = None
    raw = data.get("command", [])
    if not isinstance(raw, list):
        sink.error("'command' must be an array of tables: write each as [[command]]", where.key("command"))
        raw = []
    if not raw:
        sink.error("the plan has no [[command]]", Span.whole_file(path))
    commands = []
    for i, entry in enumerate(raw):
        if not isinstance(entry, dict):
            sink.error("a command must be a table with 'time' and 'target'", where.command(i))
            continue
        for key in entry:
            if key not in COMMAND_KEYS:
                sink.error(f"unknown key '{key}' in a command{did_you_mean(key, COMMAND_KEYS)}", where.key(key, i))
        t, target = entry.get("time"), entry.get("target")
        ok = True
        if t is None:
            sink.error("this command has no 'time'", where.command(i))
            ok = False
        elif not (_number(t) and t >= 0):
            sink.error("'time' must be a number of seconds >= 0", where.key("time", i))
            ok = False
        elif period is not None and t >= period:
            sink.error(f"'time' {t} s is not within the repeat period ({period} s)", where.key("time", i))
            ok = False
        if target is None:
            sink.error("this command has no 'target'", where.command(i))
            ok = False
        elif not (isinstance(target, list) and len(target) == 3
                  and all(isinstance(v, int) and not isinstance(v, bool) for v in target)):
            sink.error("'target' must be three integers [X, Y, Z] (grid indices)", where.key("target", i))
            ok = False
        elif not all(-(1 << 63) <= v < (1 << 63) for v in target):
            sink.error("'target' indices must fit in an Int64", where.key("target", i))
            ok = False
        if ok:
            commands.append(Command(float(t), (target[0], target[1], target[2])))
    times = [c.time for c in commands]
    if times != sorted(times):
        sink.error("commands must be listed in time order", Span.whole_file(path))
    sink.raise_if_errors()
    return CommandPlan(tuple(commands), float(period) if period is not None else None,
                float(end) if end is not None else None)


def load_plan(path: str | Path) -> CommandPlan:
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise RobogenError.at(f"cannot read the plan: {exc.strerror}", Span.whole_file(str(path))) from None
    return parse_plan(text, str(path))
