"""Where a swing foot lands and the curve that carries it there (world axes).

The foothold (:func:`foothold`) is the foot's nominal place under the centre of mass (the
standing stance, centred on it), turned by half the stance's yaw, moved by half the stance's
travel at the velocity set point (the feed-forward: the stance is then centred under the body)
and by the capture term (``sqrt(h / g)`` times the velocity error, Raibert's correction), all in
the heading frame predicted for touchdown. :func:`swing_point` is the swing curve: a smooth
reach from lift-off to the foothold and a lift profile above the line between their heights.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

from ..planar import lift_profile, smoothstep

Pair = tuple[float, float]


class BodyState(NamedTuple):
    """The body as the swing feet's set points need it this tick (world frame).

    Attributes:
        com: Centre of mass [m].
        base: The body frame's origin [m].
        linear: Its velocity [m/s].
        angular: The body's angular velocity [rad/s].
        yaw: Its heading [rad].

    """

    com: Sequence[float]
    base: Sequence[float]
    linear: Sequence[float]
    angular: Sequence[float]
    yaw: float


class Motion(NamedTuple):
    """The body's planar motion the footholds are placed for (heading frame, set points).

    Attributes:
        velocity: Velocity set point ``(vx, vy)`` in the heading frame [m/s].
        error: Measured minus set point velocity, heading frame [m/s].
        yaw_rate: Yaw rate set point [rad/s].

    """

    velocity: Pair
    error: Pair
    yaw_rate: float


def foothold(
    nominal: Pair,
    motion: Motion,
    stance_time: float,
    capture_time: float,
    reach: float,
) -> tuple[float, float]:
    """The foothold relative to the centre of mass at touchdown, heading frame [m].

    Args:
        nominal: The foot's nominal place relative to the centre of mass [m].
        motion: The body's velocity set point, its error and the yaw rate.
        stance_time: How long the foot will stand [s].
        capture_time: Seconds of velocity error the foothold moves by (``sqrt(h / g)``) [s].
        reach: Largest distance from the nominal place [m].

    """
    half = 0.5 * stance_time
    angle = motion.yaw_rate * half
    c, s = math.cos(angle), math.sin(angle)
    x, y = nominal
    (vx, vy), (ex, ey) = motion.velocity, motion.error
    dx = c * x - s * y - x + vx * half + capture_time * ex
    dy = s * x + c * y - y + vy * half + capture_time * ey
    scale = min(1.0, reach / max(math.hypot(dx, dy), 1e-12))
    return x + scale * dx, y + scale * dy


def swing_point(
    start: Sequence[float], land: Sequence[float], phase: float, lift: float, peak: float
) -> list[float]:
    """The swing foot's set point at ``phase`` (0 at lift-off, 1 at touchdown), world [m].

    Horizontally a smooth step that arrives at 80 % of the swing; vertically a smooth step
    between the two heights plus ``lift`` times :func:`~virtual_actuators.gaits.planar.
    lift_profile`. Past phase 1 it stays at the foothold (the gait lowers ``land`` instead).
    """
    (x0, y0, z0), (x1, y1, z1) = start, land
    reach = smoothstep(min(1.0, 1.25 * phase))
    height = z0 + (z1 - z0) * smoothstep(phase) + lift * lift_profile(phase, peak)
    return [x0 + (x1 - x0) * reach, y0 + (y1 - y0) * reach, height]


__all__ = ["BodyState", "Motion", "foothold", "swing_point"]
