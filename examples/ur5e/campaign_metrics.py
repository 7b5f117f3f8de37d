"""User metrics of the UR5e campaigns (examples/ur5e/campaign*.toml), computed from each run's
results table (robogen.cosim.SimulationResult: ``columns``, ``rows``, ``column(name)``).

Shipped to the workers as source by ``robogen campaign``: it sits beside the campaign files.
"""

import math

from robogen.platforms.kinematics import grid_position

MOVING = 0.05  # rad/s: a joint faster than this is moving


def _ticked(results, clock: str) -> list[int]:
    """Row numbers in which the clock ticked."""
    return [i for i, v in enumerate(results.column(clock)) if v == 1]


def reach(results) -> dict:
    """Whether the platform accepted the command, and the flange's distance from the commanded
    cell at the end of the run (mm; only for accepted commands)."""
    accepted = bool(_ticked(results, "platform.feasibleMoveDiscreteCommand"))
    refused = bool(_ticked(results, "platform.nonfeasibleMoveDiscreteCommand"))
    commands = _ticked(results, "controller.moveDiscreteCommand")
    if not commands or not accepted or refused:
        return {"feasible": accepted and not refused, "flange_error_mm": None}
    row = results.rows[commands[0]]
    cell = [row[results.columns.index(f"controller.moveDiscreteCommand.target_{axis}")] for axis in "XYZ"]
    final = results.rows[-1]
    flange = [final[results.columns.index(f"platform.ee_{axis}")] for axis in "xyz"]
    return {"feasible": True, "flange_error_mm": 1000.0 * math.dist(flange, grid_position(*cell))}


def motion_start(results) -> dict:
    """Seconds from the command to the first recorded instant at which a joint moves."""
    commands = _ticked(results, "controller.moveDiscreteCommand")
    if not commands:
        return {"to_motion": None}
    time = results.column("time")
    speeds = [results.column(f"platform.dq{i}") for i in range(6)]
    for row in range(commands[0], len(time)):
        if any(abs(dq[row]) > MOVING for dq in speeds):
            return {"to_motion": time[row] - time[commands[0]]}
    return {"to_motion": None}
