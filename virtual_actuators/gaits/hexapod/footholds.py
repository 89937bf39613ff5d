"""Where the hexapod's feet are and where they land: strides, lag behind, landing places.

A support foot moves over the ground relative to the body; the gait measures how far the
support tripod is behind its nominal places (in strides, an ellipse of axes step length and
width) to end the stance, and places the swing feet so that the next stance is centred under
the body. Body axes throughout.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from .body import GRAVITY
from .parameters import HexapodParameters

Pair = tuple[float, float]


def ground_velocity(
    velocity: Pair, yaw_rate: float, nominal: Sequence[Sequence[float]]
) -> list[Pair]:
    """Velocity over the ground of the nominal foot points, body axes [m/s].

    A support foot moves at minus this relative to the body.

    Args:
        velocity: The measured (low-passed) body velocity ``(vx, vy)`` [m/s].
        yaw_rate: The commanded yaw rate [rad/s].
        nominal: The nominal foot points ``(x, y, z)`` relative to the body [m].

    """
    vx, vy = velocity
    w = yaw_rate
    return [(vx - w * y, vy + w * x) for x, y, _ in nominal]


def strides(parameters: HexapodParameters, dx: float, dy: float) -> float:
    """A horizontal displacement in strides: the ellipse of axes step length and width is 1."""
    p = parameters
    return math.sqrt((dx / p.step_length) ** 2 + (dy / p.step_width) ** 2)


def behind(
    parameters: HexapodParameters,
    offsets: Sequence[Sequence[float]],
    sx: Sequence[float],
    sy: Sequence[float],
) -> float:
    """How far the support feet are behind their nominal places, in strides (largest).

    Measured along each foot's motion relative to the body (against its velocity over the
    ground at the nominal place): -0.5 where the feet land, 0.5 where the stance ends (the
    tripod's static margin is spent beyond). 0 when the body does not move.

    Args:
        parameters: The gait's step length and width.
        offsets: Support feet minus their nominal places, body axes, one row each [m].
        sx: Velocity over the ground of their nominal places along body x [m/s].
        sy: The same along body y.

    """
    lag = None
    length, width = parameters.step_length, parameters.step_width
    for (dx, dy, *_), vx, vy in zip(offsets, sx, sy, strict=True):
        speed = math.hypot(vx, vy)
        if speed > 1e-3:
            ux, uy = vx / speed, vy / speed
            value = -(dx * ux + dy * uy) * math.sqrt((ux / length) ** 2 + (uy / width) ** 2)
            if lag is None or value > lag:  # max(lag, value)
                lag = value
    return 0.0 if lag is None else float(lag)


def landing(
    parameters: HexapodParameters,
    ground: Sequence[Pair],
    nominal: Sequence[Sequence[float]],
    velocity: Pair,
    setpoint: Pair,
    acceleration: Pair,
) -> list[list[float]]:
    """Where the swing feet land relative to the body (body axes, x and y) [m].

    Half a stance's travel plus a double support's ahead of their nominal place (the
    tripod's stance is then centred under the body: its feet go from half a stance ahead of
    their nominal places to half a stance behind), with the body's measured velocity and
    the commanded yaw rate, plus the Raibert term, minus ``height / g`` times the velocity
    set point's acceleration (the centre of pressure trails the centre of mass by that much
    while the body accelerates: without it the front foot of the next tripod unloads);
    within 0.6 strides of the nominal place.

    Args:
        parameters: The gait's constants.
        ground: `ground_velocity` of the swing feet's nominal points.
        nominal: The swing feet's nominal points ``(x, y, z)`` [m].
        velocity: The measured (low-passed) body velocity [m/s].
        setpoint: The velocity set point [m/s].
        acceleration: The velocity set point's acceleration [m/s^2].

    """
    p = parameters
    length, width = p.step_length, p.step_width
    rate = max([math.sqrt((x / length) ** 2 + (y / width) ** 2) for x, y in ground])  # [1/s]
    stance = p.max_stance_time if rate * p.max_stance_time <= 1.0 else 1.0 / rate
    (fx, fy), (cx, cy) = velocity, setpoint
    ax, ay = acceleration
    lean = p.height / GRAVITY  # the centre of pressure trails by lean * acceleration [s^2]
    ex = p.placement_gain * (fx - cx) - lean * ax
    ey = p.placement_gain * (fy - cy) - lean * ay
    lead = 0.5 * stance + p.double_support_time  # [s]
    places = []
    for (sx, sy), (x, y, _) in zip(ground, nominal, strict=True):
        ox, oy = lead * sx + ex, lead * sy + ey
        factor = min(1.0, 0.6 / max(math.sqrt((ox / length) ** 2 + (oy / width) ** 2), 1e-9))
        places.append([x + ox * factor, y + oy * factor])
    return places


def support_plane(
    stance: Sequence[Sequence[float]], previous: tuple[float, float, float]
) -> tuple[float, float, float]:
    """The ground plane ``z = a x + b y + c`` through three support feet, ``(a, b, c)``.

    Args:
        stance: The three feet ``(x, y, z)`` relative to the body, body axes [m].
        previous: The plane kept when the feet are in a line.

    """
    (x1, y1, z1), (x2, y2, z2), (x3, y3, z3) = stance
    ux, uy, uz, vx, vy, vz = x2 - x1, y2 - y1, z2 - z1, x3 - x1, y3 - y1, z3 - z1
    nx, ny, nz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx  # normal
    if abs(nz) > 1e-9:  # else the feet are in a line: keep the previous plane
        a, b = -nx / nz, -ny / nz
        return (a, b, z1 - a * x1 - b * y1)
    return previous


def swing_targets(
    starts: Sequence[Sequence[float]],
    places: Sequence[Pair],
    plane: tuple[float, float, float],
    reach: float,
    rest: float,
    up: float,
) -> list[tuple[float, float, float]]:
    """Where the swing feet are carried this tick, body axes [m].

    Args:
        starts: The feet's lift-off points ``(x, y, z)``.
        places: Their landing places ``(x, y)``.
        plane: The ground plane ``(a, b, c)`` (`support_plane`).
        reach: How far along from lift-off to landing, 0 to 1.
        rest: How much of the lift-off height above the plane is left, 1 to 0.
        up: The lift above the plane [m].

    """
    a, b, c = plane
    targets = []
    for (sx, sy, sz), (lx, ly) in zip(starts, places, strict=True):
        x, y = sx + (lx - sx) * reach, sy + (ly - sy) * reach
        above = sz - (a * sx + b * sy + c)  # lift-off height above the plane [m]
        targets.append((x, y, a * x + b * y + c + rest * above + up))
    return targets
