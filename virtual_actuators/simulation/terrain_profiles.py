"""The built-in terrain profiles, and the text form of a terrain (``--terrain`` on the CLI)."""

from __future__ import annotations

import math
from collections.abc import Sequence

from virtual_actuators.exceptions import InvalidInputError, suggestion

__all__ = [
    "BUILTIN_NAMES",
    "LEVEL_START",
    "PROFILES",
    "VALID_SPECS",
    "flat_height",
    "parse_points",
    "profile_points",
]

#: Length of the level ground that every built-in profile starts with [m].
LEVEL_START = 2.0

# Built-in profiles as (horizontal length [m], slope [deg]) segments after LEVEL_START m of level
# ground starting at x = 0; the height starts at 0.
PROFILES: dict[str, tuple[tuple[float, float], ...]] = {
    "profile-one": (
        (1.5, 15.0),
        (1.6, 0.0),
        (1.5, -15.0),
        (1.6, 0.0),
        (1.2, 20.0),
        (1.6, 0.0),
        (1.2, -20.0),
        (1.8, 0.0),
    ),
    "profile-two": (
        (1.0, 10.0),
        (0.8, 18.0),
        (1.2, 5.0),
        (0.7, -10.0),
        (1.0, -18.0),
        (0.6, -5.0),
        (1.5, 8.0),
        (0.9, 15.0),
        (0.8, 0.0),
        (1.1, -14.0),
        (0.7, 3.0),
        (1.3, 12.0),
        (0.6, -6.0),
        (1.0, -16.0),
        (1.2, 0.0),
    ),
    "rolling": (
        (1.0, 5.0),
        (1.0, 10.0),
        (1.0, 5.0),
        (1.0, -5.0),
        (1.0, -10.0),
        (1.0, -5.0),
        (1.0, 5.0),
        (1.0, 10.0),
        (1.0, 5.0),
        (1.0, -5.0),
        (1.0, -10.0),
        (1.0, -5.0),
    ),
}

#: Names accepted by :meth:`Terrain.builtin <virtual_actuators.simulation.terrain.Terrain.builtin>`.
BUILTIN_NAMES = ("flat", *PROFILES)

#: What a terrain spec may be, for error messages.
VALID_SPECS = (
    f"valid terrains: {', '.join(BUILTIN_NAMES)}, 'flat:HEIGHT', or points 'x:z,x:z,...' "
    "in metres with increasing x (e.g. '0:0,2:0,3:0.27')"
)


def profile_points(segments: Sequence[tuple[float, float]]) -> list[tuple[float, float]]:
    """Points ``(x, z)`` [m] of a built-in profile: (0, 0), (LEVEL_START, 0), one per segment.

    Args:
        segments: ``(horizontal length [m], slope [deg])`` per segment, as in `PROFILES`.
    """
    points = [(0.0, 0.0), (LEVEL_START, 0.0)]
    x, z = LEVEL_START, 0.0
    for length, slope_deg in segments:
        x += length
        z += length * math.tan(math.radians(slope_deg))
        points.append((round(x, 12), z))
    return points


def flat_height(text: str, spec: str) -> float:
    """The height [m] of a ``"flat:HEIGHT"`` spec.

    Args:
        text: The stripped spec, starting with ``"flat:"``.
        spec: The spec as given (quoted in the error).

    Raises:
        InvalidInputError: If ``HEIGHT`` is not a finite number.
    """
    height = text.removeprefix("flat:").strip()
    try:
        value = float(height)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise InvalidInputError(
            f"Bad terrain height {height!r} in {spec!r}: 'flat:HEIGHT' needs a finite "
            f"number of metres; {VALID_SPECS}."
        )
    return value


def parse_points(text: str, spec: str) -> list[list[float]]:
    """The points ``[x, z]`` [m] of an ``"x:z,x:z,..."`` spec, in the order given.

    Args:
        text: The stripped spec.
        spec: The spec as given (quoted in the error).

    Raises:
        InvalidInputError: If a token is not two finite numbers ``x:z`` (the message quotes
            it, and suggests a built-in name for a word).
    """
    points = []
    for token in text.split(","):
        parts = token.split(":")
        values: list[float] = []
        if len(parts) == 2:
            try:
                values = [float(part) for part in parts]
            except ValueError:
                values = []
        if len(values) != 2 or not all(math.isfinite(v) for v in values):
            hint = ""
            if ":" not in token and token.strip():
                hint = " " + suggestion(token.strip(), BUILTIN_NAMES, "terrains")
            raise InvalidInputError(
                f"Bad terrain token {token.strip()!r} in {spec!r}: expected a point 'x:z' "
                f"with two finite numbers in metres; {VALID_SPECS}.{hint}"
            )
        points.append(values)
    return points
