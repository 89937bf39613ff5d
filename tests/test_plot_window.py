"""Long runs stay readable: time windows on logs and plots, transition marks that thin out."""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.collections import LineCollection

from virtual_actuators.exceptions import InvalidInputError
from virtual_actuators.experiments.plot_panels import (
    MAX_FULL_LINES,
    mark_states,
    new_figure,
    save_figure,
)
from virtual_actuators.experiments.plots import draw_walk
from virtual_actuators.experiments.walk_log import WalkLog


def plot_walk(log, path, **options):
    """draw_walk's figure saved as a PNG at ``path`` (as the walks' --plot does)."""
    return save_figure(draw_walk(log, **options), path)


STATES = ("double_support", "left_support", "right_support")


def _walk(seconds: float, step: float = 0.4) -> WalkLog:
    t = np.arange(0.0, seconds, 1e-3)
    phase = np.mod(t, 2 * step) / step  # 0..2
    state = np.where(np.mod(phase, 1.0) < 0.2, 0, np.where(phase < 1.0, 1, 2))
    return WalkLog(
        data={
            "time": t,
            "x": 0.5 * t,
            "z": 0.7 + 0.01 * np.sin(t),
            "pitch": 0.0 * t,
            "xdot": 0.5 + 0.0 * t,
        },
        state=state,
        state_names=STATES,
        metadata={"step_states": ["left_support", "right_support"]},
    )


def test_window_keeps_the_ticks_in_range():
    log = _walk(10.0)
    part = log.window(2.0, 3.5)
    assert part.time[0] == pytest.approx(2.0) and part.time[-1] == pytest.approx(3.5)
    assert np.array_equal(part["x"], log["x"][(log.time >= 2.0) & (log.time <= 3.5)])
    assert part.state_names == log.state_names
    assert len(log.window(None, 1.0)) == 1001
    with pytest.raises(InvalidInputError, match="covers 0.000..9.999 s"):
        log.window(20.0, 30.0)
    with pytest.raises(InvalidInputError, match="after stop"):
        log.window(3.0, 2.0)


def _mark_heights(log: WalkLog) -> list[float]:
    fig = new_figure(7, 3)
    ax = fig.add_subplot()
    mark_states([ax], log.time, log)
    heights = []
    for collection in ax.collections:
        if isinstance(collection, LineCollection):
            heights += [abs(seg[1, 1] - seg[0, 1]) for seg in collection.get_segments()]
    return heights


def test_marks_are_full_lines_on_short_runs_and_short_ticks_on_long_ones():
    short, long = _walk(6.0), _walk(60.0)
    assert len(short.entries(STATES[1:])) + len(short.entries(STATES[:1])) <= MAX_FULL_LINES
    assert set(_mark_heights(short)) == {1.0}
    heights = _mark_heights(long)
    assert len(heights) > 200 and max(heights) < 0.05


def test_plot_with_a_window(tmp_path):
    path = plot_walk(_walk(60.0), tmp_path / "w.png", layout="time", window=(10.0, 14.0))
    assert path.read_bytes().startswith(b"\x89PNG")
    with pytest.raises(InvalidInputError, match="holds no tick"):
        plot_walk(_walk(5.0), tmp_path / "x.png", layout="time", window=(10.0, 14.0))
