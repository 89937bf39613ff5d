"""What the robot's model says about drawing it: sizes, planarity, gauges, ground and terrain."""

from __future__ import annotations

import itertools
import math
from typing import TYPE_CHECKING, NamedTuple

import meshcat.geometry as mg
import numpy as np
import pinocchio as pin

from ..exceptions import InvalidInputError
from ..models.robot import Robot

if TYPE_CHECKING:
    from ..simulation.terrain import Terrain


class EffortJoint(NamedTuple):
    """An actuated 1-dof joint, as its effort gauge needs it."""

    name: str
    joint: int  # Pinocchio joint id
    index_v: int  # velocity index
    limit: float | None  # effort limit, None when the URDF has none
    axis: np.ndarray  # unit axis in the joint frame


def _jacobian(model: pin.Model, data: pin.Data, joint: int, frame: object) -> np.ndarray:
    """Joint Jacobian ``(6, nv)`` (Pinocchio returns a flat array for a robot with one dof)."""
    return np.asarray(pin.getJointJacobian(model, data, joint, frame)).reshape(6, model.nv)


def marker_sizes(detail: float) -> dict[str, float]:
    """Sizes of shafts, heads, gauges, coils... [m] for a typical link length ``detail``."""
    return {
        "shaft": max(1e-3, 0.035 * detail),
        "head_length": 0.2 * detail,
        "head_radius": max(2.5e-3, 0.085 * detail),
        "triad_radius": max(8e-4, 0.018 * detail),
        "effort": 0.16 * detail,
        "support": 0.14 * detail,
        "coil": 0.09 * detail,
        "damper": 0.07 * detail,
        "setpoint": 0.07 * detail,
    }


def is_planar(model: pin.Model, data: pin.Data) -> bool:
    """Whether every joint moves in the x-z plane (rotations about y, translations in x-z).

    Overwrites the joint Jacobians of ``data`` (at the neutral configuration).
    """
    if model.njoints <= 1:
        return False
    pin.computeJointJacobians(model, data, pin.neutral(model))
    for j in range(1, model.njoints):
        joint = model.joints[j]
        if joint.nv != 1:
            return False
        column = _jacobian(model, data, j, pin.LOCAL_WORLD_ALIGNED)[:, joint.idx_v]
        linear, angular = column[:3], column[3:]
        if np.linalg.norm(angular) > 1e-9:
            if abs(abs(angular[1]) - np.linalg.norm(angular)) > 1e-6:
                return False
        elif abs(linear[1]) > 1e-6:
            return False
    return True


def effort_joints(robot: Robot, data: pin.Data, q0: np.ndarray) -> list[EffortJoint]:
    """The actuated 1-dof joints (not passive), with their axes at ``q0``.

    Leaves ``data`` at the forward kinematics and frame placements of ``q0``.
    """
    model = robot.model
    pin.computeJointJacobians(model, data, q0)
    out = []
    passive = set(robot.passive_joints)
    for j in range(1, model.njoints):
        joint = model.joints[j]
        name = model.names[j]
        if joint.nv != 1 or name in passive:
            continue
        column = _jacobian(model, data, j, pin.LOCAL)[:, joint.idx_v]
        axis = column[3:] if np.linalg.norm(column[3:]) > 1e-9 else column[:3]
        axis = axis / max(np.linalg.norm(axis), 1e-12)
        limit = float(model.effortLimit[joint.idx_v])
        limit = limit if math.isfinite(limit) and 0 < limit < 1e300 else None
        out.append(EffortJoint(name, j, joint.idx_v, limit, axis))
    pin.forwardKinematics(model, data, q0)
    pin.updateFramePlacements(model, data)
    return out


def ground_grid(centre: np.ndarray, height: float) -> mg.LineSegments:
    """A 20 m grid of 0.5 m squares at ``height``, centred on ``centre`` (x, y)."""
    # short segments: some renderers (SwiftShader) drop a whole line that passes behind
    # the camera, and the camera stands inside the grid
    half, step = 10.0, 0.5
    ticks = np.arange(-half, half + step / 2, step)
    starts, ends = np.meshgrid(ticks, ticks[:-1], indexing="ij")
    starts, ends = starts.ravel(), ends.ravel()
    along_y = np.stack((starts, ends, starts, ends + step), axis=1)
    along_x = np.stack((ends, starts, ends + step, starts), axis=1)
    points = np.vstack((along_y, along_x)).reshape(-1, 2) + centre
    vertices = np.column_stack((points, np.full(len(points), height))).T
    return mg.LineSegments(
        mg.PointsGeometry(vertices.astype(np.float32)), mg.LineBasicMaterial(color=0x9A9A9A)
    )


def terrain_segments(
    terrain: Terrain | np.ndarray, run: float
) -> list[tuple[tuple[float, float], tuple[float, float]]]:
    """The straight pieces of a ground profile, with level run-in and run-out of ``run`` m.

    Args:
        terrain: A [`Terrain`][] or ``(n, 2)`` points.
        run: Length of the level pieces before the first and after the last point [m].

    Returns:
        ``((x0, z0), (x1, z1))`` per piece, from left to right.

    Raises:
        InvalidInputError: The points are not an ``(n, 2)`` finite array.
    """
    if hasattr(terrain, "segments"):
        return terrain.segments(run)
    points = np.asarray(terrain, dtype=float)
    if points.ndim != 2 or points.shape[1] != 2 or not np.all(np.isfinite(points)):
        raise InvalidInputError(
            f"terrain must be a Terrain or (n, 2) finite (x, z) points, got {terrain!r}."
        )
    (x0, z0), (x1, z1) = points[0], points[-1]
    return list(itertools.pairwise([(x0 - run, z0), *map(tuple, points), (x1 + run, z1)]))
