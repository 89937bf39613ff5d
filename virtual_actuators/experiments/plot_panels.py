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

from virtual_actuators.exceptions import import_optional
from virtual_actuators.experiments.metrics import first_fall
from virtual_actuators.experiments.walk_log import WalkLog, resolve_step_states

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


ACTUAL_STYLE = {"color": "C0", "lw": 1.2}
SETPOINT_STYLE = {"color": "C3", "lw": 1.1, "ls": "--"}
DESIRED_SPEED = {"color": "C3", "lw": 1.3, "ls": ":"}
FORCE_STYLE = {"color": "C2", "lw": 1.0}


#: Above this many state transitions, they are marked along the top edge instead of full lines.
MAX_FULL_LINES = 60


#: Labels of the step marks (`mark_states`) and the fall line (`fall_marks`).
STEP_LABEL = "step (single support) begins"
DOUBLE_LABEL = "double support begins"
FALL_LABEL = "fell"


def new_figure(width: float, height: float, dpi: float = 100) -> Figure:
    """A matplotlib figure on an Agg canvas of its own (no pyplot), size in inches.

    Raises:
        MissingDependencyError: matplotlib is not installed (the extra ``plots``).
    """
    import_optional("matplotlib", "plots", "Plots")
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=dpi, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def save_figure(fig: Figure, path: str | os.PathLike[str]) -> Path:
    """Save ``fig`` as a PNG at ``path`` at the figure's dpi (parents created)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=fig.dpi, format="png")
    return path


def fit_text(fig: Figure, text: str, fontsize: float) -> str:
    """Break ``text`` into lines no wider than 96 % of the figure's width.

    Lines break after a comma where they can (metric summaries are comma-separated clauses),
    else between words; existing line breaks are kept.
    """
    from matplotlib.text import Text

    probe = Text(0, 0, "", fontsize=fontsize, figure=fig)
    renderer = fig.canvas.get_renderer()
    limit = 0.96 * fig.bbox.width

    def fits(line: str) -> bool:
        probe.set_text(line)
        return probe.get_window_extent(renderer).width <= limit

    lines: list[str] = []
    for paragraph in text.split("\n"):
        line = ""
        for clause in paragraph.split(", "):
            # a clause is split into words only when it does not fit on a line of its own
            pieces = [clause] if fits(clause) else clause.split(" ")
            for k, piece in enumerate(pieces):
                glue = ", " if k == 0 else " "
                if line and fits(line + glue + piece):
                    line += glue + piece
                elif line:
                    lines.append(line + glue.rstrip())
                    line = piece
                else:
                    line = piece
        lines.append(line)
    return "\n".join(lines)


def set_heading(fig: Figure, text: str, fontsize: float = 10) -> None:
    """The figure's title, broken into lines that fit its width (`fit_text`)."""
    fig.suptitle(fit_text(fig, text, fontsize), fontsize=fontsize)


def not_recorded(ax: Axes, name: str) -> None:
    """Write "NAME: not recorded" in the middle of an empty panel."""
    note = {"ha": "center", "va": "center", "color": "0.5", "fontsize": 8}
    ax.text(0.5, 0.5, f"{name}: not recorded", transform=ax.transAxes, **note)


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
    ax.step(xs[keep], state[keep].astype(float), where="post", color="C4", lw=1.3, label="state")
    ticks = list(range(len(log.state_names)))
    labels = list(log.state_names)
    if np.any(state < 0):
        ticks.insert(0, -1)
        labels.insert(0, "(unknown)")
    ax.set_yticks(ticks, labels, fontsize=7)
    ax.set_ylim(min(ticks) - 0.5, max(ticks) + 0.5)


def mark_states(axes: Sequence[Axes], xs: np.ndarray, log: WalkLog) -> None:
    """Mark step-state entries (dash-dot) and double-support entries (dotted) on every axis."""
    keys = ("step_states", "double_support_states")
    steps, double = (resolve_step_states(log.state_names, log.metadata, key=k) for k in keys)
    marks = (
        (log.entries(steps), "dashdot", STEP_LABEL, "0.3"),
        (log.entries(double), "dotted", DOUBLE_LABEL, "0.6"),
    )
    count = sum(ticks.size for ticks, *_ in marks)
    # Full-height lines while they stay apart; beyond that they would hatch the panels solid:
    # short marks along the top edge instead, one row per kind.
    dense = count > MAX_FULL_LINES
    rows = ("top row of ticks", "second row of ticks")
    for ax in axes:
        for row, (ticks, style, label, shade) in enumerate(marks):
            if ticks.size:
                low, high = (0.955 - 0.045 * row, 0.995 - 0.045 * row) if dense else (0.0, 1.0)
                ax.vlines(
                    xs[ticks],
                    low,
                    high,
                    transform=ax.get_xaxis_transform(),
                    colors=shade if dense else "0.55",
                    linestyles="solid" if dense else style,
                    lw=0.6 if dense else 0.7,
                    zorder=0.5,
                    label=f"{label}: {rows[row]}" if dense else label,
                )
        if dense and ax.get_legend() is not None:  # below the rows of ticks, not over them
            ax.get_legend().set_bbox_to_anchor((0.0, 0.0, 1.0, 0.9), transform=ax.transAxes)


def key_marks(fig: Figure, ax: Axes) -> None:
    """A legend under the figure for the marks every panel shares (the ones on ``ax``).

    The step and double-support marks of `mark_states` (lines or rows of ticks) and the
    fall line of `fall_marks`; nothing is added when ``ax`` has none of them.
    """
    from matplotlib.lines import Line2D

    handles = []
    for artist in ax.collections + ax.lines:
        label = artist.get_label()
        if label.startswith((STEP_LABEL, DOUBLE_LABEL)) and label.endswith("row of ticks"):
            color = artist.get_colors()[0]
            handles.append(Line2D([], [], ls="none", marker="|", ms=7, color=color, label=label))
        elif label in (STEP_LABEL, DOUBLE_LABEL):
            style = "-." if label == STEP_LABEL else ":"
            handles.append(Line2D([], [], color="0.55", lw=0.9, ls=style, label=label))
        elif label == FALL_LABEL:
            handles.append(artist)
    if handles:
        fig.legend(handles=handles, loc="outside lower center", ncols=len(handles), fontsize=8)


def fall_marks(axes: Sequence[Axes], xs: np.ndarray, log: WalkLog, *, span: bool) -> None:
    """Shade (or mark with a line) everything from the first fallen tick on."""
    fell, _, i = first_fall(log)
    if not fell:
        return
    for ax in axes:
        if span:
            ax.axvspan(xs[i], xs[-1], color="red", alpha=0.08, lw=0)
        ax.axvline(xs[i], color="red", lw=1.0, alpha=0.7, label=FALL_LABEL)
    above = axes[0].get_xaxis_transform()  # x in data, y in axes units
    axes[0].text(xs[i], 1.0, " fell", color="red", fontsize=8, va="bottom", transform=above)


def body_height_world(log: WalkLog, terrain: np.ndarray) -> np.ndarray | None:
    """The hip's world height: ``z_world``, else terrain height below plus ``z``."""
    if log.has("z_world"):
        return log["z_world"]
    if log.has("z"):
        return np.interp(log["x"], terrain[:, 0], terrain[:, 1]) + log["z"]
    return None


def terrain_panel(ax: Axes, log: WalkLog, terrain: np.ndarray) -> None:
    """Draw the terrain profile (filled) over the walked x range and the body path above it."""
    body_x, body_z = log["x"], body_height_world(log, terrain)
    lo, hi = _x_range(body_x, terrain)
    order = np.argsort(terrain[:, 0], kind="stable")
    tx, tz = terrain[order, 0], terrain[order, 1]
    inside = (tx >= lo) & (tx <= hi)
    visible = np.concatenate((tz[inside], np.interp([lo, hi], tx, tz)))
    tops = [float(np.max(visible))]
    if body_z is not None and np.any(np.isfinite(body_z)):
        tops.append(float(np.nanmax(body_z)))
    bottom, top = float(np.min(visible)), max(tops)
    pad = 0.08 * max(top - bottom, 0.1)
    ax.fill_between(tx, tz, bottom - 2 * pad, color="0.85", lw=0)
    ax.plot(tx, tz, color="0.3", lw=1.2, label="terrain")
    if body_z is not None:
        ax.plot(body_x, body_z, label="body (hip) path", **ACTUAL_STYLE)
        ax.legend(loc="upper right", fontsize=7, framealpha=0.7)
    ax.set_xlim(lo, hi)
    ax.set_ylim(bottom - pad, top + pad)
    ax.set_ylabel("world z [m]")
    ax.grid(True, lw=0.4, alpha=0.5)


def _x_range(x: np.ndarray, terrain: np.ndarray) -> tuple[float, float]:
    """The walked x range with a small margin (the terrain's range if x is not finite)."""
    finite = x[np.isfinite(x)]
    if finite.size == 0:
        return float(np.min(terrain[:, 0])), float(np.max(terrain[:, 0]))
    lo, hi = float(np.min(finite)), float(np.max(finite))
    pad = 0.03 * max(hi - lo, 0.1)
    return lo - pad, hi + pad
