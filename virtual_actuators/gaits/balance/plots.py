"""Plot a balance run: the body's drift, height, tilt and velocity against time."""

from __future__ import annotations

from typing import TYPE_CHECKING

from ...experiments.plot_panels import FORCE_STYLE, new_figure, set_heading
from ...experiments.walk_log import WalkLog

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["draw_balance_log"]

PANELS = (
    (("x", "y"), "drift [m]", True),
    (("z",), "height [m]", False),
    (("roll", "pitch"), "tilt [rad]", False),
    (("vx", "vy"), "velocity [m/s]", False),
)


def draw_balance_log(log: WalkLog, summary: str = "") -> Figure:
    """The body's drift, height, roll and pitch, and horizontal velocity, ``summary`` its title."""
    figure = new_figure(8.0, 8.0, dpi=110)
    axes = figure.subplots(len(PANELS), 1, sharex=True)
    t = log.time
    for ax, (names, label, relative) in zip(axes, PANELS, strict=True):
        for k, name in enumerate(names):
            values = log[name] - log[name][0] if relative else log[name]
            style = FORCE_STYLE if k else {"color": "C0", "lw": 1.2}
            ax.plot(t, values, label=name, **style)
        ax.set_ylabel(label)
        ax.grid(True, lw=0.4, alpha=0.5)
        ax.legend(loc="upper right", fontsize=7)
    axes[-1].set_xlabel("time [s]")
    if summary:
        set_heading(figure, summary, fontsize=9)
    return figure
