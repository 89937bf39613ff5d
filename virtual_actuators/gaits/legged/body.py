"""The body's virtual model: a spaceship held by springs and steered by dampers (VAC 1996, 4).

Its formulas are written with [`va.scalar`][virtual_actuators.scalar]: floats in Python, traced
ops in a compiled plan.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace

import numpy as np

from ...actuators.producible import RANK_TOL
from ...components.base import Component
from ...components.gains import Gains
from ...components.slots import Slotted
from ...vocabulary.axes import check_axes_subset
from ...vocabulary.scalar import cos, dot, maximum, select, sin, sqrt
from ..attitude import rotation_vector_angles
from ..base import SizedSlots, SlotFormula, sized_slot
from .parameters import GRAVITY, LeggedGains

AXES = ("x", "y", "z", "rx", "ry", "rz")


def body_wrench(
    gains: Sequence, setpoints: Sequence, position: Sequence, velocity: Sequence
) -> list:
    """The body model's wrench, world axes, about the body's origin.

    Args:
        gains: ``(11,)`` damping x, y; stiffness, damping z; stiffness roll, pitch; damping
            roll, pitch, yaw; mass; weight (SI units).
        setpoints: ``(8,)`` height [m], heading-frame velocity (2) [m/s] and its rate (2)
            [m/s^2], yaw rate [rad/s], the lever's x and y [m].
        position: ``(6,)`` the sensor's position and rotation vector [m, rad].
        velocity: ``(6,)`` linear and angular velocity, world axes [m/s, rad/s].

    Returns:
        ``[fx, fy, fz, mx, my, mz]`` [N, N m] (floats or traced values).
    """
    yaw, pitch, roll = rotation_vector_angles(position[3], position[4], position[5])
    c, s = cos(yaw), sin(yaw)
    v0, v1, v2, w0, w1, w2 = velocity
    vx = c * v0 + s * v1
    vy = -s * v0 + c * v1
    wx = c * w0 + s * w1
    wy = -s * w0 + c * w1
    height, set_x, set_y, ax, ay, yaw_rate, lever_x, lever_y = setpoints
    mass, weight = gains[9], gains[10]
    fx = gains[0] * (set_x - vx) + mass * ax
    fy = gains[1] * (set_y - vy) + mass * ay
    fz = weight + gains[2] * (height - position[2]) - gains[3] * v2
    mx = -gains[4] * roll - gains[6] * wx
    my = -gains[5] * pitch - gains[7] * wy
    mz = gains[8] * (yaw_rate - w2)
    return [
        c * fx - s * fy, s * fx + c * fy, fz,
        c * mx - s * my + lever_y * weight, s * mx + c * my - lever_x * weight, mz,
    ]  # fmt: skip


def give_way(wrench: Sequence, missing: Sequence, yielding: Sequence[int]) -> list:
    """``wrench`` made orthogonal to ``missing`` by the least move along the ``yielding`` axes.

    What those axes cannot absorb is projected out; a zero ``missing`` changes nothing.

    Args:
        wrench: ``(6,)`` the request.
        missing: ``(6,)`` the unit direction the support cannot produce, or zeros.
        yielding: Indices of the axes that give way.

    Returns:
        The producible request ``(6,)``.
    """
    across = [missing[axis] for axis in yielding]  # how each yielding axis moves the gap
    gap = dot(missing, wrench)
    norm2 = dot(across, across)
    moves = norm2 > 1e-12
    ratio = gap / maximum(norm2, 1e-12)
    out = list(wrench)
    for axis, amount in zip(yielding, across, strict=True):
        out[axis] = select(moves, wrench[axis] - amount * ratio, wrench[axis])
    rest = dot(missing, out)
    return [value - direction * rest for value, direction in zip(out, missing, strict=True)]


def missing_direction(body: Sequence, first: Sequence, second: Sequence) -> tuple:
    """``(r x d, d)`` normalised: the unit wrench two point contacts cannot produce, world axes.

    ``d`` runs from the first contact to the second, ``r`` from the body's origin to the first.

    Args:
        body: The body's origin, world [m].
        first: The first contact, world [m].
        second: The second contact, world [m].

    Returns:
        ``(6,)`` the direction, or zeros when the contacts coincide.
    """
    x, y, z = (first[i] - body[i] for i in range(3))
    dx, dy, dz = (second[i] - first[i] for i in range(3))
    apart = dx * dx + dy * dy + dz * dz > RANK_TOL * maximum(x * x + y * y + z * z, 1e-300)
    values = (y * dz - z * dy, z * dx - x * dz, x * dy - y * dx, dx, dy, dz)
    norm = sqrt(maximum(dot(values, values), 1e-300))
    return tuple(select(apart, value / norm, 0.0) for value in values)


class BodyModel(SlotFormula, SizedSlots, Slotted, Component):
    """Height, roll and pitch springs, x, y and yaw dampers, in the heading frame.

    The weight is carried at the centre of mass; x and y add the mass times the set point's
    acceleration. Where the support cannot produce the request (`missing`), it gives way along
    `yielding` (`give_way`).

    Args:
        mass: The robot's mass [kg] (its weight is carried).
        gains: The stiffnesses and dampings.
        yielding: Axes that give way first when the support cannot produce the request.
        name: Label used in reports.

    Attributes:
        yielding: Indices of the axes that give way.

    Raises:
        InvalidAxisError: A yielding axis that is not one of `AXES`.
    """

    SIZES = {"height": 1, "velocity": 2, "acceleration": 2, "yaw_rate": 1, "lever": 3, "missing": 6}
    SLOTS = ("packed", *SIZES)

    def __init__(
        self,
        mass: float,
        gains: LeggedGains,
        yielding: tuple[str, ...] = ("x", "y"),
        name: str = "body",
    ) -> None:
        super().__init__(AXES, name)
        self.yielding = tuple(
            AXES.index(axis) for axis in check_axes_subset(yielding, AXES, "give way axes")
        )
        self._mass = float(mass)
        self.gains = gains
        for name, size in self.SIZES.items():  # every set point at zero
            setattr(self, name, (0.0,) * size)

    @property
    def gains(self) -> LeggedGains:
        """The stiffnesses and dampings."""
        return self._legged

    @gains.setter
    def gains(self, gains: LeggedGains) -> None:
        self._legged = g = gains
        mass = self._mass  # slot ``packed``: the gains as `body_wrench` reads them
        self._assign("_packed", np.array((
            *g.damping_xy, g.stiffness_z, g.damping_z, *g.stiffness_attitude,
            *g.damping_attitude, mass, mass * GRAVITY,
        )))  # fmt: skip

    height = sized_slot("height", "Height set point of the body's origin [m].", scalar=True)
    velocity = sized_slot("velocity", "Velocity set point in the heading frame [m/s].")
    acceleration = sized_slot("acceleration", "The velocity set point's rate [m/s^2].")
    yaw_rate = sized_slot("yaw_rate", "Yaw rate set point [rad/s].", scalar=True)
    lever = sized_slot("lever", "Centre of mass minus the body's origin, world axes [m].")
    missing = sized_slot("missing", "The unit wrench the support cannot produce, or zeros.")

    def linear_gains(self) -> Gains:
        """Stiffness and damping on `AXES` (the heading frame's, world axes when level)."""
        g = self._legged
        stiffness = (0.0, 0.0, g.stiffness_z, *g.stiffness_attitude, 0.0)
        damping = (*g.damping_xy, g.damping_z, *g.damping_attitude)
        return Gains(np.array(stiffness), np.array(damping))

    def scale_gains(self, factor: np.ndarray) -> None:
        """Multiply the stiffness and damping of each axis by ``factor`` (``(6,)``)."""
        fx, fy, fz, froll, fpitch, fyaw = (float(f) for f in factor)
        g = self._legged
        (k_roll, k_pitch), (d_roll, d_pitch, d_yaw) = g.stiffness_attitude, g.damping_attitude
        self.gains = replace(
            g,
            stiffness_z=g.stiffness_z * fz,
            damping_z=g.damping_z * fz,
            stiffness_attitude=(k_roll * froll, k_pitch * fpitch),
            damping_attitude=(d_roll * froll, d_pitch * fpitch, d_yaw * fyaw),
            damping_xy=(g.damping_xy[0] * fx, g.damping_xy[1] * fy),
        )

    def _formula(self, slots: Mapping, position: Sequence, velocity: Sequence) -> list:
        """`body_wrench` given way (`give_way`), on the slots as floats or traced values."""
        (height,), (yaw_rate,), lever = slots["height"], slots["yaw_rate"], slots["lever"]
        setpoints = (height, *slots["velocity"], *slots["acceleration"], yaw_rate, *lever[:2])
        wrench = body_wrench(slots["packed"], setpoints, position, velocity)
        return give_way(wrench, slots["missing"], self.yielding)
