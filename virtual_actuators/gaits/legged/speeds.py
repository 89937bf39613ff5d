"""The legged walk's supported desired speeds, per gait pattern and robot (measured).

Each range's ends walk 4 s (the walk's default duration) without falling, on flat ground, in
closed-loop MuJoCo (``python -m virtual_actuators demo legged --robot R --gait G --speed S``).
A robot not in the table (another name, a URDF path) gets the pattern's ``None`` entry, the
range that every measured robot walks; the trot has none: its speeds depend on the robot's size
and strength, so an unmeasured robot trots at any speed it is given (laikago and a copy of go2's
URDF with renamed feet, loaded from its path, trot from 0.1 to 0.5 m/s).
"""

from __future__ import annotations

from typing import Any

from ...models.names import ALIASES

#: ``{pattern: {robot (file stem) or None: (low, high)}}`` [m/s].
LEGGED_SPEEDS: dict[str, dict[str | None, tuple[float, float]]] = {
    "trot": {
        "go2": (0.1, 1.5),
        "solo12": (0.1, 0.8),
        "anymal": (0.1, 1.0),
        "anymal_c": (0.1, 1.0),
        "hyq_no_sensors": (0.1, 1.0),
    },
    "pace": {None: (0.1, 0.4)},
    "walk": {"hexapod": (0.05, 0.3), None: (0.05, 0.2)},
    "tripod": {None: (0.1, 0.8)},
}


def legged_speeds(
    robot: str = "solo12", gait: str = "trot", **options: Any
) -> tuple[float, float] | None:
    """The supported desired speeds ``(low, high)`` [m/s] of ``robot`` walking ``gait``.

    None for a robot the trot was not measured on (no range is enforced). An unknown pattern
    gets the trot's (the walk itself refuses it with the valid names).
    """
    table = LEGGED_SPEEDS.get(gait, LEGGED_SPEEDS["trot"])
    name = ALIASES.get(str(robot), str(robot))
    return table.get(name, table.get(None))


__all__ = ["LEGGED_SPEEDS", "legged_speeds"]
