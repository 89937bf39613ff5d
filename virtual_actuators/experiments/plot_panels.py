"""The panels of the walk plots: series with set points, states, step marks, falls, terrain.

Shared by `plots` and the hexapod's plots; every function
draws on a matplotlib ``Axes`` it is given (`new_figure` makes a figure without pyplot).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from virtual_actuators.experiments.channels import resolve_step_states

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from virtual_actuators.experiments.walk_log import WalkLog

__all__ = [
    "ACTUAL_STYLE",
    "DESIRED_SPEED",
    "FORCE_STYLE",
    "MAX_FULL_LINES",
    "SETPOINT_STYLE",
    "body_height_world",
    "draw_series",
    "draw_state_panel",
    "fall_marks",
    "new_figure",
    "not_recorded",
    "mark_states",
    "save_figure",
    "terrain_panel",
]

ACTUAL_STYLE = {"color": "C0", "lw": 1.2}
SETPOINT_STYLE = {"color": "C3", "lw": 1.1, "ls": "--"}
DESIRED_SPEED = {"color": "C3", "lw": 1.3, "ls": ":"}
FORCE_STYLE = {"color": "C2", "lw": 1.0}


#: Above this many state transitions, they are marked along the top edge instead of full lines.
MAX_FULL_LINES = 60


def new_figure(width: float, height: float) -> Figure:
    """A matplotlib figure on an Agg canvas of its own (no pyplot), size in inches."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def save_figure(fig: Figure, path: str | os.PathLike[str], dpi: float) -> Path:
    """Save ``fig`` as a PNG at ``path`` (parents created) and return the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=dpi, format="png")
    return path


def not_recorded(ax: Axes, name: str) -> None:
    """Write "NAME: not recorded" in the middle of an empty panel."""
    ax.text(
        0.5,
        0.5,
        f"{name}: not recorded",
        transform=ax.transAxes,
        ha="center",
        va="center",
        color="0.5",
        fontsize=8,
    )


def draw_series(
    ax: Axes,
    xs: np.ndarray,
    log: WalkLog,
    name: str,
    ylabel: str,
    *,
    style: dict[str, Any] = ACTUAL_STYLE,
    setpoint: str | None = None,
    setpoint_style: dict[str, Any] = SETPOINT_STYLE,
    setpoint_label: str = "set point",
    stride: slice = slice(None),
) -> None:
    """Plot channel ``name`` (and its set point) against ``xs``, or say it was not recorded."""
    ax.set_ylabel(ylabel)
    ax.grid(True, lw=0.4, alpha=0.5)
    if not log.has(name):
        not_recorded(ax, name)
        return
    ax.plot(xs[stride], log[name][stride], label=name, **style)
    if setpoint is not None and log.has(setpoint):
        ax.plot(xs[stride], log[setpoint][stride], label=setpoint_label, **setpoint_style)
        ax.legend(loc="upper right", fontsize=7, framealpha=0.7)


def draw_state_panel(ax: Axes, xs: np.ndarray, log: WalkLog) -> None:
    """Draw the state machine state as a step plot with the state names as y tick labels."""
    ax.set_ylabel("state")
    ax.grid(True, axis="x", lw=0.4, alpha=0.5)
    state = log.state
    if not np.any(state >= 0):
        not_recorded(ax, "state")
        return
    # Exact step plot from the change points only (no decimation can hide a short state).
    change = np.flatnonzero(state[1:] != state[:-1]) + 1
    keep = np.concatenate(([0], change, [len(state) - 1]))
    ax.step(xs[keep], state[keep].astype(float), where="post", color="C4", lw=1.3)
    ticks = list(range(len(log.state_names)))
    labels = list(log.state_names)
    if np.any(state < 0):
        ticks.insert(0, -1)
        labels.insert(0, "(unknown)")
    ax.set_yticks(ticks, labels, fontsize=7)
    ax.set_ylim(min(ticks) - 0.5, max(ticks) + 0.5)


def _double_support_states(log: WalkLog) -> tuple[str, ...]:
    names = log.metadata.get("double_support_states")
    if names is None:
        return tuple(s for s in log.state_names if "double" in s.lower())
    if isinstance(names, str):
        names = (names,)
    names = tuple(str(s) for s in names)
    for name in names:
        log.state_index(name)  # raises on an unknown state, listing the valid ones
    return names


def mark_states(axes: Sequence[Axes], xs: np.ndarray, log: WalkLog) -> None:
    """Mark step-state entries (dash-dot) and double-support entries (dotted) on every axis."""
    marks = (
        (log.entries(resolve_step_states(log)), "dashdot"),
        (log.entries(_double_support_states(log)), "dotted"),
    )
    count = sum(ticks.size for ticks, _ in marks)
    # Full-height lines while they stay apart (about one per 8 mm of a 7-inch axis); beyond that
    # (a 60 s run has ~150 transitions) they would hatch the panels solid: short marks along the
    # top edge instead, one row per kind, and the data stays readable.
    dense = count > MAX_FULL_LINES
    for ax in axes:
        for row, (ticks, style) in enumerate(marks):
            if ticks.size:
                low, high = (0.955 - 0.045 * row, 0.995 - 0.045 * row) if dense else (0.0, 1.0)
                ax.vlines(
                    xs[ticks],
                    low,
                    high,
                    transform=ax.get_xaxis_transform(),
                    colors="0.45" if dense else "0.55",
                    linestyles="solid" if dense else style,
                    lw=0.6 if dense else 0.7,
                    zorder=0.5,
                )


def fall_marks(axes: Sequence[Axes], xs: np.ndarray, log: WalkLog, *, span: bool) -> None:
    """Shade (or mark with a line) everything from the first fallen tick on."""
    if not log.has("fallen"):
        return
    fallen = np.nan_to_num(log["fallen"], nan=0.0) > 0.5
    if not np.any(fallen):
        return
    i = int(np.argmax(fallen))
    for ax in axes:
        if span:
            ax.axvspan(xs[i], xs[-1], color="red", alpha=0.08, lw=0)
        ax.axvline(xs[i], color="red", lw=1.0, alpha=0.7)
    axes[0].text(
        xs[i],
        1.0,
        " fell",
        color="red",
        fontsize=8,
        va="bottom",
        transform=axes[0].get_xaxis_transform(),
    )


def body_height_world(log: WalkLog, terrain: np.ndarray) -> np.ndarray | None:
    """The hip's world height: ``z_world``, else terrain height below plus ``z``."""
    if log.has("z_world"):
        return log["z_world"]
    if log.has("z"):
        return np.interp(log["x"], terrain[:, 0], terrain[:, 1]) + log["z"]
    return None


def terrain_panel(
    ax: Axes,
    terrain: np.ndarray,
    body_x: np.ndarray | None,
    body_z: np.ndarray | None,
    *,
    xlim: tuple[float, float] | None = None,
) -> None:
    """Draw the terrain profile (filled) and the body path above it."""
    order = np.argsort(terrain[:, 0], kind="stable")
    tx, tz = terrain[order, 0], terrain[order, 1]
    lo, hi = xlim if xlim is not None else (float(tx[0]), float(tx[-1]))
    inside = (tx >= lo) & (tx <= hi)
    visible = np.concatenate((tz[inside], np.interp([lo, hi], tx, tz)))
    tops = [float(np.max(visible))]
    if body_z is not None and np.any(np.isfinite(body_z)):
        tops.append(float(np.nanmax(body_z)))
    bottom, top = float(np.min(visible)), max(tops)
    pad = 0.08 * max(top - bottom, 0.1)
    ax.fill_between(tx, tz, bottom - 2 * pad, color="0.85", lw=0)
    ax.plot(tx, tz, color="0.3", lw=1.2, label="terrain")
    if body_x is not None and body_z is not None:
        ax.plot(body_x, body_z, label="body (hip) path", **ACTUAL_STYLE)
        ax.legend(loc="upper right", fontsize=7, framealpha=0.7)
    ax.set_xlim(lo, hi)
    ax.set_ylim(bottom - pad, top + pad)
    ax.set_ylabel("world z [m]")
    ax.grid(True, lw=0.4, alpha=0.5)
