"""Contact settings of the MuJoCo model: friction, softness and which geoms collide."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import mujoco

from virtual_actuators.exceptions import InvalidInputError

__all__ = [
    "ROBOT_BITS",
    "ROBOT_SELF_BITS",
    "TERRAIN_BITS",
    "ContactParameters",
    "set_contact",
]

# Collision bits: robot geoms (contype 2, conaffinity 1) touch the terrain (contype 1,
# conaffinity 2) but not each other unless self-collisions are enabled (both 3).
TERRAIN_BITS = (1, 2)
ROBOT_BITS = (2, 1)
ROBOT_SELF_BITS = (3, 3)


@dataclass(frozen=True)
class ContactParameters:
    """Contact settings shared by every robot and terrain geom.

    Attributes:
        friction: Sliding friction coefficient (MuJoCo takes the larger of the two geoms').
        torsional_friction: Torsional friction [m] (``condim`` 4 or 6).
        rolling_friction: Rolling friction [m] (``condim`` 6).
        condim: 1 (frictionless), 3 (sliding friction), 4 (+ torsional) or 6 (+ rolling).
        solref: ``(time constant [s], damping ratio)``; the time constant should be at least
            twice the physics time step.
        solimp: MuJoCo's impedance ``(dmin, dmax, width [m], midpoint, power)``.
        margin: Distance [m] at which contacts become active.
        cone: Friction cone, ``"pyramidal"`` or ``"elliptic"``.
        self_collisions: Whether robot geoms collide with each other (never across a joint).
    """

    friction: float = 1.0
    torsional_friction: float = 0.005
    rolling_friction: float = 0.0001
    condim: int = 3
    solref: tuple[float, float] = (0.005, 1.0)
    solimp: tuple[float, float, float, float, float] = (0.9, 0.95, 0.001, 0.5, 2.0)
    margin: float = 0.0
    cone: Literal["pyramidal", "elliptic"] = "pyramidal"
    self_collisions: bool = False

    def __post_init__(self) -> None:
        if self.condim not in (1, 3, 4, 6):
            raise InvalidInputError(f"condim must be 1, 3, 4 or 6, got {self.condim!r}.")
        if self.cone not in ("pyramidal", "elliptic"):
            raise InvalidInputError(f"cone must be 'pyramidal' or 'elliptic', got {self.cone!r}.")
        values = (self.friction, self.torsional_friction, self.rolling_friction, self.margin)
        if not all(math.isfinite(v) and v >= 0.0 for v in values):
            raise InvalidInputError(
                "friction, torsional_friction, rolling_friction and margin must be finite and "
                f">= 0, got {values}."
            )
        if len(self.solref) != 2 or len(self.solimp) != 5:
            raise InvalidInputError("solref needs 2 values and solimp 5 values.")


def set_contact(
    geom: mujoco.MjsGeom, contact: ContactParameters, contype: int, conaffinity: int
) -> None:
    """Give a geom the settings of ``contact`` and its collision bits."""
    geom.contype = contype
    geom.conaffinity = conaffinity
    geom.condim = contact.condim
    geom.friction = [contact.friction, contact.torsional_friction, contact.rolling_friction]
    geom.solref = list(contact.solref)
    geom.solimp = list(contact.solimp)
    geom.margin = contact.margin
