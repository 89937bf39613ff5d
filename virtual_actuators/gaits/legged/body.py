"""The body's virtual model: a spaceship held by springs and steered by dampers (VAC 1996, 4).

:class:`BodyModel` is one component on all six axes of the support actuator (reference the
world, action the body), acting in the body's *heading frame* (its yaw alone):

* height ``z``: a spring-damper to the set point, plus the robot's weight;
* roll and pitch: spring-dampers about the heading axes;
* ``x``, ``y``: dampers toward the commanded velocity in the heading frame, plus the mass times
  the set point's acceleration;
* yaw: a damper toward the commanded yaw rate;
* the weight acts at the centre of mass: its moment about the body's origin is added.

When the gait gives it the support's producible directions (:attr:`BodyModel.basis`, from
:meth:`ParallelVirtualActuator.producible <virtual_actuators.ParallelVirtualActuator.producible>`),
the request gives way along :attr:`BodyModel.yielding` (by default the horizontal force) just
enough to become producible, and stays exact on the rest
(:func:`~virtual_actuators.actuators.producible.give_way`). With two point feet the moment about
the line between them cannot be produced: yielding the horizontal force lets the centre of mass
move away from that line as an inverted pendulum does (``m g e / h`` for an offset ``e``) while
height, roll, pitch and yaw stay exact; yielding the moments instead would spin the body against
its legs.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from ...actuators.producible import Directions, give_way
from ...components.base import Component
from .parameters import GRAVITY, LeggedGains

AXES = ("x", "y", "z", "rx", "ry", "rz")


def yaw_pitch_roll(rotation: np.ndarray) -> tuple[float, float, float]:
    """Z-Y-X angles of a rotation matrix ``R = Rz(yaw) Ry(pitch) Rx(roll)`` [rad]."""
    yaw = math.atan2(rotation[1, 0], rotation[0, 0])
    pitch = math.asin(max(-1.0, min(1.0, -rotation[2, 0])))
    roll = math.atan2(rotation[2, 1], rotation[2, 2])
    return yaw, pitch, roll


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
        basis: The support's :class:`~virtual_actuators.actuators.producible.Directions`, or
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

    def compute_wrench(self, position: np.ndarray, velocity: np.ndarray, time: float) -> np.ndarray:
        """The wrench on the body, world axes (given way where the support cannot produce it)."""
        g = self.gains
        yaw, pitch, roll = yaw_pitch_roll(pin.exp3(position[3:]))
        self.yaw = yaw
        c, s = math.cos(yaw), math.sin(yaw)
        v0, v1, v2, w0, w1, w2 = velocity.tolist()
        vx = c * v0 + s * v1
        vy = -s * v0 + c * v1
        wx = c * w0 + s * w1
        wy = -s * w0 + c * w1
        ax, ay = self.acceleration
        fx = g.damping_xy[0] * (self.velocity[0] - vx) + self.mass * ax
        fy = g.damping_xy[1] * (self.velocity[1] - vy) + self.mass * ay
        weight = self.mass * GRAVITY
        fz = weight + g.stiffness_z * (self.height - float(position[2])) - g.damping_z * v2
        k, b = g.stiffness_attitude, g.damping_attitude
        mx = -k[0] * roll - b[0] * wx
        my = -k[1] * pitch - b[1] * wy
        mz = b[2] * (self.yaw_rate - w2)
        lever = np.asarray(self.lever, dtype=float).tolist()
        wrench = np.array(
            (
                c * fx - s * fy,
                s * fx + c * fy,
                fz,
                c * mx - s * my + lever[1] * weight,
                s * mx + c * my - lever[0] * weight,
                mz,
            )
        )
        if self.basis is not None:
            wrench = give_way(self.basis.producible, wrench, self.yielding, self.basis.missing)
        return wrench


__all__ = ["AXES", "BodyModel", "yaw_pitch_roll"]
