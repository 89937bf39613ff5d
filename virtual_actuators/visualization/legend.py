"""Colours and the legend (as text, HTML and scene objects), which lists only what was drawn."""

from __future__ import annotations

import html
from collections.abc import Collection
from dataclasses import dataclass, fields


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


def legend_entries(
    palette: Palette,
    force_scale: float,
    moment_scale: float,
    effort_reference: float,
    drawn: Collection[str] | None = None,
) -> list[tuple[int | None, str]]:
    """The legend as ``(colour or None, short line)`` pairs.

    Args:
        palette: The colours.
        force_scale: Arrow length per newton [m/N].
        moment_scale: Arrow length per newton-metre [m/(N m)].
        effort_reference: Effort shown as a full gauge at joints without a limit [N m or N].
        drawn: Keys drawn: `Palette` fields, ``"no_limit"``, ``"frames"`` (None: all).
    """
    p = palette
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
    return [(color, text) for key, color, text in entries if drawn is None or key in drawn]


def legend_text(entries: list[tuple[int | None, str]]) -> str:
    """The legend as plain text, one entry per line."""
    swatches = [(" " * 7 if color is None else f"#{color:06X}", text) for color, text in entries]
    return "\n".join(f"{swatch}  {text}" for swatch, text in swatches)


def legend_html(entries: list[tuple[int | None, str]], title: str = "") -> str:
    """The legend as an HTML box (for standalone pages)."""
    rows = []
    for color, text in entries:
        style = f"background:#{color:06X}" if color is not None else "border-color:transparent"
        rows.append(f'<div><span class="sw" style="{style}"></span>{html.escape(text)}</div>')
    heading = f"<div><b>{html.escape(title)}</b></div>" if title else ""
    return f'<div id="va-overlay">{heading}{"".join(rows)}</div>'
