"""Writing TOML: enough for a system file derived from a parsed one (``tomllib`` only reads).

Tables become ``[a.b]`` sections, tables inside arrays become inline tables; keys are always
quoted, strings written with JSON escapes (which TOML's basic strings share), floats with
``repr`` (``inf`` and ``nan`` are TOML too). ``tomllib.loads(dumps(d)) == d`` for every ``d``
made of dicts, lists, strings, booleans, integers and floats.
"""

from __future__ import annotations

import json
import math


def _key(key: str) -> str:
    return json.dumps(key, ensure_ascii=False)


def _value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(value) if math.isfinite(value) else ("nan" if math.isnan(value) else ("inf" if value > 0 else "-inf"))
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, list):
        return "[" + ", ".join(_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{_key(k)} = {_value(v)}" for k, v in value.items()) + "}"
    raise TypeError(f"cannot write {type(value).__name__} as TOML")


def dumps(data: dict) -> str:
    lines: list[str] = []

    def table(d: dict, path: tuple[str, ...]) -> None:
        plain = {k: v for k, v in d.items() if not isinstance(v, dict)}
        nested = {k: v for k, v in d.items() if isinstance(v, dict)}
        if path and (plain or not nested):
            lines.append("[" + ".".join(_key(p) for p in path) + "]")
        lines.extend(f"{_key(k)} = {_value(v)}" for k, v in plain.items())
        for k, v in nested.items():
            table(v, path + (k,))

    table(data, ())
    return "\n".join(lines) + "\n"
