"""The terrain geoms of the MuJoCo model, and the contact settings of every geom."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import mujoco
import numpy as np

from virtual_actuators.exceptions import InvalidInputError
from virtual_actuators.simulation.terrain import Terrain
from virtual_actuators.vocabulary.arguments import check_number

#: Thickness of the terrain boxes, perpendicular to the surface [m].
TERRAIN_THICKNESS = 0.2

#: Length of the level terrain boxes before the first and after the last profile point [m].
TERRAIN_RUN = 50.0

#: Prefix of the names of the terrain geoms.
TERRAIN_PREFIX = "terrain_"


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
        for name in ("friction", "torsional_friction", "rolling_friction", "margin"):
            check_number(getattr(self, name), f"ContactParameters: {name}", minimum=0.0)
        if len(self.solref) != 2 or len(self.solimp) != 5:
            raise InvalidInputError("solref needs 2 values and solimp 5 values.")


def set_contact(geom: mujoco.MjsGeom, contact: ContactParameters, bits: tuple[int, int]) -> None:
    """Give a geom the settings of ``contact`` and its collision bits (contype, conaffinity)."""
    geom.contype, geom.conaffinity = bits
    geom.condim = contact.condim
    geom.friction = [contact.friction, contact.torsional_friction, contact.rolling_friction]
    geom.solref = list(contact.solref)
    geom.solimp = list(contact.solimp)
    geom.margin = contact.margin


def add_terrain(spec: mujoco.MjSpec, terrain: Terrain, contact: ContactParameters) -> list[str]:
    """Add the terrain to the world body (a plane, or a box per segment); return the geom names."""
    world = spec.worldbody
    names = []
    if terrain.is_flat:
        height = float(terrain.points[0, 1])
        geom = world.add_geom(
            name=f"{TERRAIN_PREFIX}plane",
            type=mujoco.mjtGeom.mjGEOM_PLANE,
            pos=[0.0, 0.0, height],
            size=[0.0, 0.0, 0.05],
        )
        set_contact(geom, contact, TERRAIN_BITS)
        geom.rgba = [0.45, 0.5, 0.45, 1.0]
        return [geom.name]
    segments = terrain.segments(TERRAIN_RUN)
    for i, ((x0, z0), (x1, z1)) in enumerate(segments):
        dx, dz = x1 - x0, z1 - z0
        length = math.hypot(dx, dz)
        angle = math.atan2(dz, dx)  # slope, uphill positive
        normal = np.array([-math.sin(angle), 0.0, math.cos(angle)])
        centre = np.array([(x0 + x1) / 2.0, 0.0, (z0 + z1) / 2.0])
        centre -= normal * (TERRAIN_THICKNESS / 2.0)  # the box's top face on the segment
        label = "run_in" if i == 0 else "run_out" if i == len(segments) - 1 else f"segment_{i - 1}"
        # A rotation by -angle about y takes the box's x axis onto the segment direction.
        quat = [math.cos(-angle / 2.0), 0.0, math.sin(-angle / 2.0), 0.0]
        geom = world.add_geom(
            name=f"{TERRAIN_PREFIX}{label}",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            pos=centre,
            quat=quat,
            size=[length / 2.0, terrain.width / 2.0, TERRAIN_THICKNESS / 2.0],
        )
        set_contact(geom, contact, TERRAIN_BITS)
        geom.rgba = [0.45, 0.5, 0.45, 1.0] if i % 2 else [0.5, 0.55, 0.5, 1.0]
        names.append(geom.name)
    return names
