"""The TOML writer round-trips what tomllib reads."""

from __future__ import annotations

import tomllib

from robogen.campaign import tomlwrite


def test_a_system_file_round_trips():
    data = {
        "connections": ["a.y -> b.u", "b.\"q\" -> a.x"],
        "experiment": {"start": 0.0, "stop": 1e-3, "step": 0.1, "order": ["a", "b"], "tolerance": float("inf")},
        "instances": {
            "a": {"fmu": "/tmp/x y/ä.fmu", "start": {"k.x": 3, "on": True, "name": "line\nbreak\t\"q\""}},
            "b": {"fmu": "b.fmu", "clocks": {"cycle": {"interval": 0.5, "shift": 0.0}}},
        },
        "record": {"variables": ["a.*"]},
        "empty": {},
    }
    assert tomllib.loads(tomlwrite.dumps(data)) == data
