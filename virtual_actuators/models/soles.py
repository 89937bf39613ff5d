"""Sole sizes from a foot's collision geometry."""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import pinocchio as pin

from ..exceptions import FrameNotFoundError, RobotDescriptionError
from .robot import Robot, frame_id, read_geometry

#: Points within this height of a foot's lowest point make up its sole [m].
SOLE_THICKNESS = 0.005


@dataclass(frozen=True, slots=True)
class Sole:
    """A foot's footprint in its frame's x-y plane [m].

    Attributes:
        half_length: Largest half-length along x of a rectangle centred at the frame origin
            inside the footprint (0 when the origin is outside it), as
            ``ParallelVirtualActuator(soles=...)`` takes.
        half_width: Likewise along y.
        lower: ``(x, y)`` of the footprint's back right corner.
        upper: ``(x, y)`` of its front left corner.
        height: The sole's z in the frame (0 when the frame lies on the sole).
    """

    half_length: float
    half_width: float
    lower: tuple[float, float]
    upper: tuple[float, float]
    height: float

    @property
    def centre(self) -> tuple[float, float]:
        """``(x, y)`` of the footprint's centre in the frame [m]."""
        return (0.5 * (self.lower[0] + self.upper[0]), 0.5 * (self.lower[1] + self.upper[1]))


def find_sole(robot: Robot, foot: str) -> Sole:
    """The footprint of ``foot``'s link from its collision geometry.

    The points of the link's shapes (its fixed children included) within `SOLE_THICKNESS` of the
    lowest along the frame's z span the footprint (a sphere counts by its lowest point).

    Args:
        robot: The robot (its URDF is read again for the geometry).
        foot: The foot frame.

    Raises:
        FrameNotFoundError: No such frame (with close matches), or its link has no collision
            geometry.
        RobotDescriptionError: Pinocchio cannot read the geometry.
    """
    frame = robot.model.frames[frame_id(robot, foot)]
    frame_in_joint = frame.placement
    points = [
        frame_in_joint.actInv(obj.placement.act(point))
        for obj in read_geometry(robot).geometryObjects
        if obj.parentJoint == frame.parentJoint
        for point in _points(obj, frame_in_joint)
    ]
    if not points:
        raise FrameNotFoundError(
            f"Frame {foot!r} of robot {robot.name!r}: its link has no collision geometry to "
            "take a sole from; give the sole's size yourself."
        )
    points = np.array(points)
    lowest = float(points[:, 2].min())
    sole = points[points[:, 2] <= lowest + SOLE_THICKNESS, :2]
    low, high = sole.min(axis=0), sole.max(axis=0)
    halves = np.maximum(np.minimum(high, -low), 0.0)
    return Sole(*halves.tolist(), tuple(low.tolist()), tuple(high.tolist()), lowest)


def _points(obj: pin.GeometryObject, frame: pin.SE3) -> list[np.ndarray]:
    """Points of a shape, in its own frame, that can touch a plane below the foot frame."""
    shape = obj.geometry
    kind = type(shape).__name__
    down = obj.placement.rotation.T @ frame.rotation @ np.array([0.0, 0.0, -1.0])  # in shape
    if kind == "Box":
        half = np.asarray(shape.halfSide, dtype=float)
        signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
        return list(signs * half)
    if kind == "Sphere":
        return [float(shape.radius) * down]
    if kind == "Capsule":
        ends = [np.array([0.0, 0.0, h]) for h in (-shape.halfLength, shape.halfLength)]
        return [end + float(shape.radius) * down for end in ends]
    if kind == "Cylinder":
        angles = np.linspace(0.0, 2.0 * np.pi, 16, endpoint=False)
        r, h = float(shape.radius), float(shape.halfLength)
        return [np.array([r * np.cos(a), r * np.sin(a), z]) for a in angles for z in (-h, h)]
    if kind.startswith(("BVHModel", "Convex")):
        vertices = np.asarray(shape.vertices(), dtype=float)
        return list(vertices * np.asarray(obj.meshScale, dtype=float))
    return []


class SoleSphere(NamedTuple):
    """A rounded sole: its sphere's centre in the foot frame and its radius [m]."""

    x: float
    y: float
    z: float
    radius: float


#: A collision sphere this close to a foot frame is its sole [m].
SOLE_SPHERE_REACH = 0.05


def sole_sphere(robot: Robot, foot: str) -> SoleSphere:
    """A foot's sole as a sphere: its centre in the foot frame [m] and its radius [m].

    The collision sphere of the foot's link nearest to the frame (within `SOLE_SPHERE_REACH`);
    else a rounded sole under the frame (``find_sole``'s depth as the radius, centre at the
    frame: a point foot's mesh); else the frame itself (radius 0: a flat sole's frame lies on it).
    """
    frame = robot.model.frames[frame_id(robot, foot)]
    spheres = [
        (float(np.linalg.norm(centre)), tuple(map(float, centre)), float(obj.geometry.radius))
        for obj in read_geometry(robot).geometryObjects
        if obj.parentJoint == frame.parentJoint and type(obj.geometry).__name__ == "Sphere"
        for centre in [frame.placement.actInv(obj.placement).translation]
    ]
    near = [sphere for sphere in spheres if sphere[0] <= SOLE_SPHERE_REACH]
    if near:
        _, centre, radius = min(near)
        return SoleSphere(*centre, radius)
    try:
        sole = find_sole(robot, foot)
    except (FrameNotFoundError, RobotDescriptionError):
        return SoleSphere(0.0, 0.0, 0.0, 0.0)
    small = max(sole.half_length, sole.half_width) < 2.0 * abs(sole.height)
    return SoleSphere(0.0, 0.0, 0.0, max(0.0, -sole.height) if small else 0.0)
