"""High-level inputs of a walk: paths and tracking turned into a velocity and a yaw rate."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..exceptions import InvalidInputError
from .base import check_distribution, check_speed_bound

#: The paths a walk's configuration may ask for (see `check_path`).
PATHS = ("line", "sine")


@dataclass(frozen=True)
class PlanarState:
    """The body's planar state in the world.

    Attributes:
        time: [s].
        x: [m].
        y: [m].
        yaw: Heading [rad].
        vx: World x velocity [m/s].
        vy: World y velocity [m/s].
    """

    time: float
    x: float
    y: float
    yaw: float
    vx: float
    vy: float


def wrap(angle: float) -> float:
    """``angle`` wrapped to ``[-pi, pi)`` [rad]."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


def _finite(what: str, **values: float) -> None:
    """Refuse a value that is not a finite number (the message starts with ``what``)."""
    for name, value in values.items():
        if not (isinstance(value, (int, float)) and math.isfinite(value)):
            raise InvalidInputError(f"{what}{name} must be a finite number, got {value!r}.")


def checked_command(velocity: object, yaw_rate: object) -> tuple[float, float, float]:
    """A ``set_command``'s ``(vx, vy, yaw_rate)`` as floats.

    Raises:
        InvalidInputError: Values that are not finite.
    """
    vx, vy = velocity
    vx, vy, yaw_rate = float(vx), float(vy), float(yaw_rate)
    if not (math.isfinite(vx) and math.isfinite(vy) and math.isfinite(yaw_rate)):
        raise InvalidInputError(
            f"set_command: velocity and yaw rate must be finite, got {velocity}, {yaw_rate}."
        )
    return vx, vy, yaw_rate


class Guidance:
    """Computes the walker's inputs from the body's state (subclasses implement `command`).

    Attributes:
        start: ``(x, y, yaw)`` of the body at `begin` [m, m, rad].
        fixed: `command` does not depend on the state (a walk sets it once).
    """

    fixed = False
    start = (0.0, 0.0, 0.0)

    def begin(self, state: PlanarState) -> None:
        """Remember where the body starts (called once before the first tick)."""
        self.start = (state.x, state.y, state.yaw)

    def command(self, state: PlanarState) -> tuple[np.ndarray, float]:
        """``(velocity in the heading frame (2,) [m/s], yaw rate [rad/s])``."""
        raise NotImplementedError

    def target(self, time: float) -> tuple[float, float] | None:
        """Position of a tracked object at ``time`` [m], or None."""
        return None


class VelocityCommand(Guidance):
    """Fixed inputs: ``speed`` at ``direction`` from the heading, and ``yaw_rate``.

    Args:
        speed: [m/s], >= 0.
        direction: Travel direction relative to the heading [rad] (pi/2: crab to the left).
        yaw_rate: [rad/s].

    Raises:
        InvalidInputError: A value that is not finite, or a negative speed.
    """

    fixed = True

    def __init__(self, speed: float, direction: float = 0.0, yaw_rate: float = 0.0) -> None:
        _finite("VelocityCommand: ", speed=speed, direction=direction, yaw_rate=yaw_rate)
        if speed < 0.0:
            raise InvalidInputError(f"VelocityCommand: speed must be >= 0, got {speed}.")
        self.velocity = speed * np.array((math.cos(direction), math.sin(direction)))
        self.yaw_rate = float(yaw_rate)

    def command(self, state: PlanarState) -> tuple[np.ndarray, float]:
        """The fixed inputs."""
        return self.velocity, self.yaw_rate


class SinePath(Guidance):
    """Travel ``y = A sin(2 pi x / L)`` (start-pose axes) at ``speed``, holding the heading.

    Args:
        speed: Speed along the path [m/s], > 0.
        amplitude: ``A`` [m].
        wavelength: ``L`` [m], > 0.
        lateral_gain: Steering toward the curve: lateral velocity per metre off it [1/s].
        heading_gain: Yaw rate per radian of heading error [1/s].

    Raises:
        InvalidInputError: A value that is not finite, or a speed or wavelength <= 0.
    """

    def __init__(
        self,
        speed: float,
        amplitude: float,
        wavelength: float,
        lateral_gain: float = 3.0,
        heading_gain: float = 4.0,
    ) -> None:
        _finite("SinePath: ", speed=speed, amplitude=amplitude, wavelength=wavelength)
        if speed <= 0.0 or wavelength <= 0.0:
            raise InvalidInputError(
                f"SinePath: speed and wavelength must be > 0, got {speed}, {wavelength}."
            )
        self.speed, self.amplitude, self.wavelength = float(speed), float(amplitude), wavelength
        self.lateral_gain, self.heading_gain = lateral_gain, heading_gain

    def curve(self, along: np.ndarray | float) -> np.ndarray | float:
        """Lateral offset of the path at ``along`` metres from the start [m]."""
        return self.amplitude * np.sin(2.0 * np.pi * np.asarray(along) / self.wavelength)

    def to_path(self, x: float, y: float) -> tuple[float, float]:
        """World ``(x, y)`` in the path's axes (start pose) [m]."""
        x0, y0, yaw0 = self.start
        c, s = math.cos(yaw0), math.sin(yaw0)
        return c * (x - x0) + s * (y - y0), -s * (x - x0) + c * (y - y0)

    def command(self, state: PlanarState) -> tuple[np.ndarray, float]:
        """Velocity along the tangent, steered back to the curve; yaw held at the start's."""
        along, across = self.to_path(state.x, state.y)
        k = 2.0 * math.pi / self.wavelength
        slope = self.amplitude * k * math.cos(k * along)
        error = across - float(self.curve(along))
        tangent = np.array((1.0, slope)) / math.hypot(1.0, slope)
        normal = np.array((-tangent[1], tangent[0]))
        velocity_path = self.speed * tangent - self.lateral_gain * error * normal
        yaw0 = self.start[2]
        heading = wrap(state.yaw - yaw0)  # body heading in path axes
        c, s = math.cos(heading), math.sin(heading)
        px, py = velocity_path
        return np.array((c * px + s * py, -s * px + c * py)), -self.heading_gain * heading


class TrackObject(Guidance):
    """Walk a fixed body-frame velocity while facing an object circling the start.

    The yaw rate is the bearing's rate plus ``gain`` times the bearing error.

    Args:
        speed: Body speed [m/s], >= 0.
        direction: Travel direction relative to the heading [rad].
        radius: Object's circle [m], > 0.
        angular_speed: Object's angular speed about the start [rad/s].
        gain: Yaw rate per radian of bearing error [1/s].

    Raises:
        InvalidInputError: A value that is not finite, a negative speed or a radius <= 0.
    """

    def __init__(
        self,
        speed: float,
        direction: float = 0.0,
        radius: float = 1.5,
        angular_speed: float = 0.25,
        gain: float = 6.0,
    ) -> None:
        _finite("TrackObject: ", radius=radius, angular_speed=angular_speed, gain=gain)
        if radius <= 0.0:
            raise InvalidInputError(f"TrackObject: radius must be > 0, got {radius}.")
        self.walk = VelocityCommand(speed, direction)
        self.radius, self.angular_speed, self.gain = float(radius), angular_speed, gain

    def target(self, time: float) -> tuple[float, float]:
        """The object's position at ``time`` [m]."""
        x0, y0, yaw0 = self.start
        angle = yaw0 + self.angular_speed * time
        return x0 + self.radius * math.cos(angle), y0 + self.radius * math.sin(angle)

    def bearing_error(self, state: PlanarState) -> float:
        """Direction of the object minus the heading [rad]."""
        tx, ty = self.target(state.time)
        return wrap(math.atan2(ty - state.y, tx - state.x) - state.yaw)

    def command(self, state: PlanarState) -> tuple[np.ndarray, float]:
        """The walk's velocity and the yaw rate that keeps the object ahead."""
        tx, ty = self.target(state.time)
        angle = self.start[2] + self.angular_speed * state.time
        rx, ry = tx - state.x, ty - state.y
        wx = -self.radius * self.angular_speed * math.sin(angle) - state.vx
        wy = self.radius * self.angular_speed * math.cos(angle) - state.vy
        distance2 = max(rx * rx + ry * ry, 1e-4)
        bearing_rate = (rx * wy - ry * wx) / distance2
        yaw_rate = bearing_rate + self.gain * self.bearing_error(state)
        return self.walk.velocity, yaw_rate


def check_path(config: object) -> None:
    """Refuse a walk's configuration whose motion does not hold together.

    ``config`` has ``speed``, ``direction``, ``yaw_rate``, ``duration``, ``path``,
    ``amplitude``, ``wavelength``, ``track`` and ``distribution`` (see `path_guidance`).

    Raises:
        InvalidInputError: A value not finite, a speed outside ``[0, MAX_SPEED]``, a duration
            <= 0, a path not in `PATHS`, a sine without a speed and a wavelength > 0 or with a
            yaw rate or tracking, tracking with a yaw rate, or an unknown distribution.
    """
    c = config
    names = ("speed", "direction", "yaw_rate", "duration", "amplitude", "wavelength")
    _finite("", **{name: getattr(c, name) for name in names})
    check_speed_bound(c.speed)
    if c.duration <= 0.0:
        raise InvalidInputError(f"duration must be > 0 s, got {c.duration}.")
    if c.path not in PATHS:
        raise InvalidInputError(f"path must be one of {PATHS}, got {c.path!r}.")
    if c.path == "sine" and (c.speed <= 0.0 or c.wavelength <= 0.0):
        raise InvalidInputError("path 'sine' needs a speed > 0 and a wavelength > 0.")
    if c.path == "sine" and (c.track or c.yaw_rate != 0.0):
        raise InvalidInputError("path 'sine' holds the heading: no yaw rate and no tracking.")
    if c.track and c.yaw_rate != 0.0:
        raise InvalidInputError("tracking sets the yaw rate itself: leave yaw_rate at 0.")
    check_distribution(c.distribution)


def path_guidance(config: object) -> Guidance:
    """The guidance of a configuration `check_path` accepted.

    A sine ``path`` is a `SinePath`; ``track`` a `TrackObject`; else a `VelocityCommand` of
    ``speed`` along ``direction`` at ``yaw_rate`` (a circle of radius ``speed / yaw_rate``).
    """
    c = config
    if c.path == "sine":
        return SinePath(c.speed, c.amplitude, c.wavelength)
    if c.track:
        return TrackObject(c.speed, c.direction)
    return VelocityCommand(c.speed, c.direction, c.yaw_rate)
