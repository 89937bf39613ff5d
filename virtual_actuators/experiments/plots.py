"""Plot a recorded walking run like the seed's figures (seed 003, Fig. 9, 15 and 16).

Matplotlib is imported inside the functions and draws on a ``FigureCanvasAgg`` of its own (no
pyplot: the global backend and open figures are untouched).
"""

from __future__ import annotations

import math
import os
from typing import TYPE_CHECKING

import numpy as np

from virtual_actuators.exceptions import InvalidInputError
from virtual_actuators.experiments.plot_panels import (
    DESIRED_SPEED,
    FORCE_STYLE,
    draw_series,
    draw_state_panel,
    fall_marks,
    key_marks,
    mark_states,
    new_figure,
    set_heading,
    terrain_panel,
)
from virtual_actuators.experiments.walk_log import WalkLog

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from virtual_actuators.experiments.metrics import WalkMetrics


_LAYOUTS = ("auto", "time", "terrain")


def _default_title(log: WalkLog) -> str:
    meta = log.metadata
    parts = [str(meta.get("robot", "walking run"))]
    if "terrain" in meta:
        parts.append(f"terrain {meta['terrain']}")
    elif "terrain_points" not in meta:
        parts.append("level ground")
    speed = meta.get("speed_setpoint_mps")
    if isinstance(speed, int | float | np.number) and math.isfinite(float(speed)):
        parts.append(f"speed set point {float(speed):.2f} m/s")
    return ", ".join(parts)


def _as_log(log: WalkLog | str | os.PathLike[str]) -> WalkLog:
    if isinstance(log, str | os.PathLike):
        log = WalkLog.load_npz(log)
    elif not isinstance(log, WalkLog):
        raise InvalidInputError(f"log: expected a WalkLog or an .npz path, got {log!r}.")
    if len(log) < 2:
        raise InvalidInputError(f"log: an empty run ({len(log)} ticks); need at least 2 to plot.")
    return log


def draw_walk(
    log: WalkLog | str | os.PathLike[str],
    *,
    title: str | None = None,
    layout: str = "auto",
    metrics: WalkMetrics | None = None,
    state_lines: bool = True,
    dpi: float = 120,
    max_points: int = 20000,
    window: tuple[float | None, float | None] | None = None,
) -> Figure:
    """A walking run in the style of the seed's Fig. 9 or Fig. 15/16, on an Agg canvas of its own.

    Save it with `save_figure` (a PNG).

    Args:
        log: The run, or the path of a log saved with `WalkLog.save_npz`.
        title: Figure title; default from the metadata (robot, terrain, speed set point).
        layout: ``"time"`` (Fig. 9), ``"terrain"`` (Fig. 15/16, against x; needs terrain points)
            or ``"auto"`` (``"terrain"`` when the log has terrain points).
        metrics: When given, its `summary` is added under the title.
        state_lines: Mark entries into step and double-support states with vertical lines.
        dpi: Resolution of the figure.
        max_points: Continuous channels are decimated to about this many points.
        window: ``(start, stop)`` simulated seconds to plot (either may be None).

    Raises:
        InvalidInputError: If the log is empty, lacks ``x`` (terrain layout), the layout is
            unknown, the terrain points are malformed or the window holds no tick.
    """
    log = _as_log(log)
    if window is not None:
        log = log.window(*window)
    if layout not in _LAYOUTS:
        raise InvalidInputError(f"layout: {layout!r} is not one of {', '.join(_LAYOUTS)}.")
    terrain = log.terrain_points
    if layout == "auto":
        layout = "terrain" if terrain is not None else "time"
    if layout == "terrain" and terrain is None:
        raise InvalidInputError(
            "layout: 'terrain' needs metadata['terrain_points'] (an (n, 2) array of (x, z))."
        )
    if layout == "terrain" or terrain is not None:
        log.channel("x")  # raises, listing the channels, when the body x is missing
    stride = slice(None, None, max(1, math.ceil(len(log) / max(int(max_points), 2))))
    draw = _time_layout if layout == "time" else _terrain_layout
    fig, axes, xs = draw(log, terrain, stride, dpi)
    if state_lines:
        mark_states(axes, xs, log)
    fall_marks(axes, xs, log, span=layout == "time")
    key_marks(fig, axes[-1])
    heading = title if title is not None else _default_title(log)
    if window is not None:
        heading += "\n" + _window_note(log, against_x=terrain is not None)
    if metrics is not None:
        heading += "\n" + metrics.summary()
    set_heading(fig, heading, fontsize=11)
    return fig


def _window_note(log: WalkLog, *, against_x: bool) -> str:
    """What a windowed plot shows: its simulated seconds, and (against x) the x range."""
    t = log.time
    note = f"window: t = {t[0]:.2f} to {t[-1]:.2f} s"
    x = log["x"] if log.has("x") else np.empty(0)
    finite = x[np.isfinite(x)]
    if against_x and finite.size:
        note += f", where the body walked x = {finite[0]:.2f} to {finite[-1]:.2f} m"
    return note


#: The force panels: ``(channel, label, draw_series options)``.
_FORCES = [
    ("fx", "Fx [N]", {"style": FORCE_STYLE}),
    ("fz", "Fz [N]", {"style": FORCE_STYLE}),
    ("m_pitch", "M_pitch [N m]", {"style": FORCE_STYLE}),
]
_DESIRED = {"setpoint": "xdot_setpoint", "setpoint_style": DESIRED_SPEED}


def _time_layout(
    log: WalkLog, terrain: np.ndarray | None, stride: slice, dpi: float
) -> tuple[Figure, list[Axes], np.ndarray]:
    """Fig. 9: positions, velocity (left) and forces, state (right) against time."""
    rows = 5 if terrain is not None else 4
    fig = new_figure(12, 11.5 if terrain is not None else 9.5, dpi)
    grid = fig.add_gridspec(rows, 2, height_ratios=[1, 1, 1, 1, 1.3][:rows])
    t = log.time
    first = fig.add_subplot(grid[0, 0])
    left = [first] + [fig.add_subplot(grid[r, 0], sharex=first) for r in range(1, 4)]
    right = [fig.add_subplot(grid[r, 1], sharex=first) for r in range(4)]
    axes = left + right
    panels = [
        ("x", "x [m]", {"setpoint": "x_setpoint"}),
        ("z", "hip height z [m]", {"setpoint": "z_setpoint"}),
        ("pitch", "pitch [rad]", {"setpoint": "pitch_setpoint"}),
        ("xdot", "xdot [m/s]", {**_DESIRED, "setpoint_label": "bunny (desired)"}),
        *_FORCES,
    ]
    _draw_panels(left, right, t, log, panels, stride, "time [s]")
    first.set_xlim(float(t[0]), float(t[-1]))
    if terrain is not None:
        has_slope = log.has("global_slope")
        ax_t = fig.add_subplot(grid[4, 0] if has_slope else grid[4, :])
        terrain_panel(ax_t, log, terrain)
        ax_t.set_xlabel("x [m]")
        if has_slope:
            ax_s = fig.add_subplot(grid[4, 1], sharex=ax_t)
            draw_series(ax_s, log["x"], log, "global_slope", "global slope [rad]", stride=stride)
            ax_s.set_xlabel("x [m]")
    return fig, axes, t


def _draw_panels(
    left: list[Axes],
    right: list[Axes],
    xs: np.ndarray,
    log: WalkLog,
    panels: list[tuple[str, str, dict]],
    stride: slice,
    xlabel: str,
) -> None:
    """The series down the left column then the right, the state last; x labelled at the foot."""
    for ax, (name, label, options) in zip(left + right, panels, strict=False):
        draw_series(ax, xs, log, name, label, stride=stride, **options)
    draw_state_panel(right[3], xs, log)
    for ax in left[:3] + right[:3]:
        ax.tick_params(labelbottom=False)
    for ax in (left[3], right[3]):
        ax.set_xlabel(xlabel)


def _terrain_layout(
    log: WalkLog, terrain: np.ndarray, stride: slice, dpi: float
) -> tuple[Figure, list[Axes], np.ndarray]:
    """Fig. 15/16: every panel against the body's x."""
    fig = new_figure(12, 11.5, dpi)
    columns = fig.add_gridspec(1, 2)
    left_grid = columns[0, 0].subgridspec(5, 1, height_ratios=[1.4, 1, 1, 1, 1])
    right_grid = columns[0, 1].subgridspec(4, 1)
    x = log["x"]
    top = fig.add_subplot(left_grid[0, 0])
    terrain_panel(top, log, terrain)
    left = [fig.add_subplot(left_grid[r, 0], sharex=top) for r in range(1, 5)]
    right = [fig.add_subplot(right_grid[r, 0], sharex=top) for r in range(4)]
    panels = [
        ("global_slope", "global slope [rad]", {}),
        ("z", "height above terrain [m]", {"setpoint": "z_setpoint"}),
        ("xdot", "xdot [m/s]", {**_DESIRED, "setpoint_label": "desired"}),
        ("pitch", "pitch [rad]", {"setpoint": "pitch_setpoint"}),
        _FORCES[1],
        _FORCES[0],
        _FORCES[2],
    ]
    top.tick_params(labelbottom=False)
    _draw_panels(left, right, x, log, panels, stride, "x [m] (body position)")
    return fig, [top, *left, *right], x
