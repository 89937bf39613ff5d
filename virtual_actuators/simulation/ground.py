"""The terrain geoms of the MuJoCo model: one plane, or one box per profile segment."""

from __future__ import annotations

import math
from collections.abc import Iterable

import mujoco
import numpy as np

from virtual_actuators.simulation.contact import TERRAIN_BITS, ContactParameters, set_contact
from virtual_actuators.simulation.terrain import Terrain

__all__ = [
    "CLEARANCE_RANGE",
    "TERRAIN_GROUP",
    "TERRAIN_PREFIX",
    "TERRAIN_RUN",
    "TERRAIN_THICKNESS",
    "add_terrain",
    "ground_clearance",
]

#: Farthest distance between the robot and the terrain that :func:`ground_clearance` measures [m].
CLEARANCE_RANGE = 100.0

#: Thickness of the terrain boxes, perpendicular to the surface [m].
TERRAIN_THICKNESS = 0.2

#: Length of the level terrain boxes before the first and after the last profile point [m].
TERRAIN_RUN = 50.0

#: Prefix of the names of the terrain geoms.
TERRAIN_PREFIX = "terrain_"

#: Geom group of the terrain (MuJoCo's visualiser shows groups 0-2 by default).
TERRAIN_GROUP = 0


def add_terrain(spec: mujoco.MjSpec, terrain: Terrain, contact: ContactParameters) -> list[str]:
    """Add the terrain geoms to the world body; return their names."""
    world = spec.worldbody
    contype, conaffinity = TERRAIN_BITS
    names = []
    if terrain.is_flat:
        height = float(terrain.points[0, 1])
        geom = world.add_geom(
            name=f"{TERRAIN_PREFIX}plane",
            type=mujoco.mjtGeom.mjGEOM_PLANE,
            pos=[0.0, 0.0, height],
            size=[0.0, 0.0, 0.05],
        )
        set_contact(geom, contact, contype, conaffinity)
        geom.group = TERRAIN_GROUP
        geom.rgba = [0.45, 0.5, 0.45, 1.0]
        return [geom.name]
    segments = terrain.segments(TERRAIN_RUN)
    for i, ((x0, z0), (x1, z1)) in enumerate(segments):
        dx, dz = x1 - x0, z1 - z0
        length = math.hypot(dx, dz)
        angle = math.atan2(dz, dx)  # slope, uphill positive
        normal = np.array([-math.sin(angle), 0.0, math.cos(angle)])
        centre = np.array([(x0 + x1) / 2.0, 0.0, (z0 + z1) / 2.0]) - normal * (
            TERRAIN_THICKNESS / 2.0
        )
        if i == 0:
            label = "run_in"
        elif i == len(segments) - 1:
            label = "run_out"
        else:
            label = f"segment_{i - 1}"
        # A rotation by -angle about y takes the box's x axis onto the segment direction.
        quat = [math.cos(-angle / 2.0), 0.0, math.sin(-angle / 2.0), 0.0]
        geom = world.add_geom(
            name=f"{TERRAIN_PREFIX}{label}",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            pos=centre,
            quat=quat,
            size=[length / 2.0, terrain.width / 2.0, TERRAIN_THICKNESS / 2.0],
        )
        set_contact(geom, contact, contype, conaffinity)
        geom.group = TERRAIN_GROUP
        geom.rgba = [0.45, 0.5, 0.45, 1.0] if i % 2 else [0.5, 0.55, 0.5, 1.0]
        names.append(geom.name)
    return names


def ground_clearance(
    model: mujoco.MjModel, data: mujoco.MjData, robot_geoms: Iterable[int], terrain: Iterable[int]
) -> float:
    """Least signed distance [m] between the robot's geoms and the terrain's (< 0: inside).

    ``data`` must hold the geoms' placements; distances beyond `CLEARANCE_RANGE` count as it.
    """
    terrain = tuple(terrain)
    clearance = CLEARANCE_RANGE
    for geom in robot_geoms:
        for ground in terrain:
            distance = mujoco.mj_geomDistance(model, data, geom, ground, CLEARANCE_RANGE, None)
            clearance = min(clearance, float(distance))
    return clearance
