"""Where the hexapod's feet are and where they land: strides, lag behind, landing places.

Body axes throughout; every function runs on floats or traced values alike.
"""

from __future__ import annotations

from collections.abc import Sequence

from ...vocabulary.scalar import (
    hypot,
    logical_and,
    logical_not,
    logical_or,
    maximum,
    minimum,
    select,
    sqrt,
)  # fmt: skip
from ..planar import lift_profile, smoothstep
from .parameters import HexapodParameters
from .pendulum import GRAVITY

Pair = tuple


def ground_velocity(velocity: Pair, yaw_rate: object, nominal: Sequence[Sequence]) -> list:
    """Velocity over the ground of the nominal foot points, body axes [m/s].

    Args:
        velocity: The measured (low-passed) body velocity ``(vx, vy)`` [m/s].
        yaw_rate: The commanded yaw rate [rad/s].
        nominal: The nominal foot points ``(x, y, z)`` relative to the body [m].
    """
    vx, vy = velocity
    w = yaw_rate
    return [(vx - w * y, vy + w * x) for x, y, _ in nominal]


def strides(parameters: HexapodParameters, dx: object, dy: object) -> object:
    """A horizontal displacement in strides: the ellipse of axes step length and width is 1."""
    x, y = dx / parameters.step_length, dy / parameters.step_width
    return sqrt(x * x + y * y)


def behind(
    parameters: HexapodParameters,
    offsets: Sequence[Sequence],
    sx: Sequence,
    sy: Sequence,
) -> object:
    """How far the support feet are behind their nominal places, in strides (largest).

    Along each foot's motion relative to the body: -0.5 where the feet land, 0.5 where the
    stance ends; 0 when the body does not move.

    Args:
        parameters: The gait's step length and width.
        offsets: Support feet minus their nominal places, body axes, one row each [m].
        sx: Velocity over the ground of their nominal places along body x [m/s].
        sy: The same along body y.
    """
    lag, found = 0.0, None
    for (dx, dy, *_), vx, vy in zip(offsets, sx, sy, strict=True):
        speed = hypot(vx, vy)
        moving = speed > 1e-3
        safe = select(moving, speed, 1.0)  # a foot at rest is not counted (no division by 0)
        ux, uy = vx / safe, vy / safe
        value = -(dx * ux + dy * uy) * strides(parameters, ux, uy)
        if found is None:  # the first foot (a constant of the loop, not of the values)
            take, found = moving, moving
        else:
            take = logical_and(moving, logical_or(logical_not(found), value > lag))
            found = logical_or(found, moving)
        lag = select(take, value, lag)
    return lag


def landing(
    parameters: HexapodParameters,
    ground: Sequence[Pair],
    nominal: Sequence[Sequence],
    velocity: Pair,
    setpoint: Pair,
    acceleration: Pair,
) -> list:
    """Where the swing feet land relative to the body (body axes, x and y) [m].

    Half a stance's travel plus a double support's ahead of the nominal place, plus the
    Raibert term, minus ``height / g`` times the set point's acceleration; within 0.6 strides.

    Args:
        parameters: The gait's constants.
        ground: `ground_velocity` of the swing feet's nominal points.
        nominal: The swing feet's nominal points ``(x, y, z)`` [m].
        velocity: The measured (low-passed) body velocity [m/s].
        setpoint: The velocity set point [m/s].
        acceleration: The velocity set point's acceleration [m/s^2].
    """
    p = parameters
    rate: object = None  # [1/s]
    for x, y in ground:
        value = strides(p, x, y)
        rate = value if rate is None else maximum(rate, value)
    short = rate * p.max_stance_time <= 1.0
    stance = select(short, p.max_stance_time, 1.0 / select(short, 1.0, rate))
    (fx, fy), (cx, cy) = velocity, setpoint
    ax, ay = acceleration
    lean = p.height / GRAVITY  # the centre of pressure trails by lean * acceleration [s^2]
    ex = p.placement_gain * (fx - cx) - lean * ax
    ey = p.placement_gain * (fy - cy) - lean * ay
    lead = 0.5 * stance + p.double_support_time  # [s]
    places = []
    for (sx, sy), (x, y, _) in zip(ground, nominal, strict=True):
        ox, oy = lead * sx + ex, lead * sy + ey
        factor = minimum(1.0, 0.6 / maximum(strides(p, ox, oy), 1e-9))
        places.append((x + ox * factor, y + oy * factor))
    return places


def support_plane(stance: Sequence[Sequence], previous: tuple) -> tuple:
    """The ground plane ``z = a x + b y + c`` through three support feet, ``(a, b, c)``.

    Args:
        stance: The three feet ``(x, y, z)`` relative to the body, body axes [m].
        previous: The plane kept when the feet are in a line.
    """
    (x1, y1, z1), (x2, y2, z2), (x3, y3, z3) = stance
    ux, uy, uz, vx, vy, vz = x2 - x1, y2 - y1, z2 - z1, x3 - x1, y3 - y1, z3 - z1
    nx, ny, nz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx  # normal
    flat = abs(nz) > 1e-9  # else the feet are in a line: keep the previous plane
    safe = select(flat, nz, 1.0)
    a, b = -nx / safe, -ny / safe
    plane = (a, b, z1 - a * x1 - b * y1)
    return tuple(select(flat, new, old) for new, old in zip(plane, previous, strict=True))


def tripod_setpoints(
    parameters: HexapodParameters,
    feet: Sequence[Sequence],
    support: Sequence[int],
    swing: Sequence[int],
    nominal: Sequence[Sequence],
    motion: Sequence,
    foot_radius: float,
    previous: object,
) -> tuple:
    """The tripod's per-tick update: ground plane, lag, phase, landing, swing set points.

    The swing feet go from lift-off to landing by ``smoothstep(1.25 phase)``, above the plane by
    what is left of their lift-off height plus the lift.

    Args:
        parameters: The gait's constants.
        feet: The six feet relative to the body, body axes [m] (row i - 1 for leg i).
        support: The support tripod's rows of ``feet``.
        swing: The swing tripod's rows.
        nominal: The feet's nominal places relative to the body [m].
        motion: Body height [m], low-passed velocity (2), velocity set point (2) [m/s] and its
            acceleration (2) [m/s^2], yaw rate command [rad/s], time in stance, time step [s].
        foot_radius: The feet's radius [m].
        previous: The gait's memory: ``plane`` (3), ``phase``, ``lift_off``, ``targets`` and
            ``rates`` (9 each).

    Returns:
        ``(plane, phase, targets, rates)`` after this tick, and ``ground`` (the ground height
        under the body [m]).
    """
    p = parameters
    height, fx, fy, cx, cy, ax, ay, yaw_rate, elapsed, dt = motion
    plane = support_plane([feet[r] for r in support], previous.plane)
    ground = height + plane[2] - foot_radius
    velocities = ground_velocity((fx, fy), yaw_rate, nominal)
    offsets = [(feet[r][0] - nominal[r][0], feet[r][1] - nominal[r][1]) for r in support]
    lag = behind(p, offsets, *zip(*[velocities[r] for r in support], strict=True))
    progress = minimum(maximum(0.5 + lag, elapsed / p.max_stance_time), 1.0)
    phase = maximum(previous.phase, progress)  # never decreasing
    reach = smoothstep(minimum(1.0, 1.25 * phase))
    rest = 1.0 - smoothstep(phase)  # of the lift-off height above the plane
    up = p.lift * lift_profile(phase, p.lift_peak) - p.touchdown_depth * phase
    places = landing(
        p, [velocities[r] for r in swing], [nominal[r] for r in swing], (fx, fy), (cx, cy),
        (ax, ay),
    )  # fmt: skip
    lift_off, last, rates = previous.lift_off, previous.targets, previous.rates
    (a, b, c), targets = plane, []
    for k, (lx, ly) in enumerate(places):  # the swing feet carried from lift-off to landing
        sx, sy, sz = lift_off[3 * k : 3 * k + 3]
        x, y = sx + (lx - sx) * reach, sy + (ly - sy) * reach
        above = sz - (a * sx + b * sy + c)  # lift-off height above the plane [m]
        targets += (x, y, a * x + b * y + c + rest * above + up)
    moved = dt > 0.0  # the set points' velocity low-pass filtered
    blend = select(moved, minimum(1.0, dt / p.velocity_filter), 0.0)
    step = select(moved, dt, 1.0)
    new_rates = tuple(
        select(moved, rate + blend * ((value - old) / step - rate), rate)
        for value, old, rate in zip(targets, last, rates, strict=True)
    )
    return plane, phase, tuple(targets), new_rates, ground
