"""What a hexapod walk is asked to do: `HexapodWalkConfig`, and the path it is commanded."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...exceptions import InvalidInputError
from ..base import check_distribution, check_speed_bound
from ..guidance import Guidance, SinePath, TrackObject, VelocityCommand

PATHS = ("line", "sine")


@dataclass(frozen=True)
class HexapodWalkConfig:
    """What to walk (SI units, angles in radians).

    Attributes:
        speed: Body speed [m/s].
        direction: Travel direction relative to the heading [rad].
        yaw_rate: [rad/s] (line path only: a circle of radius ``speed / yaw_rate``).
        path: ``"line"`` (the velocity fixed in the body frame) or ``"sine"``.
        amplitude: Sine amplitude [m].
        wavelength: Sine wavelength [m].
        pendulum: Balance the pendulum (its LQR owns the x motion).
        track: Face an object circling the start while walking.
        terrain: A `Terrain.parse` spec (profiles run along the world x axis).
        duration: Simulated time [s].
        seed: Random initial disturbance (body velocity, pendulum angle); None for none.
        distribution: ``"qp"`` or ``"partitioned"``.
    """

    speed: float = 0.4
    direction: float = 0.0
    yaw_rate: float = 0.0
    path: str = "line"
    amplitude: float = 0.2
    wavelength: float = 2.0
    pendulum: bool = False
    track: bool = False
    terrain: str = "flat"
    duration: float = 10.0
    seed: int | None = None
    distribution: str = "qp"

    def __post_init__(self) -> None:
        numbers = {k: getattr(self, k) for k in ("speed", "direction", "yaw_rate", "duration")}
        numbers.update(amplitude=self.amplitude, wavelength=self.wavelength)
        for name, value in numbers.items():
            if not (isinstance(value, (int, float)) and math.isfinite(value)):
                raise InvalidInputError(f"{name} must be a finite number, got {value!r}.")
        check_speed_bound(self.speed)
        if self.duration <= 0.0:
            raise InvalidInputError(f"duration must be > 0 s, got {self.duration}.")
        if self.path not in PATHS:
            raise InvalidInputError(f"path must be one of {PATHS}, got {self.path!r}.")
        if self.path == "sine" and (self.speed <= 0.0 or self.wavelength <= 0.0):
            raise InvalidInputError("path 'sine' needs a speed > 0 and a wavelength > 0.")
        check_distribution(self.distribution)
        if self.path == "sine" and (self.track or self.yaw_rate != 0.0):
            raise InvalidInputError("path 'sine' holds the heading: no yaw rate and no tracking.")
        if self.track and self.yaw_rate != 0.0:
            raise InvalidInputError("tracking sets the yaw rate itself: leave yaw_rate at 0.")

    def guidance(self) -> Guidance:
        """The guidance for this configuration."""
        if self.path == "sine":
            return SinePath(self.speed, self.amplitude, self.wavelength)
        if self.track:
            return TrackObject(self.speed, self.direction)
        return VelocityCommand(self.speed, self.direction, self.yaw_rate)


def command_path(config: HexapodWalkConfig, guidance: Guidance) -> np.ndarray:
    """The commanded path, ``(n, 2)`` world points [m] (the object's circle when tracking)."""
    x0, y0, yaw0 = guidance.start
    reach = max(config.speed * config.duration, 1e-3)
    if isinstance(guidance, TrackObject):
        angles = np.linspace(0.0, 2.0 * np.pi, 181)
        return np.c_[x0 + guidance.radius * np.cos(angles), y0 + guidance.radius * np.sin(angles)]
    if isinstance(guidance, SinePath):
        along = np.linspace(0.0, reach, 400)
        across = guidance.curve(along)
    elif config.yaw_rate != 0.0 and config.speed > 0.0:
        radius = config.speed / abs(config.yaw_rate)
        sweep = min(abs(config.yaw_rate) * config.duration, 2.0 * np.pi)
        angles = np.linspace(0.0, sweep, 181) * np.sign(config.yaw_rate)
        # start at the origin heading along the travel direction, centre on the turning side
        side = np.sign(config.yaw_rate) * radius * (1 - np.cos(angles))
        local = np.c_[radius * np.sin(np.abs(angles)), side]
        c, s = math.cos(config.direction), math.sin(config.direction)
        along, across = c * local[:, 0] - s * local[:, 1], s * local[:, 0] + c * local[:, 1]
    else:
        distances = np.linspace(0.0, reach, 2)
        along = distances * math.cos(config.direction)
        across = distances * math.sin(config.direction)
    c, s = math.cos(yaw0), math.sin(yaw0)
    return np.c_[x0 + c * along - s * across, y0 + s * along + c * across]
