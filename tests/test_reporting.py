"""Recording, metrics and plots of walking runs (virtual_actuators.simulation.{recording,...}).

Append cost, measured once by hand (not asserted; timings are machine dependent): on the dev
machine ``Recorder.append`` with the 15 standard channels as keyword arguments plus a state costs
about 2.6-3.2 µs per tick, ``append_row`` about 0.6 µs (list) to 1.6 µs (ndarray), including the
amortised doubling; e.g.

    rec = Recorder(STANDARD_CHANNELS, state_names=("a", "b"), capacity=16)
    kw = {c: 0.1 for c in STANDARD_CHANNELS}
    timeit.timeit(lambda: rec.append(state=1, **kw), number=200_000) / 200_000  # ~3e-6 s
"""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from virtual_actuators.exceptions import InvalidInputError
from virtual_actuators.experiments.metrics import WalkMetrics, compute_metrics, write_json
from virtual_actuators.experiments.plot_panels import save_figure
from virtual_actuators.experiments.plots import draw_walk
from virtual_actuators.experiments.recorder import Recorder
from virtual_actuators.experiments.walk_log import STANDARD_CHANNELS, WalkLog, default_step_states


def log_from_arrays(*, state=None, state_names=(), metadata=None, **channels) -> WalkLog:
    """A WalkLog of whole arrays (``state`` None: all unknown)."""
    state = np.zeros(0, dtype=np.int64) if state is None else np.asarray(state)
    return WalkLog(dict(channels), state, tuple(state_names), dict(metadata or {}))


def plot_walk(log, path, **options):
    """draw_walk's figure saved as a PNG at ``path`` (as the walks' --plot does)."""
    return save_figure(draw_walk(log, **options), path)


PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
STATES = ("double_support", "left_support", "left_support_2", "right_support", "right_support_2")
STEP_STATES = ("left_support", "right_support")


# -- synthetic runs ----------------------------------------------------------------------------
def gait_states(t: np.ndarray, step_time: float = 0.5) -> np.ndarray:
    """Turkey walking: left support, buffer, double, right support, buffer, double, ..."""
    ms = np.round(t * 1000).astype(np.int64)  # integer milliseconds: exact phase boundaries
    step_ms = round(step_time * 1000)
    local = np.mod(ms, step_ms)
    left = np.mod(ms, 2 * step_ms) < step_ms
    state = np.where(left, 1, 3)
    state = np.where(local >= 0.7 * step_ms, np.where(left, 2, 4), state)
    state = np.where(local >= 0.8 * step_ms, 0, state)
    return state.astype(np.int64)


def turkey_log(duration: float = 6.0, dt: float = 0.002) -> WalkLog:
    t = np.arange(0.0, duration + dt / 2, dt)
    w = 2 * np.pi / 0.5
    x = 0.5 * t + 0.01 * np.sin(w * t)
    return log_from_arrays(
        time=t,
        x=x,
        z=0.54 + 0.012 * np.sin(w * t),
        z_world=0.54 + 0.012 * np.sin(w * t),
        pitch=0.06 * np.sin(w * t + 0.3),
        xdot=0.5 + 0.01 * w * np.cos(w * t),
        x_setpoint=np.full_like(t, np.nan),
        z_setpoint=np.full_like(t, 0.54),
        pitch_setpoint=np.zeros_like(t),
        xdot_setpoint=np.where(gait_states(t) == 0, 0.5, np.nan),
        fx=np.where(gait_states(t) == 0, 5.0 * np.cos(w * t), 0.0),
        fz=98.0 + 10.0 * np.sin(w * t),
        m_pitch=2.0 * np.sin(w * t + 1.0),
        global_slope=np.full_like(t, np.nan),
        fallen=np.zeros_like(t),
        state=gait_states(t),
        state_names=STATES,
        metadata={
            "robot": "spring_turkey",
            "speed_setpoint_mps": 0.5,
            "nominal_height_m": 0.54,
            "step_states": list(STEP_STATES),
            "double_support_states": ["double_support"],
        },
    )


PROFILE = np.array(
    [[-1.0, 0.0], [2.0, 0.0], [4.0, 0.35], [6.0, 0.35], [8.0, 0.0], [9.0, 0.1], [12.0, 0.1]]
)


def flamingo_log(duration: float = 28.0, dt: float = 0.01) -> WalkLog:
    t = np.arange(0.0, duration + dt / 2, dt)
    w = 2 * np.pi / 0.7
    x = 0.4 * t + 0.01 * np.sin(w * t)
    ground = np.interp(x, PROFILE[:, 0], PROFILE[:, 1])
    slope = np.arctan(np.gradient(ground, x))
    height = 0.74 - 0.1 * slope
    z = height + 0.015 * np.sin(w * t)
    return log_from_arrays(
        time=t,
        x=x,
        z=z,
        z_world=ground + z,
        pitch=0.05 * np.sin(w * t),
        xdot=0.4 + 0.01 * w * np.cos(w * t),
        x_setpoint=np.full_like(t, np.nan),
        z_setpoint=height,
        pitch_setpoint=np.zeros_like(t),
        xdot_setpoint=np.full_like(t, 0.4),
        fx=3.0 * np.cos(w * t),
        fz=118.0 + 15.0 * np.sin(w * t),
        m_pitch=4.0 * np.sin(w * t),
        global_slope=slope,
        fallen=np.zeros_like(t),
        state=gait_states(t, step_time=0.7),
        state_names=STATES,
        metadata={
            "robot": "spring_flamingo",
            "terrain": "profile_one",
            "terrain_points": PROFILE,
            "speed_setpoint_mps": 0.4,
            "step_states": list(STEP_STATES),
        },
    )


def ramp_log(duration: float = 10.0, dt: float = 0.01, **extra: np.ndarray) -> WalkLog:
    t = np.arange(round(duration / dt) + 1) * dt
    channels = {"time": t, "x": 0.5 * t, "xdot": np.full_like(t, 0.5)}
    channels.update({k: v(t) if callable(v) else v for k, v in extra.items()})
    return log_from_arrays(**channels)


# -- recorder ----------------------------------------------------------------------------------
def test_recorder_grows_beyond_capacity_and_keeps_rows_in_order():
    rec = Recorder(("time", "x", "fz"), state_names=("a", "b", "c"), capacity=3)
    for i in range(1000):
        if i % 2:
            rec.append(time=i * 0.001, x=float(i), fz=-i, state=i % 3)
        else:
            rec.append_row([i * 0.001, float(i), -i], state=("a", "b", "c")[i % 3])
    assert len(rec) == 1000 and rec.capacity >= 1000
    log = rec.to_log()
    assert len(log) == 1000
    np.testing.assert_array_equal(log["x"], np.arange(1000.0))
    np.testing.assert_array_equal(log.channel("fz"), -np.arange(1000.0))
    np.testing.assert_allclose(log.time, np.arange(1000) * 0.001)
    np.testing.assert_array_equal(log["state"], np.arange(1000) % 3)
    assert log.state_names == ("a", "b", "c")


def test_recorder_defaults_standard_channels_missing_values_nan_and_copies():
    rec = Recorder(state_names=STATES, metadata={"robot": "spring_turkey"})
    assert rec.channels == STANDARD_CHANNELS
    rec.append(time=0.0, x=0.1, fallen=False)
    rec.append(time=0.01, x=0.2, z=0.54)
    log = rec.to_log()
    assert math.isnan(log["z"][0]) and log["z"][1] == 0.54
    assert log["fallen"][0] == 0.0
    np.testing.assert_array_equal(log.state, [-1, -1])  # state not given: unknown
    rec.append(time=0.02, x=0.3)
    rec.metadata["robot"] = "changed"
    assert len(log) == 2 and log.metadata["robot"] == "spring_turkey"
    assert "state" in log and "x" in log and "nope" not in log
    assert not log.has("pitch") and log.has("x")


def test_recorder_validates_channels_and_states():
    rec = Recorder(("time", "x", "z"), state_names=("double", "single"))
    with pytest.raises(InvalidInputError) as err:
        rec.append(time=0.0, xx=1.0)
    message = str(err.value)
    assert "'xx'" in message and all(repr(c) in message for c in ("time", "x", "z"))
    assert len(rec) == 0  # nothing recorded by the failed tick
    with pytest.raises(InvalidInputError, match="'hovering'.*'double', 'single'"):
        rec.append(time=0.0, state="hovering")
    with pytest.raises(InvalidInputError, match="state"):
        rec.append(time=0.0, state=2)
    with pytest.raises(InvalidInputError, match="channel 'x'"):
        rec.append(time=0.0, x="fast")
    with pytest.raises(InvalidInputError, match="expected 3 values"):
        rec.append_row([0.0, 1.0])
    assert len(rec) == 0
    with pytest.raises(InvalidInputError, match="'time' is required"):
        Recorder(("x", "z"))
    with pytest.raises(InvalidInputError, match="'x' is given twice"):
        Recorder(("time", "x", "x"))
    with pytest.raises(InvalidInputError, match="capacity"):
        Recorder(("time",), capacity=0)
    rec.append(time=0.0, x=1.0, state="single")
    log = rec.to_log()
    with pytest.raises(InvalidInputError, match="'pitch'.*'time', 'x', 'z', 'state'"):
        log.channel("pitch")
    with pytest.raises(InvalidInputError, match="'pitch'"):
        log["pitch"]


def test_walklog_validates_arrays():
    with pytest.raises(InvalidInputError, match="channel 'x': 2 samples"):
        log_from_arrays(time=[0.0, 1.0, 2.0], x=[0.0, 1.0])
    with pytest.raises(InvalidInputError, match="'time' channel is required"):
        log_from_arrays(x=[0.0, 1.0])
    with pytest.raises(InvalidInputError, match="'time': decreases at tick 2"):
        log_from_arrays(time=[0.0, 1.0, 0.5])
    with pytest.raises(InvalidInputError, match="state: 5 at tick 1"):
        log_from_arrays(time=[0.0, 1.0], state=[0, 5], state_names=("a", "b"))


def test_npz_round_trip(tmp_path):
    rec = Recorder(("time", "x", "z", "tau_left_knee"), state_names=STATES, capacity=2)
    for i in range(50):
        rec.append(time=i * 0.01, x=0.005 * i, tau_left_knee=np.float64(i), state=i % 5)
    rec.metadata.update(
        robot="spring_flamingo",
        terrain_points=PROFILE,
        speed_setpoint_mps=np.float64(0.4),
        step_states=("left_support", "right_support"),
        seed=None,
        notes={"k_height": 0.85},
    )
    log = rec.to_log()
    path = log.save_npz(tmp_path / "runs" / "walk.log")  # any name; no suffix is added
    assert path == tmp_path / "runs" / "walk.log" and path.is_file()
    back = WalkLog.load_npz(path)
    assert back.channels == log.channels and back.state_names == STATES
    for name in log.channels:
        np.testing.assert_array_equal(back[name], log[name])  # NaN == NaN here
    np.testing.assert_array_equal(back.state, log.state)
    assert back.state.dtype == np.int64
    np.testing.assert_array_equal(back.metadata["terrain_points"], PROFILE)
    np.testing.assert_array_equal(back.terrain_points, PROFILE)
    assert back.metadata["robot"] == "spring_flamingo"
    assert back.metadata["speed_setpoint_mps"] == 0.4
    assert back.metadata["step_states"] == ["left_support", "right_support"]
    assert back.metadata["seed"] is None and back.metadata["notes"] == {"k_height": 0.85}
    assert compute_metrics(back).to_dict() == compute_metrics(log).to_dict()


def test_npz_rejects_unstorable_metadata_and_foreign_files(tmp_path):
    log = log_from_arrays(time=[0.0, 1.0], metadata={"callback": print})
    with pytest.raises(InvalidInputError, match="metadata\\['callback'\\]"):
        log.save_npz(tmp_path / "bad.npz")
    np.savez(tmp_path / "other.npz", a=np.zeros(3))
    with pytest.raises(InvalidInputError, match="not a walk log"):
        WalkLog.load_npz(tmp_path / "other.npz")


# -- metrics -----------------------------------------------------------------------------------
def test_constant_speed_ramp():
    m = compute_metrics(ramp_log(), startup_s=2.0)
    assert m.mean_speed_mps == pytest.approx(0.5, rel=1e-12, abs=0)
    assert m.speed_std_mps == pytest.approx(0.0, abs=1e-15)
    assert m.distance_m == pytest.approx(5.0, rel=1e-12)
    assert m.duration_s == pytest.approx(10.0, rel=1e-12)
    assert m.window_start_s == pytest.approx(2.0) and m.window_end_s == pytest.approx(10.0)
    assert not m.fell and m.fall_time_s is None
    assert m.height_dev_m is None and m.pitch_max_abs_rad is None and m.steps == 0
    assert m.realtime_factor is None and m.speed_setpoint_mps is None


def test_run_ending_before_startup_uses_whole_run():
    m = compute_metrics(ramp_log(duration=1.0), startup_s=2.0)
    assert m.mean_speed_mps == pytest.approx(0.5, rel=1e-12)
    assert m.window_start_s == 0.0 and m.window_end_s == pytest.approx(1.0)


def test_height_bump_after_startup_counts_and_before_startup_is_ignored():
    def z(t):
        out = np.full_like(t, 0.54)
        out[(t >= 1.0) & (t < 1.2)] += 0.10  # during start-up: ignored
        out[(t >= 5.0) & (t < 5.1)] += 0.03  # after start-up
        return out

    log = ramp_log(z=z, z_setpoint=lambda t: np.full_like(t, 0.54))
    m = compute_metrics(log, startup_s=2.0)
    assert m.height_dev_m == pytest.approx(0.03, rel=1e-9)
    assert compute_metrics(log, startup_s=0.0).height_dev_m == pytest.approx(0.10, rel=1e-9)
    assert 0.54 < m.height_mean_m < 0.541


def test_nan_setpoints_and_samples_are_ignored():
    def setpoint(t):
        out = np.full_like(t, 0.54)
        out[t > 6.0] = np.nan  # spring inactive
        return out

    def z(t):
        out = np.full_like(t, 0.54)
        out[t > 6.0] = 0.2  # far from 0.54, but no set point there
        out[(t > 3.0) & (t < 3.5)] = 0.56
        return out

    def pitch(t):
        out = np.full_like(t, 0.02)
        out[::7] = np.nan
        out[500] = -0.08
        return out

    log = ramp_log(
        z=z,
        z_setpoint=setpoint,
        pitch=pitch,
        pitch_setpoint=lambda t: np.full_like(t, np.nan),
        xdot_setpoint=lambda t: np.where(np.mod(t, 1.0) < 0.5, 0.45, np.nan),
    )
    m = compute_metrics(log)
    assert m.height_dev_m == pytest.approx(0.02, rel=1e-9)
    assert m.pitch_max_abs_rad == pytest.approx(0.08)
    assert m.pitch_dev_rad is None
    assert m.speed_setpoint_mps == pytest.approx(0.45)  # no metadata: median of the bunny


def test_fall_sets_fell_and_time():
    def fallen(t):
        return (t >= 4.0 - 1e-9).astype(float)

    def z(t):
        return np.where(t >= 4.0 - 1e-9, 0.05, 0.54)

    log = ramp_log(fallen=fallen, z=z, z_setpoint=lambda t: np.full_like(t, 0.54))
    m = compute_metrics(log)
    assert m.fell is True and m.fall_time_s == pytest.approx(4.0)
    assert m.height_dev_m == pytest.approx(0.0)  # statistics stop at the fall
    assert m.window_end_s == pytest.approx(3.99)
    assert m.duration_s == pytest.approx(10.0) and m.distance_m == pytest.approx(5.0)
    assert "FELL at 4.00 s" in m.summary()
    down = compute_metrics(ramp_log(fallen=lambda t: np.ones_like(t)))
    assert down.fell and down.fall_time_s == 0.0 and down.mean_speed_mps is None
    assert down.window_start_s is None and down.steps == 0 and down.distance_m == 5.0


def test_steps_counted_from_state_entries():
    log = turkey_log(duration=6.0)
    m = compute_metrics(log, wall_time_s=3.0)
    # Starts in left support (not an entry), then one entry every 0.5 s: 0.5, 1.0, ..., 6.0.
    assert m.steps == 12
    assert m.step_time_mean_s == pytest.approx(0.5, abs=1e-9)
    assert m.realtime_factor == pytest.approx(2.0)
    assert m.step_states == STEP_STATES
    assert m.speed_setpoint_mps == 0.5
    assert m.mean_speed_mps == pytest.approx(0.5, abs=0.01)
    assert m.height_dev_m == pytest.approx(0.012, abs=1e-4)
    assert m.pitch_max_abs_rad == pytest.approx(0.06, abs=1e-4)
    # The same answer from the default guess, and with explicit names.
    bare = log_from_arrays(state=log.state, state_names=STATES, time=log.time, x=log["x"])
    assert default_step_states(STATES) == STEP_STATES
    assert compute_metrics(bare).steps == 12
    assert compute_metrics(bare, step_states=["double_support"]).steps == 12
    with pytest.raises(InvalidInputError, match="'flight'.*'double_support'"):
        compute_metrics(bare, step_states=["flight"])


def test_metrics_reject_empty_runs_and_bad_arguments():
    with pytest.raises(InvalidInputError, match="empty run"):
        compute_metrics(log_from_arrays(time=[], x=[]))
    with pytest.raises(InvalidInputError, match="empty run"):
        compute_metrics(Recorder(("time", "x")).to_log())
    with pytest.raises(InvalidInputError, match="'x'"):
        compute_metrics(log_from_arrays(time=[0.0, 1.0], z=[0.5, 0.5]))
    with pytest.raises(InvalidInputError, match="startup_s"):
        compute_metrics(ramp_log(), startup_s=-1.0)
    with pytest.raises(InvalidInputError, match="wall_time_s"):
        compute_metrics(ramp_log(), wall_time_s=0.0)


def test_json_has_every_key_and_serialises(tmp_path):
    m = compute_metrics(turkey_log(duration=3.0), wall_time_s=1.5)
    path = write_json(m, tmp_path / "out" / "metrics.json")
    text = path.read_text()
    data = json.loads(text)
    required = {
        "fell",
        "fall_time_s",
        "duration_s",
        "distance_m",
        "mean_speed_mps",
        "speed_std_mps",
        "height_dev_m",
        "height_mean_m",
        "pitch_max_abs_rad",
        "steps",
        "step_time_mean_s",
        "realtime_factor",
        "speed_setpoint_mps",
    }
    assert required <= set(data)
    assert list(data) == sorted(data) and text.startswith("{\n  ")
    assert data["fell"] is False and data["fall_time_s"] is None
    assert isinstance(data["steps"], int) and isinstance(data["mean_speed_mps"], float)
    assert data == m.to_dict()
    for value in m.to_dict().values():
        assert value is None or isinstance(value, bool | int | float | str | list)
    assert isinstance(m, WalkMetrics)
    write_json({"a": np.float64(np.nan), "b": np.int64(3)}, tmp_path / "d.json")
    assert json.loads((tmp_path / "d.json").read_text()) == {"a": None, "b": 3}
    with pytest.raises(InvalidInputError, match="metrics\\['c'\\]"):
        write_json({"c": object()}, tmp_path / "e.json")


# -- plots -------------------------------------------------------------------------------------
def assert_png(path, min_bytes=10_000):
    data = path.read_bytes()
    assert data[:8] == PNG_SIGNATURE
    assert len(data) > min_bytes, len(data)


def test_plot_walk_turkey(tmp_path):
    log = turkey_log()
    path = plot_walk(log, tmp_path / "turkey.png", metrics=compute_metrics(log))
    assert path == tmp_path / "turkey.png"
    assert_png(path)


def test_plot_walk_flamingo_on_terrain(tmp_path):
    log = flamingo_log()
    log.save_npz(tmp_path / "flamingo.npz")
    assert_png(plot_walk(tmp_path / "flamingo.npz", tmp_path / "flamingo.png", title="Profile"))
    time_layout = plot_walk(log, tmp_path / "time.png", layout="time", state_lines=False, dpi=80)
    assert_png(time_layout)


def test_plot_walk_sparse_logs_and_errors(tmp_path):
    t = np.linspace(0.0, 2.0, 201)
    fallen = (t > 1.5).astype(float)
    sparse = log_from_arrays(time=t, x=0.3 * t, fallen=fallen)
    assert_png(plot_walk(sparse, tmp_path / "sparse.png", dpi=60), min_bytes=1_000)
    with pytest.raises(InvalidInputError, match="layout"):
        plot_walk(sparse, tmp_path / "x.png", layout="fig9")
    with pytest.raises(InvalidInputError, match="terrain_points"):
        plot_walk(sparse, tmp_path / "x.png", layout="terrain")
    with pytest.raises(InvalidInputError, match="empty run"):
        plot_walk(log_from_arrays(time=[0.0]), tmp_path / "x.png")
    bad = log_from_arrays(time=t, x=t, metadata={"terrain_points": [[0.0, 0.0]]})
    with pytest.raises(InvalidInputError, match="terrain_points"):
        plot_walk(bad, tmp_path / "x.png")


def test_importing_plots_does_not_import_matplotlib():
    code = (
        "import sys, virtual_actuators.simulation\n"
        "if 'matplotlib' in sys.modules: print('preloaded'); raise SystemExit\n"
        "import virtual_actuators.experiments.plots, virtual_actuators.experiments.metrics\n"
        "print('matplotlib' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    if out.stdout.strip() == "preloaded":
        pytest.skip("virtual_actuators.simulation itself imports matplotlib")
    assert out.stdout.strip() == "False"


# -- no negative zero in what the terminal shows (issue 35: "-0.0 mm") ----------------------------
#: A number printed as a negative zero: -0, -0.0, -0.000...
NEGATIVE_ZERO = r"(?<![\w.])-0(?:\.0+)?(?![\d.])"


def _tiny_negatives(cls, signed=None):
    """A metrics dataclass whose floats are -1e-9 (only those named in ``signed`` when given,
    the others +1e-9): every figure that rounds to zero, from below where it can."""
    import dataclasses

    values = {}
    for field in dataclasses.fields(cls):
        kind = str(field.type)
        if kind == "bool":
            values[field.name] = True
        elif kind.startswith("int"):
            values[field.name] = 3
        elif "float" in kind:
            values[field.name] = -1e-9 if signed is None or field.name in signed else 1e-9
        elif "tuple" in kind:
            values[field.name] = ()
        elif "str" in kind:
            values[field.name] = "r"
    return cls(**values)


def test_summaries_print_no_negative_zero():
    import re

    from virtual_actuators.gaits.balance.walk import BalanceMetrics
    from virtual_actuators.gaits.hexapod.metrics import HexapodMetrics
    from virtual_actuators.gaits.legged.metrics import LeggedMetrics

    for metrics in (
        _tiny_negatives(WalkMetrics),
        _tiny_negatives(LeggedMetrics),
        _tiny_negatives(HexapodMetrics),
        _tiny_negatives(BalanceMetrics, signed=("height_error_m",)),  # the others are >= 0
    ):
        cls, summary = type(metrics), metrics.summary()
        assert "0.0" in summary and not re.search(NEGATIVE_ZERO, summary), (cls, summary)
    assert re.search(NEGATIVE_ZERO, "height error -0.0 mm, x -0.000")  # what it catches
    assert not re.search(NEGATIVE_ZERO, "-0.01 -0.5 -10.0 x-0 1e-05")


def test_force_and_effort_tables_print_no_negative_zero():
    import re

    import virtual_actuators as va
    from virtual_actuators.cli.views import _joint_table

    robot = va.load_robot("solo12")
    feet = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
    body = va.ParallelVirtualActuator(robot, "base_link", feet, reference="base_link")
    solution = body.solve(robot.neutral(), np.full(6, -1e-9))
    table = solution.table()
    assert "0.000" in table and not re.search(NEGATIVE_ZERO, table), table
    efforts = _joint_table(robot, np.full(robot.model.nv, -1e-9))
    assert "0.0000" in efforts and not re.search(NEGATIVE_ZERO, efforts), efforts
