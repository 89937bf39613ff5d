"""The hexapod body's virtual components, in its heading frame (VAC 1996, section 4).

Roll and pitch are read about the heading (the body's yaw alone), as yaw, pitch, roll (Z-Y-X);
the wrenches are in world axes.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from ...components.base import Component
from ...components.slots import Slotted
from ...vocabulary.scalar import cos, sin
from ..attitude import rotation_vector_angles
from ..base import SizedSlots, SlotFormula, sized_slot


class HeadingAttitude(SlotFormula, SizedSlots, Slotted, Component):
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

    SIZES = {"stiffness": 2, "damping": 3, "roll": 1, "pitch": 1, "yaw_rate": 1}
    SLOTS = tuple(SIZES)
    GAINS = ("stiffness", "damping")

    def __init__(
        self, stiffness: Sequence[float], damping: Sequence[float], name: str | None = None
    ) -> None:
        super().__init__(("rx", "ry", "rz"), name)
        self.stiffness, self.damping = stiffness, damping
        self.roll = self.pitch = self.yaw_rate = 0.0

    stiffness = sized_slot("stiffness", "``(roll, pitch)`` [N m/rad].")
    damping = sized_slot("damping", "``(roll, pitch, yaw)`` [N m s/rad].")
    roll = sized_slot("roll", "Roll set point [rad].", scalar=True)
    pitch = sized_slot("pitch", "Pitch set point [rad].", scalar=True)
    yaw_rate = sized_slot("yaw_rate", "Yaw rate set point [rad/s].", scalar=True)

    def _formula(self, slots: Mapping, position: Sequence, velocity: Sequence) -> list:
        """The moment, world axes, from the body's rotation vector and angular velocity."""
        yaw, pitch, roll = rotation_vector_angles(*position)
        c, s = cos(yaw), sin(yaw)
        v0, v1, v2 = velocity
        wx = c * v0 + s * v1  # angular velocity in the heading frame
        wy = -s * v0 + c * v1
        k0, k1 = slots["stiffness"]
        b0, b1, b2 = slots["damping"]
        (roll_d,), (pitch_d,), (rate_d,) = (slots[n] for n in ("roll", "pitch", "yaw_rate"))
        mx = k0 * (roll_d - roll) - b0 * wx
        my = k1 * (pitch_d - pitch) - b1 * wy
        mz = b2 * (rate_d - v2)
        return [c * mx - s * my, s * mx + c * my, mz]


class HeadingDamper(SlotFormula, SizedSlots, Slotted, Component):
    """Dampers toward a velocity given in the heading frame, plus a force in that frame.

    Args:
        damping: ``(along, across)`` the heading [N s/m].
        name: Label used in reports.

    Attributes:
        damping: As above; set ``damping[0] = 0`` to leave x to another law (an LQR's force).

    Raises:
        InvalidInputError: A damping that is not a finite number >= 0, or not two of them.
    """

    SIZES = {"damping": 2, "yaw": 1, "velocity": 2, "force": 2}
    SLOTS = tuple(SIZES)
    GAINS = ("damping",)

    def __init__(self, damping: Sequence[float], name: str | None = None) -> None:
        super().__init__(("x", "y"), name)
        self.damping = damping
        self.yaw = 0.0
        self.velocity = self.force = (0.0, 0.0)

    damping = sized_slot("damping", "``(along, across)`` the heading [N s/m].")
    yaw = sized_slot("yaw", "Heading of the body [rad].", scalar=True)
    velocity = sized_slot("velocity", "Commanded body velocity in the heading frame [m/s].")
    force = sized_slot("force", "Extra force in the heading frame ``(fx, fy)`` [N].")

    def _formula(self, slots: Mapping, position: Sequence, velocity: Sequence) -> list:
        """The force, world axes, from the body's velocity along world x and y."""
        (yaw,) = slots["yaw"]
        c, s = cos(yaw), sin(yaw)
        v0, v1 = velocity
        vx = c * v0 + s * v1
        vy = -s * v0 + c * v1
        d0, d1 = slots["damping"]
        cx, cy = slots["velocity"]
        f0, f1 = slots["force"]
        fx = d0 * (cx - vx) + f0
        fy = d1 * (cy - vy) + f1
        return [c * fx - s * fy, s * fx + c * fy]
