"""Every figure the library draws shows all its text and names its marks.

Each figure is rendered on Agg (no file needed) and checked by :mod:`figure_checks`: every text
drawn lies inside the image, every axis showing numbers or names is labelled (colour bars too),
and every line beyond a panel's own series (step marks, rows of ticks, fall lines, set points)
has a legend entry. Fast tests draw logs recorded tick by tick with the real
:class:`~virtual_actuators.experiments.recorder.Recorder`; the slow ones draw short real walks of
every registered gait.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from figure_checks import assert_figure_fits, render

from virtual_actuators.demos.sweep import SweepResult, draw_success_map
from virtual_actuators.experiments.plot_panels import (
    DOUBLE_LABEL,
    FALL_LABEL,
    STEP_LABEL,
    fit_text,
    new_figure,
)
from virtual_actuators.experiments.plots import draw_walk
from virtual_actuators.experiments.recorder import Recorder
from virtual_actuators.experiments.walk_log import STANDARD_CHANNELS, WalkLog
from virtual_actuators.gaits.balance.walk import draw_balance_log
from virtual_actuators.gaits.hexapod.plots import draw_hexapod

STATES = ("double_support", "left_support", "left_support_2", "right_support", "right_support_2")
PROFILE = np.array([[-1.0, 0.4], [1.0, 0.4], [2.6, 0.0], [4.2, 0.0], [5.6, 0.45], [9.0, 0.45]])
#: A real summary line of ``demo hexapod-walk --pendulum --speed 0.2 --duration 4`` (the one
#: that was cut on both sides of Fig. 6).
HEXAPOD_SUMMARY = (
    "4.0 s, 12 steps, speed 0.20 m/s (set 0.20), direction error 0.000, heading drift 0.001, "
    "pendulum peak 0.049, pendulum rms 0.000, 1.19x real time (MuJoCo alone 6.6x)"
)


def recorded_walk(seconds: float, *, terrain: bool = False, fall_at: float = math.inf) -> WalkLog:
    """A planar walk at 0.4 m/s, recorded tick by tick at 100 Hz, steps of 0.5 s."""
    metadata = {"robot": "spring_flamingo", "speed_setpoint_mps": 0.4}
    metadata["step_states"] = ["left_support", "right_support"]
    metadata["double_support_states"] = ["double_support"]
    if terrain:
        metadata |= {"terrain": "profile-one", "terrain_points": PROFILE}
    recorder = Recorder(STANDARD_CHANNELS, state_names=STATES, metadata=metadata)
    w = 2 * math.pi / 0.5
    for t in np.arange(0.0, seconds, 0.01):
        local = math.fmod(t, 0.5) / 0.5
        state = 0 if local >= 0.8 else (2 if local >= 0.7 else 1)
        if state and math.fmod(t, 1.0) >= 0.5:
            state += 2
        x = 0.4 * t + 0.01 * math.sin(w * t)
        ground = float(np.interp(x, PROFILE[:, 0], PROFILE[:, 1])) if terrain else 0.0
        recorder.append(
            state=state,
            time=t,
            x=x,
            z=0.7 + 0.01 * math.sin(w * t),
            z_world=ground + 0.7 + 0.01 * math.sin(w * t),
            pitch=0.03 * math.sin(w * t),
            xdot=0.4 + 0.01 * w * math.cos(w * t),
            z_setpoint=0.7,
            pitch_setpoint=0.0,
            xdot_setpoint=0.4,
            fx=5.0 * math.cos(w * t),
            fz=110.0 + 10.0 * math.sin(w * t),
            m_pitch=3.0 * math.sin(w * t),
            global_slope=0.1 * math.sin(0.3 * t) if terrain else math.nan,
            fallen=float(t >= fall_at),
        )
    return recorder.to_log()


def legend_texts(figure) -> list[str]:
    legends = [*figure.legends, *(ax.get_legend() for ax in figure.axes if ax.get_legend())]
    return [text.get_text() for legend in legends for text in legend.get_texts()]


@pytest.mark.parametrize(
    ("seconds", "layout", "dense"),
    [(6.0, "time", False), (60.0, "time", True), (12.0, "terrain", False)],
)
def test_walk_figures_fit_and_key_their_marks(seconds, layout, dense):
    log = recorded_walk(seconds, terrain=layout == "terrain")
    figure = draw_walk(log, layout=layout)
    renderer = assert_figure_fits(figure).renderer
    keys = legend_texts(figure)
    for label in (STEP_LABEL, DOUBLE_LABEL):
        shown = [key for key in keys if key.startswith(label)]
        assert len(shown) == 1, keys
        assert ("row of ticks" in shown[0]) == dense
    if dense:  # the panels' legends sit below the two rows of ticks along their top edge
        for ax in (ax for ax in figure.axes if ax.get_legend() is not None):
            box = ax.get_window_extent(renderer)
            top = ax.get_legend().get_window_extent(renderer).y1
            assert top <= box.y0 + 0.9 * box.height + 0.5


def test_a_fall_is_keyed_and_its_note_stays_inside():
    figure = draw_walk(recorded_walk(8.0, fall_at=5.0), layout="time")
    report = assert_figure_fits(figure)
    assert FALL_LABEL in legend_texts(figure)
    assert " fell" in report.texts


@pytest.mark.parametrize(
    ("layout", "terrain"), [("time", False), ("time", True), ("terrain", True)]
)
def test_a_window_is_named_in_seconds_and_against_x_in_metres(layout, terrain):
    log = recorded_walk(12.0, terrain=terrain)
    report = assert_figure_fits(draw_walk(log, layout=layout, window=(4.0, 8.0)))
    title = next(text for text in report.texts if "window" in text)
    part = log.window(4.0, 8.0)
    assert f"t = {part.time[0]:.2f} to {part.time[-1]:.2f} s" in title
    metres = f"x = {part['x'][0]:.2f} to {part['x'][-1]:.2f} m"
    assert (metres in title) == terrain  # a terrain adds panels against x
    x_labels = {ax.get_xlabel() for ax in draw_walk(log, layout=layout).axes} - {""}
    expected = {"time [s]", "x [m]"} if terrain else {"time [s]"}
    assert x_labels == ({"x [m] (body position)"} if layout == "terrain" else expected)


def test_a_long_title_and_summary_wrap_inside_the_figure():
    log = recorded_walk(3.0)
    figure = draw_walk(log, layout="time", title="a title " * 40, dpi=80)
    assert_figure_fits(figure)


def sweep_results(speeds, terrains, seeds) -> list[SweepResult]:
    return [
        SweepResult("flamingo-slopes", s, t, k, (k + i) % 3 == 0, 20.0, 8.0, s, 20, 3.0)
        for i, s in enumerate(speeds)
        for t in terrains
        for k in range(seeds)
    ]


@pytest.mark.parametrize(
    ("speeds", "terrains"),
    [
        ([0.3], ["flat"]),
        ([0.3, 0.4, 0.5, 0.6], ["profile-one", "profile-two"]),  # the README's sweep
        (list(np.round(np.arange(0.1, 1.35, 0.05), 2)), ["flat", "a-very-long-terrain-name"]),
    ],
)
def test_sweep_map_fits_and_labels_its_colour_bar(speeds, terrains):
    figure = draw_success_map(sweep_results(speeds, terrains, seeds=3))
    assert_figure_fits(figure)
    heat, bar = figure.axes
    assert bar.get_ylabel() == "walks that did not fall"
    assert heat.get_ylabel() == "terrain"


def hexapod_log(seconds: float = 3.0) -> WalkLog:
    """Fig. 6's channels and the path's, recorded tick by tick at 200 Hz."""
    names = ("time", "x", "y", "yaw", "pendulum", "vx_heading", "vx_command", "fx", "fallen")
    metadata = {"robot": "hexapod_pendulum", "config": {"speed": 0.2}, "terrain": "flat"}
    metadata["command_path"] = [[0.2 * t, 0.0] for t in np.arange(0.0, seconds, 0.5)]
    recorder = Recorder(names, state_names=("tripod_a", "double_a", "tripod_b", "double_b"))
    recorder.metadata.update(metadata)
    for t in np.arange(0.0, seconds, 0.005):
        recorder.append(
            state=int(4 * math.fmod(t, 0.7) / 0.7),
            time=t,
            x=0.2 * t,
            y=0.01 * math.sin(t),
            yaw=0.01 * t,
            pendulum=0.05 * math.exp(-t) * math.sin(6 * t),
            vx_heading=0.2 * (1 - math.exp(-3 * t)),
            vx_command=0.2,
            fx=2.0 * math.exp(-t),
            fallen=0.0,
        )
    return recorder.to_log()


@pytest.mark.parametrize("layout", ["pendulum", "path"])
def test_hexapod_figures_fit_with_the_summary(layout):
    figure = draw_hexapod(hexapod_log(), layout=layout, summary=HEXAPOD_SUMMARY)
    report = assert_figure_fits(figure)
    heading = next(text for text in report.texts if text.startswith("hexapod-walk"))
    assert heading.replace(",\n", ", ").endswith(HEXAPOD_SUMMARY)


def test_balance_figure_fits_with_a_long_summary():
    names = ("time", "x", "y", "z", "roll", "pitch", "vx", "vy")
    recorder = Recorder(names)
    for t in np.arange(0.0, 2.0, 0.01):
        wave = 1e-4 * math.exp(-t) * math.sin(9 * t)
        recorder.append(time=t, x=wave, y=-wave, z=1.02 + wave, roll=wave, pitch=wave, vx=wave)
    summary = "talos stood for 1.99 s: tilt <= 0.000 rad, " * 4 + "0.75x real time"
    assert_figure_fits(draw_balance_log(recorder.to_log(), summary=summary))


@pytest.mark.parametrize("fontsize", [7, 10, 14])
def test_fit_text_breaks_at_commas_within_the_width(fontsize):
    figure = new_figure(5.0, 3.0)
    text = HEXAPOD_SUMMARY + ", " + "x" * 90 + " " + "word " * 30
    lines = fit_text(figure, text, fontsize).split("\n")
    probe = figure.text(0, 0, "", fontsize=fontsize)
    renderer = render(figure)
    widths = []
    for line in lines:
        probe.set_text(line)
        widths.append(probe.get_window_extent(renderer).width)
    limit = 0.96 * figure.bbox.width
    # one word wider than the figure is the only line allowed past the limit
    wide = [line for width, line in zip(widths, lines, strict=True) if width > limit]
    assert wide == ["x" * 90], wide
    assert " ".join(lines).split() == text.split()  # nothing lost, nothing added
    assert lines[0].endswith(",")  # the summary's clauses break after their commas


# -- real walks (MuJoCo) ---------------------------------------------------------------------------
def _draw(name: str, result):
    from virtual_actuators.gaits.balance.walk import draw_balance
    from virtual_actuators.gaits.hexapod.walk import draw_hexapod_walk
    from virtual_actuators.gaits.legged.walk import draw_legged_walk
    from virtual_actuators.gaits.planar_walk import draw_planar_walk

    drawers = {
        "turkey-walk": lambda r: draw_planar_walk(r, (0.5, None)),
        "flamingo-slopes": draw_planar_walk,
        "hexapod-walk": draw_hexapod_walk,
        "legged": draw_legged_walk,
        "balance": draw_balance,
    }
    return drawers[name](result)


WALK_RUNS = {
    "turkey-walk": [{"duration": 2.0}],
    "flamingo-slopes": [{"duration": 2.0}],
    "hexapod-walk": [{"duration": 1.0, "pendulum": True}, {"duration": 1.0, "yaw_rate": 0.6}],
    "legged": [{"duration": 0.5}],
    "balance": [{"duration": 0.5}],
}


def test_every_registered_walk_has_a_figure_test():
    from virtual_actuators.gaits.registry import WALKS

    assert set(WALKS) == set(WALK_RUNS)


@pytest.mark.slow
@pytest.mark.parametrize(
    ("name", "options"), [(name, run) for name, runs in WALK_RUNS.items() for run in runs]
)
def test_real_walk_figures_fit(name, options):
    from virtual_actuators.gaits.registry import run_walk

    result = run_walk(name, progress=False, **options)
    assert_figure_fits(_draw(name, result))
