"""Colour distances in CIELAB, and the desaturation that keeps the robot apart from the overlays.

The robot is drawn with a chroma of at most `ROBOT_MAX_CHROMA`, every overlay colour has at least
`OVERLAY_MIN_CHROMA`, so they differ by at least the difference (CIE76 Delta E) whatever a URDF
declares.
"""

from __future__ import annotations

import numpy as np

#: Largest CIELAB chroma of a robot colour as drawn.
ROBOT_MAX_CHROMA = 15.0
#: Smallest CIELAB chroma of an overlay colour of the palette.
OVERLAY_MIN_CHROMA = 44.0

_SRGB_TO_XYZ = np.array(
    [[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722], [0.0193, 0.1192, 0.9505]]
)
_WHITE = np.array([0.95047, 1.0, 1.08883])  # D65
_EPSILON = (6.0 / 29.0) ** 3


def rgb(color: int) -> np.ndarray:
    """A ``0xRRGGBB`` colour as three floats in ``[0, 1]``."""
    return np.array([(color >> 16) & 255, (color >> 8) & 255, color & 255], dtype=float) / 255.0


def to_lab(color: int) -> np.ndarray:
    """CIELAB ``(L, a, b)`` of an sRGB colour ``0xRRGGBB`` (D65 white)."""
    srgb = rgb(color)
    linear = np.where(srgb <= 0.04045, srgb / 12.92, ((srgb + 0.055) / 1.055) ** 2.4)
    xyz = _SRGB_TO_XYZ @ linear / _WHITE
    f = np.where(xyz > _EPSILON, np.cbrt(xyz), xyz / (3 * (6 / 29) ** 2) + 4 / 29)
    return np.array([116.0 * f[1] - 16.0, 500.0 * (f[0] - f[1]), 200.0 * (f[1] - f[2])])


def from_lab(lab: np.ndarray) -> int:
    """The sRGB colour ``0xRRGGBB`` of a CIELAB colour (clipped to the sRGB gamut)."""
    fy = (lab[0] + 16.0) / 116.0
    f = np.array([fy + lab[1] / 500.0, fy, fy - lab[2] / 200.0])
    xyz = np.where(f > 6 / 29, f**3, 3 * (6 / 29) ** 2 * (f - 4 / 29)) * _WHITE
    linear = np.clip(np.linalg.solve(_SRGB_TO_XYZ, xyz), 0.0, 1.0)
    srgb = np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * linear ** (1 / 2.4) - 0.055)
    r, g, b = (int(round(255 * float(c))) for c in np.clip(srgb, 0.0, 1.0))
    return (r << 16) | (g << 8) | b


def chroma(color: int) -> float:
    """CIELAB chroma ``sqrt(a^2 + b^2)`` of a colour (0 for greys)."""
    _, a, b = to_lab(color)
    return float(np.hypot(a, b))


def color_distance(first: int, second: int) -> float:
    """CIE76 Delta E between two colours (Euclidean distance in CIELAB)."""
    return float(np.linalg.norm(to_lab(first) - to_lab(second)))


def desaturate(color: int, max_chroma: float = ROBOT_MAX_CHROMA) -> int:
    """The colour with its chroma limited to ``max_chroma`` (+1.5 for 8-bit rounding), same hue."""
    lab = to_lab(color)
    current = float(np.hypot(lab[1], lab[2]))
    if current <= max_chroma:
        return color
    lab[1:] *= max_chroma / current
    return from_lab(lab)
