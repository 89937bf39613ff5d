"""Colours and the legend (as text, HTML and scene objects), which lists only what was drawn.

The robot is drawn with a CIELAB chroma of at most `ROBOT_MAX_CHROMA`, every overlay colour has at
least `OVERLAY_MIN_CHROMA`, so they differ by at least the difference (CIE76 Delta E) whatever a
URDF declares.
"""

from __future__ import annotations

import html
from collections.abc import Collection
from dataclasses import dataclass, fields

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


def desaturate(color: int) -> int:
    """The colour with its chroma cut to `ROBOT_MAX_CHROMA` (+1.5: 8-bit rounding), same hue."""
    lab = to_lab(color)
    current = float(np.hypot(lab[1], lab[2]))
    if current <= ROBOT_MAX_CHROMA:
        return color
    lab[1:] *= ROBOT_MAX_CHROMA / current
    return from_lab(lab)


@dataclass(frozen=True)
class Palette:
    """Colours (``0xRRGGBB``) of everything the viewer draws over the robot.

    Each default has a CIELAB chroma of at least `OVERLAY_MIN_CHROMA` (above the robot's
    `ROBOT_MAX_CHROMA`), and any two differ by a CIE76 Delta E of at least 25.

    Attributes:
        requested_force: Requested force on the action frame.
        requested_moment: Requested moment on the action frame (double head).
        share_force: A chain's share, drawn at its reaction frame.
        share_moment: Its moment about the reaction frame's origin.
        produced: Produced wrench of an admissible request it differs from (free axes).
        inadmissible: Produced wrench of an inadmissible request (least squares).
        spring: Virtual springs.
        damper: Virtual dampers.
        setpoint: Spring set points.
        effort_positive: Joint effort gauge, positive effort.
        effort_negative: Joint effort gauge, negative effort.
        effort_limit: The gauge's shell (the effort limit).
        saturated: Shell of a saturated joint.
        support: Support feet.
    """

    requested_force: int = 0x1E88E5  # blue
    requested_moment: int = 0x651FFF  # violet
    share_force: int = 0x2E7D32  # dark green
    share_moment: int = 0x1DE9B6  # aquamarine
    produced: int = 0xFB8C00  # orange
    inadmissible: int = 0xE53935  # red
    spring: int = 0xD500F9  # magenta
    damper: int = 0x880E4F  # wine
    setpoint: int = 0xFFD600  # yellow
    effort_positive: int = 0xC6FF00  # lime
    effort_negative: int = 0x00E5FF  # cyan
    effort_limit: int = 0x3D5AFE  # indigo (a translucent shell)
    saturated: int = 0x8D1F00  # rust
    support: int = 0x00E676  # bright green

    def __repr__(self) -> str:
        items = ", ".join(f"{f.name}=0x{getattr(self, f.name):06X}" for f in fields(self))
        return f"Palette({items})"


PALETTE = Palette()


def legend_entries(scene: object, drawn: Collection[str]) -> list[tuple[int | None, str]]:
    """The legend as ``(colour or None, short line)`` pairs.

    Args:
        scene: Has the ``palette``, ``force_scale`` [m/N], ``moment_scale`` [m/(N m)] and
            ``effort_reference`` (a full gauge without a limit) of a `RobotScene`.
        drawn: Keys drawn: `Palette` fields, ``"no_limit"``, ``"frames"``.
    """
    p, force_scale, moment_scale = scene.palette, scene.force_scale, scene.moment_scale
    effort_reference = scene.effort_reference
    entries = [
        ("requested_force", p.requested_force, f"force: 1 m = {1 / force_scale:.3g} N"),
        ("requested_moment", p.requested_moment, f"moment: 1 m = {1 / moment_scale:.3g} N m"),
        ("share_force", p.share_force, "chain share at reaction"),
        ("share_moment", p.share_moment, "chain moment at reaction"),
        ("produced", p.produced, "produced (adjusted)"),
        ("inadmissible", p.inadmissible, "produced (inadmissible)"),
        ("spring", p.spring, "virtual spring"),
        ("damper", p.damper, "virtual damper (dashpot)"),
        ("setpoint", p.setpoint, "spring set point"),
        ("effort_positive", p.effort_positive, "effort + (|tau| / limit)"),
        ("effort_negative", p.effort_negative, "effort -"),
        ("saturated", p.saturated, "saturated joint"),
        ("support", p.support, "support foot"),
        ("no_limit", None, f"no limit: full = {effort_reference:.3g}"),
        ("frames", None, "frames: x y z = red green blue"),
    ]
    return [(color, text) for key, color, text in entries if key in drawn]


def legend_html(entries: list[tuple[int | None, str]], title: str = "") -> str:
    """The legend as an HTML box (for standalone pages)."""
    rows = []
    for color, text in entries:
        style = f"background:#{color:06X}" if color is not None else "border-color:transparent"
        rows.append(f'<div><span class="sw" style="{style}"></span>{html.escape(text)}</div>')
    heading = f"<div><b>{html.escape(title)}</b></div>" if title else ""
    return f'<div id="va-overlay">{heading}{"".join(rows)}</div>'
