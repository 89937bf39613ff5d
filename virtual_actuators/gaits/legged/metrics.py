"""Figures of a legged walk, stated as the issue's targets are: on the second half of the trace."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...experiments.smoothness import SmoothnessFigures
from ..guidance import wrap
from ..runner import summary_line


@dataclass(frozen=True)
class LeggedMetrics(SmoothnessFigures):
    """What a legged walk achieved, with `SmoothnessFigures`.

    Attributes:
        fell: Whether the robot fell.
        fall_time_s: Time of the fall [s] (None if it did not).
        duration_s: Simulated time [s].
        steps: Swings started.
        speed_mps: Mean speed over the ground, second half [m/s] (a circle: by chords).
        speed_command_mps: Commanded speed [m/s].
        speed_error: ``speed / command - 1`` (None at zero command) [-].
        direction_error_rad: Travel direction minus the commanded one, second half; None when
            turning [rad].
        heading_drift_rad: Largest ``|yaw - yaw_0 - yaw_rate t|`` [rad] (straight lines).
        yaw_rate_radps: Mean yaw rate of the second half [rad/s].
        yaw_rate_command_radps: Commanded yaw rate [rad/s].
        roll_max_rad: Largest ``|roll|`` [rad].
        pitch_max_rad: Largest ``|pitch|`` [rad].
        path_error_max_m: A sine path: the largest distance across from it, second half [m].
        bearing_error_max_rad: Tracking: the largest bearing error after 3 s [rad].
        stance_normal_min_n: Least normal force on a support foot, after its first 20 ms [N].
        stance_friction_ratio_max: Largest tangential over normal force on such a foot [-].
        realtime_factor: Simulated over wall-clock time of the loop.
        physics_realtime_factor: Simulated over wall-clock time of MuJoCo's steps alone.
    """

    fell: bool
    fall_time_s: float | None
    duration_s: float
    steps: int
    speed_mps: float
    speed_command_mps: float
    speed_error: float | None
    direction_error_rad: float | None
    heading_drift_rad: float | None
    yaw_rate_radps: float
    yaw_rate_command_radps: float
    roll_max_rad: float
    pitch_max_rad: float
    path_error_max_m: float | None = None
    bearing_error_max_rad: float | None = None
    stance_normal_min_n: float | None = None
    stance_friction_ratio_max: float | None = None
    realtime_factor: float | None = None
    physics_realtime_factor: float | None = None

    def summary(self) -> str:
        """One line for the terminal."""
        parts = [
            f"{self.duration_s:z.1f} s, {self.steps} steps",
            f"speed {self.speed_mps:z.2f} m/s (set {self.speed_command_mps:z.2f})",
        ]
        labelled = (
            ("direction error", self.direction_error_rad),
            ("heading drift", self.heading_drift_rad),
            ("roll max", self.roll_max_rad),
            ("pitch max", self.pitch_max_rad),
            ("path error", self.path_error_max_m),
            ("bearing error max", self.bearing_error_max_rad),
        )
        yaw_rate, command = self.yaw_rate_radps, self.yaw_rate_command_radps
        turn = (f"yaw rate {yaw_rate:z.2f} (set {command:z.2f})",) if command else ()
        return summary_line(self, parts, labelled, turn)


def legged_metrics(
    trace: dict[str, list[float]],
    speed: float,
    direction: float,
    yaw_rate: float,
    steps: int,
    fall_time: float | None,
) -> LeggedMetrics:
    """The figures of a walk from its trace.

    Args:
        trace: ``t, x, y, roll, pitch, yaw`` (yaw unwrapped) lists.
        speed: Commanded speed [m/s].
        direction: Commanded travel direction relative to the heading [rad].
        yaw_rate: Commanded yaw rate [rad/s].
        steps: Swings started.
        fall_time: Time of the fall, or None.
    """
    t, x, y, yaw = (np.asarray(trace[k], dtype=float) for k in ("t", "x", "y", "yaw"))
    half = len(t) // 2
    span = max(t[-1] - t[half], 1e-9) if len(t) > 1 else 1e-9
    if yaw_rate == 0.0 or len(t) < 2:  # a line: the displacement (sway left out)
        path = math.hypot(x[-1] - x[half], y[-1] - y[half]) if len(t) > 1 else 0.0
    else:  # a circle: chords a quarter second apart
        every = max(1, int(round(0.25 / max(t[1] - t[0], 1e-9))))
        xs, ys = x[half::every], y[half::every]
        path = float(np.hypot(np.diff(xs), np.diff(ys)).sum())
        path *= span / max(t[half::every][-1] - t[half], 1e-9)  # over the whole half
    measured = float(path / span)
    direction_error = drift = None
    if yaw_rate == 0.0 and len(t) > 1:
        if speed > 0.0:
            travel = math.atan2(y[-1] - y[half], x[-1] - x[half])
            direction_error = abs(wrap(travel - (yaw[0] + direction)))
        drift = float(np.max(np.abs(yaw - yaw[0])))
    turn = float((yaw[-1] - yaw[half]) / span) if len(t) > 1 else 0.0
    return LeggedMetrics(
        fell=fall_time is not None,
        fall_time_s=fall_time,
        duration_s=float(t[-1]) if len(t) else 0.0,
        steps=steps,
        speed_mps=measured,
        speed_command_mps=speed,
        speed_error=measured / speed - 1.0 if speed > 0.0 else None,
        direction_error_rad=direction_error,
        heading_drift_rad=drift,
        yaw_rate_radps=turn,
        yaw_rate_command_radps=yaw_rate,
        roll_max_rad=float(np.max(np.abs(trace["roll"]))) if len(t) else 0.0,
        pitch_max_rad=float(np.max(np.abs(trace["pitch"]))) if len(t) else 0.0,
    )
