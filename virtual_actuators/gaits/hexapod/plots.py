"""Plot a hexapod walk (`run_hexapod_walk`): the seed's Fig. 6 (VAC 1996) or the body's path."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ...exceptions import InvalidInputError
from ...experiments.metrics import first_fall
from ...experiments.plot_panels import (
    ACTUAL_STYLE,
    FORCE_STYLE,
    SETPOINT_STYLE,
    draw_series,
    draw_state_panel,
    new_figure,
    set_heading,
)
from ...experiments.walk_log import WalkLog

if TYPE_CHECKING:
    from matplotlib.figure import Figure

_LAYOUTS = ("auto", "pendulum", "path")
ARROW_PERIOD = 0.5  # [s] between heading arrows


def draw_hexapod(log: WalkLog, *, layout: str = "auto", summary: str | None = None) -> Figure:
    """A hexapod walk's figure on an Agg canvas of its own, not yet drawn.

    Args:
        log: The run's log (``HexapodResult.log``).
        layout: ``"pendulum"`` (Fig. 6: angle, x velocity, virtual x force, state against
            time), ``"path"`` (the x-y path with heading arrows) or ``"auto"`` (pendulum if any).
        summary: A line under the metadata's title (e.g. ``HexapodMetrics.summary()``).

    Raises:
        InvalidInputError: An unknown layout, an empty log, or ``"pendulum"`` for a log without
            pendulum angles.
    """
    if layout not in _LAYOUTS:
        raise InvalidInputError(f"layout: {layout!r} is not one of {', '.join(_LAYOUTS)}.")
    if not isinstance(log, WalkLog) or len(log) < 2:
        raise InvalidInputError(
            "log: expected a WalkLog of a hexapod walk with two samples or more."
        )
    has_pendulum = log.has("pendulum")
    if layout == "auto":
        layout = "pendulum" if has_pendulum else "path"
    if layout == "pendulum" and not has_pendulum:
        raise InvalidInputError("layout 'pendulum' needs a log with pendulum angles.")
    fig = _pendulum_figure(log) if layout == "pendulum" else _path_figure(log)
    config = log.metadata.get("config", {})
    heading = (
        f"hexapod-walk: {log.metadata.get('robot', 'hexapod')}, "
        f"{config.get('speed', float('nan')):.2f} m/s on {log.metadata.get('terrain', 'flat')}"
    )
    if summary:
        heading += "\n" + summary
    set_heading(fig, heading, fontsize=10)
    return fig


def _pendulum_figure(log: WalkLog) -> Figure:
    fig = new_figure(8.0, 8.0, 120)
    axes = fig.subplots(4, 1, sharex=True)
    t = log.time
    draw_series(axes[0], t, log, "pendulum", "pendulum [rad]")
    desired = {"setpoint_style": SETPOINT_STYLE, "setpoint_label": "desired"}
    draw_series(axes[1], t, log, "vx_heading", "x velocity [m/s]", setpoint="vx_command", **desired)
    draw_series(axes[2], t, log, "fx", "virtual x force [N]", style=FORCE_STYLE)
    draw_state_panel(axes[3], t, log)
    axes[3].set_xlabel("time [s]")
    for ax in axes[:3]:
        ax.axhline(0.0, color="0.6", lw=0.6)
    return fig


def _path_figure(log: WalkLog) -> Figure:
    fig = new_figure(7.5, 7.0, 120)
    ax = fig.subplots()
    x, y, yaw, t = log["x"], log["y"], log["yaw"], log.time
    command = log.metadata.get("command_path")
    tracked = log.has("target_x")
    if command is not None and len(command):
        command = np.asarray(command, dtype=float)
        style = {**SETPOINT_STYLE, "color": "0.35"}
        label = "object's path" if tracked else "command"
        ax.plot(command[:, 0], command[:, 1], label=label, **style)
    ax.plot(x, y, label="body", **ACTUAL_STYLE)
    step = max(1, round(ARROW_PERIOD / max(float(np.median(np.diff(t))), 1e-6)))
    marks = slice(0, None, step)
    extent = max(float(np.ptp(x)), float(np.ptp(y)), 0.3)
    length = 0.05 * extent
    u, v = np.cos(yaw[marks]) * length, np.sin(yaw[marks]) * length
    arrows = {"angles": "xy", "scale_units": "xy", "scale": 1.0, "width": 0.004, "color": "C1"}
    ax.quiver(x[marks], y[marks], u, v, label="heading", **arrows)
    if tracked:
        ax.plot(
            log["target_x"][marks], log["target_y"][marks], "o", ms=3, color="C3", label="object"
        )
    fell, _, first = first_fall(log)
    if fell:
        ax.plot(x[first], y[first], "x", color="red", ms=10, mew=2, label="fell")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.grid(True, lw=0.4, alpha=0.5)
    ax.legend(loc="best", fontsize=8)
    span = math.hypot(float(np.ptp(x)), float(np.ptp(y)))
    ax.set_title(f"path: {span:.2f} m across, {t[-1] - t[0]:.1f} s", fontsize=9)
    return fig
