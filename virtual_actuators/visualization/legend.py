"""Colours and the legend: what each colour and size means, as text, HTML and scene objects."""

from __future__ import annotations

import html
from dataclasses import dataclass, fields


@dataclass(frozen=True)
class Palette:
    """Colours (``0xRRGGBB``) of everything the viewer draws.

    Attributes:
        requested_force: Requested force on the action frame.
        requested_moment: Requested moment on the action frame (double head).
        share_force: A chain's share, drawn at its reaction frame.
        share_moment: Its moment about the reaction frame's origin.
        produced: Produced wrench when it differs from the request but was admissible (free
            axes, a request scaled down to keep the feet on the ground).
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

    requested_force: int = 0x1E88E5
    requested_moment: int = 0x8E24AA
    share_force: int = 0x43A047
    share_moment: int = 0x00ACC1
    produced: int = 0xFB8C00
    inadmissible: int = 0xE53935
    spring: int = 0xE6A100
    damper: int = 0x795548
    setpoint: int = 0xFFD600
    effort_positive: int = 0xFF9800
    effort_negative: int = 0x5E35B1
    effort_limit: int = 0x9E9E9E
    saturated: int = 0xD50000
    support: int = 0x00C853

    def __repr__(self) -> str:
        items = ", ".join(f"{f.name}=0x{getattr(self, f.name):06X}" for f in fields(self))
        return f"Palette({items})"


PALETTE = Palette()


def _number(value: float) -> str:
    return f"{value:.3g}"


def legend_entries(
    palette: Palette, force_scale: float, moment_scale: float, effort_reference: float
) -> list[tuple[int | None, str]]:
    """The legend as ``(colour or None, short line)`` pairs.

    Args:
        palette: The colours.
        force_scale: Arrow length per newton [m/N].
        moment_scale: Arrow length per newton-metre [m/(N m)].
        effort_reference: Effort shown as a full gauge at joints without a limit [N m or N].

    """
    p = palette
    return [
        (p.requested_force, f"force: 1 m = {_number(1 / force_scale)} N"),
        (p.requested_moment, f"moment: 1 m = {_number(1 / moment_scale)} N m"),
        (p.share_force, "chain share at reaction"),
        (p.share_moment, "chain moment at reaction"),
        (p.produced, "produced (adjusted)"),
        (p.inadmissible, "produced (inadmissible)"),
        (p.spring, "virtual spring"),
        (p.damper, "virtual damper"),
        (p.setpoint, "spring set point"),
        (p.effort_positive, "effort + (|tau| / limit)"),
        (p.effort_negative, "effort -"),
        (p.saturated, "saturated joint"),
        (p.support, "support foot"),
        (None, f"no limit: full = {_number(effort_reference)}"),
        (None, "frames: x y z = red green blue"),
    ]


def legend_text(entries: list[tuple[int | None, str]]) -> str:
    """The legend as plain text, one entry per line."""
    lines = []
    for color, text in entries:
        swatch = f"#{color:06X}" if color is not None else " " * 7
        lines.append(f"{swatch}  {text}")
    return "\n".join(lines)


def legend_html(entries: list[tuple[int | None, str]], title: str = "") -> str:
    """The legend as an HTML box (for standalone pages)."""
    rows = []
    for color, text in entries:
        swatch = (
            f'<span class="sw" style="background:#{color:06X}"></span>'
            if color is not None
            else '<span class="sw" style="border-color:transparent"></span>'
        )
        rows.append(f"<div>{swatch}{html.escape(text)}</div>")
    heading = f"<div><b>{html.escape(title)}</b></div>" if title else ""
    return f'<div id="va-overlay">{heading}{"".join(rows)}</div>'
