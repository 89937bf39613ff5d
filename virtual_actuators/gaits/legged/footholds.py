"""Where a swing foot lands and the curve that carries it there (world axes).

The foothold (`foothold`) is the foot's nominal place under the centre of mass (the
standing stance, centred on it), turned by half the stance's yaw, moved by half the stance's
travel at the velocity set point (the feed-forward: the stance is then centred under the body)
and by the capture term (``sqrt(h / g)`` times the velocity error, Raibert's correction), all in
the heading frame predicted for touchdown. `swing_point` is the swing curve: a smooth
reach from lift-off to the foothold and a lift profile above the line between their heights.
`SwingFeet` keeps the swinging feet's lift-off points and set points and moves their
springs every tick with one compiled call (`swing_setpoints`: every swinging foot, plain
loops).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

import numpy as np

from ...core import CORE
from ..planar import lift_profile, smoothstep


def foothold(
    x: float, y: float, vx: float, vy: float, ex: float, ey: float, yaw_rate: float,
    stance_time: float, capture_time: float, reach: float,
) -> tuple[float, float]:
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
    c, s = math.cos(angle), math.sin(angle)
    dx = c * x - s * y - x + vx * half + capture_time * ex
    dy = s * x + c * y - y + vy * half + capture_time * ey
    scale = min(1.0, reach / max(math.hypot(dx, dy), 1e-12))
    return x + scale * dx, y + scale * dy


def swing_point(
    start: np.ndarray, x: float, y: float, z: float, phase: float, lift: float, peak: float
) -> tuple[float, float, float]:
    """The swing foot's set point at ``phase`` (0 at lift-off, 1 at touchdown), world [m].

    From ``start`` (lift-off) to the landing point ``(x, y, z)``: horizontally a smooth step
    that arrives at 80 % of the swing; vertically a smooth step between the two heights plus
    ``lift`` times `lift_profile`. Past phase 1 it stays
    at the foothold (the gait lowers ``z`` instead).
    """
    x0, y0, z0 = start[0], start[1], start[2]
    reach = smoothstep(min(1.0, 1.25 * phase))
    height = z0 + (z - z0) * smoothstep(phase) + lift * lift_profile(phase, peak)
    return x0 + (x - x0) * reach, y0 + (y - y0) * reach, height


def swing_setpoints(
    feet: np.ndarray, swing: np.ndarray, nominal: np.ndarray, body: np.ndarray,
    motion: np.ndarray, dt: float, shape: np.ndarray, out: np.ndarray,
) -> None:
    """The set points of the feet ``feet`` index, relative to the body, and their velocities.

    Each foot lands at its `foothold` turned into the heading predicted for touchdown
    around the centre of mass predicted for it, the ground ``depth`` below the support (deeper
    past the planned touchdown: a depth per quarter swing), along `swing_point`; the set
    point's velocity is low-pass filtered (time constant ``shape[7]``) and written relative to
    the body (minus its velocity and ``angular x offset``).

    Args:
        feet: ``(k,)`` indices of the swinging feet (rows of the per-foot arrays).
        swing: ``(f, 9)`` per foot: lift-off point, last set point, its velocity (the last two
            updated) [m, m/s], world.
        nominal: ``(f, 2)`` the feet's nominal places (`foothold`'s ``x``, ``y``) [m].
        body: ``(12,)`` centre of mass, the body's origin, its velocity and angular velocity,
            world [m, m/s, rad/s].
        motion: ``(8,)`` velocity set point and its error (measured minus set) in the
            heading frame (``vx, vy, ex, ey``), yaw rate set point, yaw, time in the swing and
            ground height [m/s, rad/s, rad, s, m].
        dt: Time since the last set points [s] (0: their velocities are kept).
        shape: ``(8,)`` swing time, stance time, capture time, reach, lift, lift peak (a
            phase), touchdown depth, rate filter [s, s, s, m, m, -, m, s].
        out: ``(k, 6)`` written: the set points minus the body's origin and their velocities
            relative to the body, world axes.

    """
    vx, vy, ex, ey, yaw_rate, yaw, elapsed, ground = motion
    swing_time, stance_time, capture, reach, lift, peak, depth, rate_filter = shape
    phase = elapsed / swing_time
    remaining = max(0.0, swing_time - elapsed)
    heading = yaw + yaw_rate * remaining
    c, s = math.cos(heading), math.sin(heading)
    cy, sy = math.cos(yaw), math.sin(yaw)
    centre_x = body[0] + remaining * (cy * vx - sy * vy)  # the centre of mass at touchdown
    centre_y = body[1] + remaining * (sy * vx + cy * vy)
    depth = depth * (1.0 + 4.0 * max(0.0, phase - 1.0))
    blend = min(1.0, dt / rate_filter) if dt > 0.0 else 0.0
    a0, a1, a2 = body[9], body[10], body[11]
    for j in range(feet.shape[0]):
        k = feet[j]
        x, y = foothold(
            nominal[k, 0], nominal[k, 1], vx, vy, ex, ey, yaw_rate, stance_time, capture, reach
        )
        target = swing_point(
            swing[k, :3], centre_x + c * x - s * y, centre_y + s * x + c * y, ground - depth,
            phase, lift, peak,
        )  # fmt: skip
        for i in range(3):
            if dt > 0.0:
                swing[k, 6 + i] += blend * ((target[i] - swing[k, 3 + i]) / dt - swing[k, 6 + i])
            swing[k, 3 + i] = target[i]
            out[j, i] = target[i] - body[3 + i]
        o0, o1, o2 = out[j, 0], out[j, 1], out[j, 2]
        out[j, 3] = swing[k, 6] - body[6] - (a1 * o2 - a2 * o1)
        out[j, 4] = swing[k, 7] - body[7] - (a2 * o0 - a0 * o2)
        out[j, 5] = swing[k, 8] - body[8] - (a0 * o1 - a1 * o0)


#: :func:`swing_setpoints` as :class:`SwingFeet` calls it: the compiled core's port when it is
#: built (``src/core/gait.hpp``, the same bits).
_SWING_SETPOINTS = CORE.swing_setpoints if CORE is not None else swing_setpoints


class SwingFeet:
    """The swing feet's state and their springs, moved by one compiled call a tick.

    Args:
        feet: The foot frames.
        nominal: ``(len(feet), 2)`` their nominal places relative to the centre of mass,
            heading frame [m].
        springs: Each foot's swing spring, on world axes ``x, y, z`` from the body (its set
            point and velocity set point are written in place: the spring reads them every
            tick).
        shape: `swing_setpoints`'s ``shape``.

    Attributes:
        time: When the set points were last set [s].

    """

    def __init__(
        self, feet: Sequence[str], nominal: np.ndarray, springs: Iterable, shape: Sequence[float]
    ) -> None:
        self.index = {foot: k for k, foot in enumerate(feet)}
        self.springs = tuple(springs)
        self.nominal = np.array(nominal, dtype=float)
        self.shape = np.array(shape, dtype=float)
        self.swing = np.zeros((len(feet), 9))  # lift-off, set point, its velocity
        self.time = 0.0
        self._out = np.zeros((len(feet), 6))
        self._indices: dict[tuple[str, ...], np.ndarray] = {}

    def lift_off(self, foot: str, position: np.ndarray) -> None:
        """A swing starts at ``position`` (world [m]): the set point there, at rest."""
        row = self.swing[self.index[foot]]
        row[:3] = row[3:6] = position
        row[6:] = 0.0

    def move(
        self, feet: tuple[str, ...], body: np.ndarray, motion: np.ndarray, time: float
    ) -> None:
        """Set the springs of ``feet`` along their curves (`swing_setpoints`).

        Args:
            feet: The feet swinging, not yet down.
            body: `swing_setpoints`'s ``body``.
            motion: Its ``motion``.
            time: Controller time [s].

        """
        indices = self._indices.get(feet)
        if indices is None:
            indices = self._indices[feet] = np.array([self.index[f] for f in feet], np.int64)
        out = self._out
        dt = time - self.time
        _SWING_SETPOINTS(indices, self.swing, self.nominal, body, motion, dt, self.shape, out)
        for j, k in enumerate(indices.tolist()):
            spring = self.springs[k]
            spring.setpoint[:] = out[j, :3]
            spring.velocity_setpoint[:] = out[j, 3:]
        self.time = time


__all__ = ["SwingFeet", "foothold", "swing_point", "swing_setpoints"]
