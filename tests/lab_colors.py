"""CIELAB measures of colours, for the tests of the palette and of the robots' colours."""

import numpy as np

from virtual_actuators.visualization.legend import to_lab


def chroma(color: int) -> float:
    """CIELAB chroma ``sqrt(a^2 + b^2)`` of a colour (0 for greys)."""
    _, a, b = to_lab(color)
    return float(np.hypot(a, b))


def color_distance(first: int, second: int) -> float:
    """CIE76 Delta E between two colours (Euclidean distance in CIELAB)."""
    return float(np.linalg.norm(to_lab(first) - to_lab(second)))
