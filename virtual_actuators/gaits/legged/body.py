"""The body's virtual model: a spaceship held by springs and steered by dampers (VAC 1996, 4).

[`BodyModel`][] is one component on all six axes of the support actuator (reference the
world, action the body), acting in the body's *heading frame* (its yaw alone):

* height ``z``: a spring-damper to the set point, plus the robot's weight;
* roll and pitch: spring-dampers about the heading axes;
* ``x``, ``y``: dampers toward the commanded velocity in the heading frame, plus the mass times
  the set point's acceleration;
* yaw: a damper toward the commanded yaw rate;
* the weight acts at the centre of mass: its moment about the body's origin is added.

When the gait gives it the support's producible directions (`BodyModel.basis`, from
[`ParallelVirtualActuator.producible`][virtual_actuators.ParallelVirtualActuator.producible]),
the request gives way along `BodyModel.yielding` (by default the horizontal force) just
enough to become producible, and stays exact on the rest
([`give_way`][]). With two point feet the moment about
the line between them cannot be produced: yielding the horizontal force lets the centre of mass
move away from that line as an inverted pendulum does (``m g e / h`` for an offset ``e``) while
height, roll, pitch and yaw stay exact; yielding the moments instead would spin the body against
its legs.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pinocchio as pin

from ...actuators.producible import Directions, give_way
from ...components.base import Component
from ...components.gains import Gains
from ...core import CORE
from ..attitude import yaw_pitch_roll
from .parameters import GRAVITY, LeggedGains

AXES = ("x", "y", "z", "rx", "ry", "rz")


class BodyModel(Component):
    """Height, roll and pitch springs, x, y and yaw dampers, in the heading frame.

    Reads the body's pose in the world (position, rotation vector) and its velocity (linear,
    angular, world axes); returns the wrench on the body in world axes about its origin.

    Args:
        mass: The robot's mass [kg] (its weight is carried).
        gains: The stiffnesses and dampings.
        yielding: Axes that give way first when the support cannot produce the request.
        name: Label used in reports.

    Attributes:
        height: Height set point of the body's origin [m] (the gait moves it with the ground).
        velocity: Velocity set point in the heading frame ``(vx, vy)`` [m/s].
        acceleration: Its rate, in the heading frame [m/s^2].
        yaw_rate: Yaw rate set point [rad/s].
        lever: Centre of mass minus the body's origin, world axes [m].
        basis: The support's [`Directions`][], or
            None (every wrench producible).
        yielding: ``(6, m)`` unit columns of the yielding axes.
        yaw: The body's yaw at the last evaluation [rad].

    """

    def __init__(
        self,
        mass: float,
        gains: LeggedGains,
        yielding: tuple[str, ...] = ("x", "y"),
        name: str = "body",
    ) -> None:
        super().__init__(AXES, name)
        self.yielding = np.eye(6)[:, [AXES.index(axis) for axis in yielding]]
        self.mass = float(mass)
        self.gains = gains
        self.height = 0.0
        self.velocity = (0.0, 0.0)
        self.acceleration = (0.0, 0.0)
        self.yaw_rate = 0.0
        self.lever = np.zeros(3)
        self.basis: Directions | None = None
        self.yaw = 0.0

    @property
    def gains(self) -> LeggedGains:
        """The stiffnesses and dampings."""
        return self._gains

    @gains.setter
    def gains(self, gains: LeggedGains) -> None:
        self._gains = gains
        self._pack()

    @property
    def mass(self) -> float:
        """The robot's mass [kg]."""
        return self._mass

    @mass.setter
    def mass(self, mass: float) -> None:
        self._mass = float(mass)
        self._pack()

    def _pack(self) -> None:
        """The gains as `body_wrench` reads them."""
        g, mass = getattr(self, "_gains", None), getattr(self, "_mass", None)
        if g is not None and mass is not None:
            self._packed = np.array((
                *g.damping_xy, g.stiffness_z, g.damping_z, *g.stiffness_attitude,
                *g.damping_attitude, mass, mass * GRAVITY,
            ))  # fmt: skip

    def linear_gains(self) -> Gains:
        """Stiffness and damping on `AXES` (the heading frame's, world axes when level)."""
        g = self._gains
        stiffness = (0.0, 0.0, g.stiffness_z, *g.stiffness_attitude, 0.0)
        damping = (*g.damping_xy, g.damping_z, *g.damping_attitude)
        return Gains(np.array(stiffness), np.array(damping))

    def scale_gains(self, factor: np.ndarray) -> None:
        """Multiply the stiffness and damping of each axis by ``factor`` (``(6,)``)."""
        fx, fy, fz, froll, fpitch, fyaw = (float(f) for f in factor)
        g = self._gains
        (k_roll, k_pitch), (d_roll, d_pitch, d_yaw) = g.stiffness_attitude, g.damping_attitude
        self.gains = replace(
            g,
            stiffness_z=g.stiffness_z * fz,
            damping_z=g.damping_z * fz,
            stiffness_attitude=(k_roll * froll, k_pitch * fpitch),
            damping_attitude=(d_roll * froll, d_pitch * fpitch, d_yaw * fyaw),
            damping_xy=(g.damping_xy[0] * fx, g.damping_xy[1] * fy),
        )

    def compute_wrench(self, position: np.ndarray, velocity: np.ndarray, time: float) -> np.ndarray:
        """The wrench on the body, world axes (given way where the support cannot produce it)."""
        lever_x, lever_y, _ = self.lever.tolist()
        setpoints = np.array((
            self.height, *self.velocity, *self.acceleration, self.yaw_rate, lever_x, lever_y
        ))  # fmt: skip
        wrench = np.empty(6)
        rotation = pin.exp3(position[3:])
        self.yaw = _BODY_WRENCH(rotation, position, velocity, self._packed, setpoints, wrench)
        if self.basis is not None:
            wrench = give_way(self.basis.producible, wrench, self.yielding, self.basis.missing)
        return wrench


def body_wrench(
    rotation: np.ndarray, position: np.ndarray, velocity: np.ndarray, gains: np.ndarray,
    setpoints: np.ndarray, out: np.ndarray,
) -> float:
    """The body model's wrench (module docstring) into ``out``; returns the body's yaw.

    Args:
        rotation: ``(3, 3)`` the body's orientation in the world.
        position: ``(6,)`` the sensor's position (its height at index 2) [m].
        velocity: ``(6,)`` linear and angular velocity, world axes [m/s, rad/s].
        gains: ``(11,)`` damping along and across the heading, stiffness and damping of the
            height, stiffness of roll and pitch, damping of roll, pitch and yaw, the mass and
            the weight (SI units).
        setpoints: ``(8,)`` height [m], velocity in the heading frame (2) [m/s], its rate (2)
            [m/s^2], yaw rate [rad/s], and the lever's x and y [m].
        out: ``(6,)`` written: the wrench, world axes, about the body's origin [N, N m].

    """
    yaw = math.atan2(rotation[1, 0], rotation[0, 0])
    pitch = math.asin(max(-1.0, min(1.0, -rotation[2, 0])))
    roll = math.atan2(rotation[2, 1], rotation[2, 2])
    c, s = math.cos(yaw), math.sin(yaw)
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
    out[0] = c * fx - s * fy
    out[1] = s * fx + c * fy
    out[2] = fz
    out[3] = c * mx - s * my + lever_y * weight
    out[4] = s * mx + c * my - lever_x * weight
    out[5] = mz
    return yaw


#: :func:`body_wrench` as the gait calls it: the compiled core's port when it is built
#: (``src/core/gait.hpp``, the same bits).
_BODY_WRENCH = CORE.body_wrench if CORE is not None else body_wrench

__all__ = ["AXES", "BodyModel", "body_wrench", "yaw_pitch_roll"]
