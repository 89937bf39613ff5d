"""The hexapod body's virtual components, in its heading frame (VAC 1996, section 4).

Roll and pitch are read about the heading (the body's yaw alone), as yaw, pitch, roll (Z-Y-X);
the wrenches are in world axes.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ...components.base import Component
from ...components.slots import Slotted
from ...exceptions import InvalidInputError
from ...vocabulary.scalar import cos, sin
from ..attitude import rotation_vector_angles


def heading_moment(
    parameters: Mapping[str, Sequence], position: Sequence, velocity: Sequence
) -> list:
    """`HeadingAttitude`'s moment, world axes, on floats or traced values alike.

    Args:
        parameters: The component's slots by name, each a sequence of values.
        position: The body's rotation vector in the world.
        velocity: Its angular velocity, world axes [rad/s].

    Returns:
        ``[mx, my, mz]`` [N m].
    """
    yaw, pitch, roll = rotation_vector_angles(*position)
    c, s = cos(yaw), sin(yaw)
    v0, v1, v2 = velocity
    wx = c * v0 + s * v1  # angular velocity in the heading frame
    wy = -s * v0 + c * v1
    k0, k1 = parameters["stiffness"]
    b0, b1, b2 = parameters["damping"]
    (roll_d,), (pitch_d,), (rate_d,) = (parameters[n] for n in ("roll", "pitch", "yaw_rate"))
    mx = k0 * (roll_d - roll) - b0 * wx
    my = k1 * (pitch_d - pitch) - b1 * wy
    mz = b2 * (rate_d - v2)
    return [c * mx - s * my, s * mx + c * my, mz]


def heading_force(parameters: Mapping[str, Sequence], velocity: Sequence) -> list:
    """`HeadingDamper`'s force, world axes, on floats or traced values alike.

    Args:
        parameters: The component's slots by name.
        velocity: The body's velocity along world x and y [m/s].

    Returns:
        ``[fx, fy]`` [N].
    """
    (yaw,) = parameters["yaw"]
    c, s = cos(yaw), sin(yaw)
    v0, v1 = velocity
    vx = c * v0 + s * v1
    vy = -s * v0 + c * v1
    d0, d1 = parameters["damping"]
    cx, cy = parameters["velocity"]
    f0, f1 = parameters["force"]
    fx = d0 * (cx - vx) + f0
    fy = d1 * (cy - vy) + f1
    return [c * fx - s * fy, s * fx + c * fy]


class _Heading(Slotted, Component):
    """What both heading components share: their slots as validated parameters."""

    def _set(self, name: str, value: object, count: int, gains: bool = False) -> None:
        """Set slot ``name`` (``count`` finite numbers, >= 0 for ``gains``) or trace it.

        Raises:
            InvalidInputError: Not ``count`` finite numbers (>= 0 for gains).
        """
        if not self._store_traced(name, value):
            self._assign(f"_{name}", _numbers(value, count, f"{self.name}: {name}", gains))

    def _floats(self) -> dict[str, list[float]]:
        return {name: getattr(self, f"_{name}").tolist() for name in self.SLOTS}


class HeadingAttitude(_Heading):
    """Roll and pitch spring-dampers about the heading axes, and a yaw-rate damper.

    Reads the body's rotation vector and angular velocity in the world; returns, in world axes::

        m_heading = (k_roll (roll_d - roll) - b_roll w_x,
                     k_pitch (pitch_d - pitch) - b_pitch w_y,
                     b_yaw (yaw_rate_d - w_z))          (w in the heading frame)

    Args:
        stiffness: ``(roll, pitch)`` [N m/rad].
        damping: ``(roll, pitch, yaw)`` [N m s/rad].
        name: Label used in reports.

    Raises:
        InvalidInputError: A gain that is not a finite number >= 0, or not 2 (3) of them.
    """

    SLOTS = ("stiffness", "damping", "roll", "pitch", "yaw_rate")

    def __init__(
        self, stiffness: Sequence[float], damping: Sequence[float], name: str | None = None
    ) -> None:
        super().__init__(("rx", "ry", "rz"), name)
        self._set("stiffness", stiffness, 2, gains=True)
        self._set("damping", damping, 3, gains=True)
        self.roll = 0.0
        self.pitch = 0.0
        self.yaw_rate = 0.0

    @property
    def stiffness(self) -> np.ndarray:
        """``(roll, pitch)`` [N m/rad]."""
        return self._traced("stiffness")

    @property
    def damping(self) -> np.ndarray:
        """``(roll, pitch, yaw)`` [N m s/rad]."""
        return self._traced("damping")

    @property
    def roll(self) -> float:
        """Roll set point [rad]."""
        return self._traced("roll")[0]

    @roll.setter
    def roll(self, value: float) -> None:
        self._set("roll", value, 1)

    @property
    def pitch(self) -> float:
        """Pitch set point [rad]."""
        return self._traced("pitch")[0]

    @pitch.setter
    def pitch(self, value: float) -> None:
        self._set("pitch", value, 1)

    @property
    def yaw_rate(self) -> float:
        """Yaw rate set point [rad/s]."""
        return self._traced("yaw_rate")[0]

    @yaw_rate.setter
    def yaw_rate(self, value: float) -> None:
        self._set("yaw_rate", value, 1)

    def compute_wrench(self, position: np.ndarray, velocity: np.ndarray, time: float) -> np.ndarray:
        """Moment on the body in world axes from its rotation vector and angular velocity."""
        position, velocity = np.asarray(position, dtype=float), np.asarray(velocity, dtype=float)
        return np.array(heading_moment(self._floats(), position.tolist(), velocity.tolist()))

    def compute_wrench_floats(
        self, position: list[float], velocity: list[float], time: float
    ) -> list[float]:
        """`compute_wrench` on plain floats."""
        return heading_moment(self._floats(), position, velocity)

    def traced_wrench(self, slots, position: tuple, velocity: tuple, time: object) -> list:
        """`heading_moment` on a plan's traced slots and readings."""
        return heading_moment(slots, position, velocity)


class HeadingDamper(_Heading):
    """Dampers toward a velocity given in the heading frame, plus a force in that frame.

    Args:
        damping: ``(along, across)`` the heading [N s/m].
        name: Label used in reports.

    Attributes:
        damping: As above; set ``damping[0] = 0`` to leave x to another law (an LQR's force).

    Raises:
        InvalidInputError: A damping that is not a finite number >= 0, or not two of them.
    """

    SLOTS = ("damping", "yaw", "velocity", "force")

    def __init__(self, damping: Sequence[float], name: str | None = None) -> None:
        super().__init__(("x", "y"), name)
        self.damping = damping
        self.yaw = 0.0
        self.velocity = (0.0, 0.0)
        self.force = (0.0, 0.0)

    @property
    def damping(self) -> np.ndarray:
        """``(along, across)`` the heading [N s/m]."""
        return self._traced("damping")

    @damping.setter
    def damping(self, value: Sequence[float]) -> None:
        self._set("damping", value, 2, gains=True)

    @property
    def yaw(self) -> float:
        """Heading of the body [rad]."""
        return self._traced("yaw")[0]

    @yaw.setter
    def yaw(self, value: float) -> None:
        self._set("yaw", value, 1)

    @property
    def velocity(self) -> np.ndarray:
        """Commanded body velocity in the heading frame ``(vx, vy)`` [m/s]."""
        return self._traced("velocity")

    @velocity.setter
    def velocity(self, value: Sequence[float]) -> None:
        self._set("velocity", value, 2)

    @property
    def force(self) -> np.ndarray:
        """Extra force in the heading frame ``(fx, fy)`` [N]."""
        return self._traced("force")

    @force.setter
    def force(self, value: Sequence[float]) -> None:
        self._set("force", value, 2)

    def compute_wrench(self, position: np.ndarray, velocity: np.ndarray, time: float) -> np.ndarray:
        """Force on the body in world axes."""
        floats = np.asarray(velocity, dtype=float).tolist()
        return np.array(heading_force(self._floats(), floats))

    def compute_wrench_floats(
        self, position: list[float], velocity: list[float], time: float
    ) -> list[float]:
        """`compute_wrench` on plain floats."""
        return heading_force(self._floats(), velocity)

    def traced_wrench(self, slots, position: tuple, velocity: tuple, time: object) -> list:
        """`heading_force` on a plan's traced slots and reading."""
        return heading_force(slots, velocity)


def _numbers(values: object, count: int, what: str, gains: bool) -> np.ndarray:
    """``values`` as ``count`` finite numbers (>= 0 for ``gains``).

    Raises:
        InvalidInputError: Not ``count`` finite numbers (>= 0 for gains).
    """
    bound = " >= 0" if gains else ""
    try:
        array = np.array(values, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InvalidInputError(f"{what} must be {count} numbers{bound}, got {values!r}.") from None
    negative = gains and np.any(array < 0.0)
    if array.shape != (count,) or not np.all(np.isfinite(array)) or negative:
        raise InvalidInputError(f"{what} must be {count} finite numbers{bound}, got {values!r}.")
    return array
