"""The legged walk's supported desired speeds, per gait pattern and robot (measured).

Each range's ends walk 4 s on flat ground in MuJoCo. A robot not in the table gets the pattern's
``None`` entry; the trot has none (an unmeasured robot trots at any speed).
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
    """The supported desired speeds ``(low, high)`` [m/s] of ``robot`` walking ``gait``, or None.

    An unknown pattern gets the trot's (the walk itself refuses it).
    """
    table = LEGGED_SPEEDS.get(gait, LEGGED_SPEEDS["trot"])
    name = ALIASES.get(str(robot), str(robot))
    return table.get(name, table.get(None))


__all__ = ["LEGGED_SPEEDS", "legged_speeds"]
