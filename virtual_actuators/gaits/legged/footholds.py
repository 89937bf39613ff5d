"""Where a swing foot lands and the curve that carries it there (world axes)."""

from __future__ import annotations

from collections.abc import Sequence

from ...vocabulary.scalar import cos, cross, hypot, maximum, minimum, select, sin
from ..planar import lift_profile, smoothstep


def foothold(
    x: object,
    y: object,
    vx: object,
    vy: object,
    ex: object,
    ey: object,
    yaw_rate: object,
    stance_time: float,
    capture_time: float,
    reach: float,
) -> tuple:
    """The foothold relative to the centre of mass at touchdown, heading frame [m].

    Args:
        x: The foot's nominal place relative to the centre of mass, along the heading [m].
        y: The same, across it [m].
        vx: The body's velocity set point along the heading [m/s].
        vy: The same, across it [m/s].
        ex: Measured minus set velocity along the heading [m/s].
        ey: The same, across it [m/s].
        yaw_rate: Yaw rate set point [rad/s].
        stance_time: How long the foot will stand [s].
        capture_time: Seconds of velocity error the foothold moves by (``sqrt(h / g)``) [s].
        reach: Largest distance from the nominal place [m].
    """
    half = 0.5 * stance_time
    angle = yaw_rate * half
    c, s = cos(angle), sin(angle)
    dx = c * x - s * y - x + vx * half + capture_time * ex
    dy = s * x + c * y - y + vy * half + capture_time * ey
    scale = minimum(1.0, reach / maximum(hypot(dx, dy), 1e-12))
    return x + scale * dx, y + scale * dy


def swing_point(
    start: Sequence, x: object, y: object, z: object, phase: object, lift: float, peak: float
) -> tuple:
    """The swing foot's set point at ``phase`` (0 at lift-off, 1 at touchdown), world [m].

    Horizontally a smooth step arriving at 80 % of the swing; vertically a smooth step between
    the two heights plus ``lift`` times `lift_profile`.
    """
    x0, y0, z0 = start[0], start[1], start[2]
    reach = smoothstep(minimum(1.0, 1.25 * phase))
    height = z0 + (z - z0) * smoothstep(phase) + lift * lift_profile(phase, peak)
    return x0 + (x - x0) * reach, y0 + (y - y0) * reach, height


def swing_setpoint(
    state: Sequence,
    nominal: Sequence[float],
    body: Sequence,
    motion: Sequence,
    dt: object,
    shape: Sequence[float],
) -> tuple[tuple, tuple]:
    """One swinging foot's next state and its spring's set points, relative to the body.

    The `foothold` is placed in the heading and about the centre of mass predicted for
    touchdown, ``depth`` below the ground; the set point's velocity is low-pass filtered.

    Args:
        state: ``(9,)`` lift-off point, last set point, its velocity [m, m/s], world.
        nominal: ``(2,)`` the foot's nominal place (`foothold`'s ``x``, ``y``) [m].
        body: ``(12,)`` centre of mass, body origin, velocity, angular velocity, world.
        motion: ``(8,)`` ``vx, vy, ex, ey`` (heading frame) [m/s], yaw rate set point [rad/s],
            yaw [rad], time in the swing [s], ground height [m].
        dt: Time since the last set points [s] (not positive: the velocity is kept).
        shape: ``(8,)`` swing time, stance time, capture time, reach, lift, lift peak (a
            phase), touchdown depth, rate filter [s, s, s, m, m, -, m, s].

    Returns:
        ``(state, setpoints)``: the new ``(9,)`` state, and ``(6,)`` the set point and its
        velocity relative to the body, world axes.
    """
    vx, vy, ex, ey, yaw_rate, yaw, elapsed, ground = motion
    swing_time, stance_time, capture, reach, lift, peak, depth, rate_filter = shape
    phase = elapsed / swing_time
    remaining = maximum(0.0, swing_time - elapsed)
    heading = yaw + yaw_rate * remaining
    c, s = cos(heading), sin(heading)
    cy, sy = cos(yaw), sin(yaw)
    centre_x = body[0] + remaining * (cy * vx - sy * vy)  # the centre of mass at touchdown
    centre_y = body[1] + remaining * (sy * vx + cy * vy)
    depth = depth * (1.0 + 4.0 * maximum(0.0, phase - 1.0))
    moving = dt > 0.0
    blend = select(moving, minimum(1.0, dt / rate_filter), 0.0)
    step = select(moving, dt, 1.0)  # the divisor where it is used
    x, y = foothold(*nominal, vx, vy, ex, ey, yaw_rate, stance_time, capture, reach)
    target = swing_point(
        state[:3], centre_x + c * x - s * y, centre_y + s * x + c * y, ground - depth, phase,
        lift, peak,
    )  # fmt: skip
    rate = tuple(
        select(moving, state[6 + i] + blend * ((target[i] - state[3 + i]) / step - state[6 + i]),
               state[6 + i])
        for i in range(3)
    )  # fmt: skip
    offset = tuple(target[i] - body[3 + i] for i in range(3))
    spin = cross(body[9:12], offset)
    relative = tuple(rate[i] - body[6 + i] - spin[i] for i in range(3))
    return (*state[:3], *target, *rate), (*offset, *relative)


__all__ = ["foothold", "swing_point", "swing_setpoint"]
