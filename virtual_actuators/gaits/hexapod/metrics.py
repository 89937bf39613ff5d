"""Figures of a hexapod walk (`run_hexapod_walk`), from its log of the body state in MuJoCo."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...exceptions import InvalidInputError
from ...experiments.smoothness import SmoothnessFigures
from ...experiments.walk_log import WalkLog
from ..guidance import Guidance, SinePath, TrackObject, VelocityCommand, wrap
from ..runner import summary_line

STARTUP = 1.0  # [s] speed, direction and path figures ignore the first second
TRACK_SETTLE = 3.0  # [s] bearing errors are judged after this


@dataclass(frozen=True)
class HexapodMetrics(SmoothnessFigures):
    """What a hexapod walk achieved (``None``: not measured), with `SmoothnessFigures`.

    Attributes:
        fell: Whether the robot fell.
        fall_time_s: Time of the fall [s].
        duration_s: Simulated time [s].
        steps: Tripod swaps.
        speed_mps: Mean speed over the ground after start-up [m/s].
        speed_command_mps: Commanded speed [m/s].
        direction_error_rad: Travel direction minus the commanded one, after start-up [rad].
        heading_drift_rad: Largest ``|yaw - initial yaw|`` (no yaw rate, no tracking) [rad].
        roll_max_rad: Largest ``|roll|`` after start-up [rad].
        pitch_max_rad: Largest ``|pitch|`` after start-up [rad].
        yaw_rate_radps: Mean yaw rate after start-up [rad/s].
        circle_radius_m: Radius of the circle fitted to the path after start-up [m].
        circle_radius_command_m: ``speed / yaw_rate`` [m].
        path_error_max_m: Sine: largest distance from the commanded curve after start-up [m].
        pendulum_peak_rad: Largest ``|pendulum angle|`` [rad].
        pendulum_rms_rad: RMS pendulum angle over the second half [rad].
        vx_second_half_mps: Mean heading-frame x velocity over the second half [m/s].
        vx_min_early_mps: Least heading-frame x velocity over the first second [m/s].
        bearing_error_max_rad: Tracking: largest bearing error after 3 s [rad].
        bearing_error_rms_rad: Tracking: RMS bearing error after 3 s [rad].
        stance_normal_min_n: Least normal force of a support foot, from 20 ms after it entered
            support, until a fall [N].
        stance_friction_ratio_max: Largest tangential / normal force of those feet where they
            carry at least 1 N [-].
        realtime_factor: Simulated time / wall-clock time of the whole loop.
        physics_realtime_factor: Simulated time / wall-clock time of MuJoCo's stepping alone.
    """

    fell: bool
    fall_time_s: float | None
    duration_s: float
    steps: int
    speed_mps: float | None
    speed_command_mps: float
    direction_error_rad: float | None = None
    heading_drift_rad: float | None = None
    roll_max_rad: float | None = None
    pitch_max_rad: float | None = None
    yaw_rate_radps: float | None = None
    circle_radius_m: float | None = None
    circle_radius_command_m: float | None = None
    path_error_max_m: float | None = None
    pendulum_peak_rad: float | None = None
    pendulum_rms_rad: float | None = None
    vx_second_half_mps: float | None = None
    vx_min_early_mps: float | None = None
    bearing_error_max_rad: float | None = None
    bearing_error_rms_rad: float | None = None
    stance_normal_min_n: float | None = None
    stance_friction_ratio_max: float | None = None
    realtime_factor: float | None = None
    physics_realtime_factor: float | None = None

    def summary(self) -> str:
        """One line for the terminal."""
        parts = [f"{self.duration_s:z.1f} s, {self.steps} steps"]
        if self.speed_mps is not None:
            parts.append(f"speed {self.speed_mps:z.2f} m/s (set {self.speed_command_mps:z.2f})")
        labelled = (
            ("direction error", self.direction_error_rad),
            ("heading drift", self.heading_drift_rad),
            ("circle radius", self.circle_radius_m),
            ("path error", self.path_error_max_m),
            ("pendulum peak", self.pendulum_peak_rad),
            ("pendulum rms", self.pendulum_rms_rad),
            ("bearing error max", self.bearing_error_max_rad),
        )
        return summary_line(self, parts, labelled)


def _circle_fit(x: np.ndarray, y: np.ndarray) -> float:
    """Radius of the least-squares circle through the points (algebraic fit) [m]."""
    a = np.c_[x, y, np.ones_like(x)]
    (cx2, cy2, c), *_ = np.linalg.lstsq(a, x * x + y * y, rcond=None)
    return float(math.sqrt(max(c + 0.25 * (cx2 * cx2 + cy2 * cy2), 0.0)))


def _command(guidance: Guidance) -> tuple[float, float, float]:
    """Commanded speed [m/s], travel direction [rad] and yaw rate [rad/s] of ``guidance``."""
    command = guidance.walk if isinstance(guidance, TrackObject) else guidance
    if isinstance(command, VelocityCommand):
        direction = math.atan2(command.velocity[1], command.velocity[0])
        return float(np.hypot(*command.velocity)), direction, command.yaw_rate
    return float(guidance.speed), 0.0, 0.0


def _pendulum_figures(log: WalkLog, walking: np.ndarray) -> dict[str, float]:
    """The pendulum's peak and RMS angle and the body's heading x velocity (none: no pendulum)."""
    if not (log.has("pendulum") and np.any(np.isfinite(log["pendulum"]))):
        return {}
    t = log.time
    angle, vx = log["pendulum"][walking], log["vx_heading"][walking]
    second = t[walking] >= t[0] + 0.5 * (t[walking][-1] - t[0])
    return {
        "pendulum_peak_rad": float(np.max(np.abs(angle))),
        "pendulum_rms_rad": float(np.sqrt(np.mean(angle[second] ** 2))),
        "vx_second_half_mps": float(np.mean(vx[second])),
        "vx_min_early_mps": float(np.min(vx[t[walking] <= t[0] + 1.0])),
    }


def _bearing_figures(log: WalkLog, walking: np.ndarray) -> dict[str, float]:
    """The largest and RMS bearing error to the tracked object after `TRACK_SETTLE`."""
    t = log.time
    settled = walking & (t >= t[0] + TRACK_SETTLE)
    if not np.any(settled):
        return {}
    x, y = log["x"], log["y"]
    bearing = np.arctan2(log["target_y"] - y, log["target_x"] - x) - log["yaw"]
    error = np.abs((bearing[settled] + np.pi) % (2.0 * np.pi) - np.pi)
    return {
        "bearing_error_max_rad": float(np.max(error)),
        "bearing_error_rms_rad": float(np.sqrt(np.mean(error**2))),
    }


def compute_hexapod_metrics(
    log: WalkLog,
    guidance: Guidance,
    steps: int,
    fall_time: float | None,
    stance_normal_min: float | None = None,
    stance_ratio_max: float | None = None,
) -> HexapodMetrics:
    """Reduce a hexapod walk's log to `HexapodMetrics` (see its attributes).

    Args:
        log: The run (channels of ``virtual_actuators.gaits.hexapod.walk.CHANNELS``).
        guidance: Its guidance (after `Guidance.begin`).
        steps: Tripod swaps.
        fall_time: Time of the fall [s], or None.
        stance_normal_min: Least normal force of a supporting foot [N], or None.
        stance_ratio_max: Largest friction ratio of a loaded supporting foot, or None.

    Returns:
        The metrics (timing fields None).

    Raises:
        InvalidInputError: A log with fewer than two samples.
    """
    t = log.time
    if len(t) < 2:
        raise InvalidInputError(f"log: {len(t)} samples; a hexapod walk needs at least two.")
    x, y, yaw = log["x"], log["y"], log["yaw"]
    walking = t <= (fall_time if fall_time is not None else np.inf)
    window = walking & (t >= t[0] + STARTUP)
    if np.count_nonzero(window) < 2:
        window = walking
    tw, xw, yw = t[window], x[window], y[window]
    span = float(tw[-1] - tw[0]) if len(tw) > 1 else 0.0
    track = isinstance(guidance, TrackObject)
    speed_command, direction, yaw_rate_command = _command(guidance)
    straight = isinstance(guidance, VelocityCommand) and yaw_rate_command == 0.0
    figures: dict[str, Any] = {}  # what this run measures (the others: None)
    speed = None
    if span > 0.0:
        displacement = math.hypot(xw[-1] - xw[0], yw[-1] - yw[0])
        ground = np.hypot(log["vx"][window], log["vy"][window])
        speed = displacement / span if straight else float(np.mean(ground))
        if straight and displacement > 1e-3:
            travel = math.atan2(yw[-1] - yw[0], xw[-1] - xw[0]) - guidance.start[2]
            figures["direction_error_rad"] = abs(wrap(travel - direction))
    if yaw_rate_command == 0.0 and not track:
        figures["heading_drift_rad"] = float(np.max(np.abs(yaw[walking] - yaw[0])))
    if yaw_rate_command != 0.0 and speed_command > 0.0 and len(tw) > 2:
        figures["circle_radius_m"] = _circle_fit(xw, yw)
        figures["circle_radius_command_m"] = speed_command / abs(yaw_rate_command)
    if isinstance(guidance, SinePath):
        along, across = guidance.to_path(xw, yw)
        figures["path_error_max_m"] = float(np.max(np.abs(across - guidance.curve(along))))
    figures |= _pendulum_figures(log, walking)
    if track:
        figures |= _bearing_figures(log, walking)
    return HexapodMetrics(
        fell=fall_time is not None,
        fall_time_s=fall_time,
        duration_s=float(t[-1] - t[0]),
        steps=int(steps),
        speed_mps=speed,
        speed_command_mps=speed_command,
        roll_max_rad=float(np.max(np.abs(log["roll"][window]))),
        pitch_max_rad=float(np.max(np.abs(log["pitch"][window]))),
        yaw_rate_radps=float(np.mean(log["yaw_rate"][window])),
        stance_normal_min_n=stance_normal_min,
        stance_friction_ratio_max=stance_ratio_max,
        **figures,
    )
