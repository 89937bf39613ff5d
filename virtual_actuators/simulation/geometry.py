"""The robot's geoms and sites in the MuJoCo model, from the geometry Pinocchio reads.

The collision (or visual) geometry of the URDF is read by Pinocchio (``pin.buildGeomFromUrdf``):
boxes, spheres, cylinders, capsules and ellipsoids become MuJoCo primitives, binary STL and OBJ
meshes become meshes (MuJoCo collides with their convex hull); other meshes (DAE, ASCII STL...)
are skipped with a warning naming them. Each geom is owned by its parent frame and by every frame
on the same joint whose origin lies on or inside it. One site per Pinocchio frame, named after the
frame, gives frame placements and a point to push.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path
from typing import Literal, NamedTuple

import mujoco
import numpy as np
import pinocchio as pin

from virtual_actuators.exceptions import RobotDescriptionError
from virtual_actuators.models.robot import Robot
from virtual_actuators.simulation.contact import (
    ROBOT_BITS,
    ROBOT_SELF_BITS,
    ContactParameters,
    set_contact,
)
from virtual_actuators.simulation.ground import TERRAIN_PREFIX

__all__ = [
    "COLLISION_CHOICES",
    "MAX_STL_FACES",
    "MESH_FORMATS",
    "ROBOT_GROUP",
    "SITE_GROUP",
    "Collisions",
    "add_geometry",
    "add_sites",
    "quat_wxyz",
]

#: Mesh formats MuJoCo reads (STL in binary form only).
MESH_FORMATS = (".stl", ".obj")

#: Most faces MuJoCo reads from an STL file.
MAX_STL_FACES = 200_000

#: Geom groups of the robot geoms and of the frame sites (MuJoCo's visualiser shows groups
#: 0-2 by default).
ROBOT_GROUP = 3
SITE_GROUP = 4

Collisions = Literal["collision", "primitives", "visual", "none"]
COLLISION_CHOICES = ("collision", "primitives", "visual", "none")


def quat_wxyz(rotation: np.ndarray) -> np.ndarray:
    """MuJoCo quaternion ``(w, x, y, z)`` of a rotation matrix."""
    quat = pin.Quaternion(np.asarray(rotation, dtype=float)).coeffs()  # (x, y, z, w)
    return np.array([quat[3], quat[0], quat[1], quat[2]])


def _geometry_model(robot: Robot, kind: pin.GeometryType) -> pin.GeometryModel:
    """Read the robot's collision or visual geometry with Pinocchio.

    Raises:
        RobotDescriptionError: If Pinocchio cannot read it (a missing mesh, say).

    """
    model = robot.model
    dirs = list(robot.package_dirs)
    try:
        if robot.urdf_path is not None:
            return pin.buildGeomFromUrdf(model, str(robot.urdf_path), kind, package_dirs=dirs)
        if robot.urdf_string is not None:
            return pin.buildGeomFromUrdfString(model, robot.urdf_string, kind, package_dirs=dirs)
    except Exception as exc:
        raise RobotDescriptionError(
            f"Pinocchio cannot read the geometry of robot {robot.name!r}: {exc}"
        ) from exc
    return pin.GeometryModel()


class _Shape(NamedTuple):
    """A MuJoCo geom type with its size (primitives) or mesh name (meshes)."""

    geom_type: mujoco.mjtGeom
    size: list[float] | None = None
    mesh: str | None = None


def _primitive(shape: object) -> _Shape | None:
    """The MuJoCo primitive of a coal shape, or None for an unsupported one."""
    shape_type = type(shape).__name__
    if shape_type == "Box":
        return _Shape(mujoco.mjtGeom.mjGEOM_BOX, list(shape.halfSide))
    if shape_type == "Sphere":
        return _Shape(mujoco.mjtGeom.mjGEOM_SPHERE, [shape.radius, 0.0, 0.0])
    if shape_type == "Cylinder":
        return _Shape(mujoco.mjtGeom.mjGEOM_CYLINDER, [shape.radius, shape.halfLength, 0])
    if shape_type == "Capsule":
        return _Shape(mujoco.mjtGeom.mjGEOM_CAPSULE, [shape.radius, shape.halfLength, 0])
    if shape_type == "Ellipsoid":
        return _Shape(mujoco.mjtGeom.mjGEOM_ELLIPSOID, list(shape.radii))
    return None


def _mesh(
    spec: mujoco.MjSpec, obj: pin.GeometryObject, meshes: dict[tuple[str, tuple], str]
) -> _Shape | None:
    """The MuJoCo mesh of a geometry object (added to ``spec`` once per file and scale).

    None when MuJoCo cannot read the file.
    """
    path = Path(obj.meshPath)
    if not _readable_mesh(path):
        return None
    scale = tuple(float(s) for s in obj.meshScale)
    key = (str(path), scale)
    if key not in meshes:
        meshes[key] = f"mesh_{len(meshes)}_{path.stem}"
        mesh = spec.add_mesh(name=meshes[key], file=str(path), scale=list(scale))
        # Mesh inertia is unused (inertias come from Pinocchio); a surface inertia compiles
        # even for open or flat meshes.
        mesh.inertia = mujoco.mjtMeshInertia.mjMESH_INERTIA_SHELL
    return _Shape(mujoco.mjtGeom.mjGEOM_MESH, mesh=meshes[key])


def add_geometry(
    spec: mujoco.MjSpec,
    robot: Robot,
    bodies: list[mujoco.MjsBody],
    contact: ContactParameters,
    collisions: str,
) -> tuple[dict[str, tuple[str, ...]], list[str]]:
    """Add the robot's geoms; return geom name -> owning frames, and the skipped geometries.

    Raises:
        RobotDescriptionError: If Pinocchio cannot read the robot's geometry.

    """
    if collisions == "none":
        return {}, []
    kind = pin.GeometryType.VISUAL if collisions == "visual" else pin.GeometryType.COLLISION
    geometry = _geometry_model(robot, kind)
    model = robot.model
    contype, conaffinity = ROBOT_SELF_BITS if contact.self_collisions else ROBOT_BITS
    placements = _frames_in_joints(model)
    owners: dict[str, tuple[str, ...]] = {}
    skipped: list[str] = []
    meshes: dict[tuple[str, tuple[float, ...]], str] = {}
    used = set()
    for obj in geometry.geometryObjects:
        if not type(obj.geometry).__name__.startswith(("BVHModel", "Convex")):
            shape = _primitive(obj.geometry)
        elif collisions == "primitives":
            continue  # meshes are left out on purpose
        else:
            shape = _mesh(spec, obj, meshes)
        if shape is None:
            skipped.append(obj.name)
            continue
        name = obj.name
        while name in used or name.startswith(TERRAIN_PREFIX):
            name = f"robot_{name}"
        used.add(name)
        geom = bodies[obj.parentJoint].add_geom(
            name=name,
            type=shape.geom_type,
            pos=np.array(obj.placement.translation, dtype=float),
            quat=quat_wxyz(obj.placement.rotation),
        )
        if shape.size is not None:
            geom.size = np.array(shape.size, dtype=float)
        if shape.mesh is not None:
            geom.meshname = shape.mesh
        set_contact(geom, contact, contype, conaffinity)
        geom.group = ROBOT_GROUP
        geom.rgba = [0.6, 0.6, 0.65, 1.0]
        owners[name] = _owners(model, obj, shape, placements)
    if skipped:
        warnings.warn(
            f"Robot {robot.name!r}: {len(skipped)} geometries cannot be simulated and are left "
            "out (unsupported shape or mesh format; MuJoCo reads OBJ and binary STL): "
            + ", ".join(skipped),
            stacklevel=3,
        )
    return owners, skipped


def _owners(
    model: pin.Model,
    obj: pin.GeometryObject,
    shape: _Shape,
    placements: dict[str, tuple[int, np.ndarray]],
) -> tuple[str, ...]:
    """The frames owning a geom: its parent frame, then the frames of its joint inside it."""
    parent = model.frames[obj.parentFrame].name
    located = [
        frame
        for frame, (joint, point) in placements.items()
        if joint == obj.parentJoint
        and frame != parent
        and shape.size is not None
        and _inside(shape.geom_type, shape.size, obj.placement.actInv(point))
    ]
    return (parent, *located)


def _readable_mesh(path: Path) -> bool:
    """Whether MuJoCo can read a mesh file: OBJ, or binary STL with 1 to 200000 faces."""
    suffix = path.suffix.lower()
    if suffix not in MESH_FORMATS or not path.is_file():
        return False
    if suffix != ".stl":
        return True
    try:
        with path.open("rb") as stream:
            header = stream.read(84)
        size = path.stat().st_size
    except OSError:
        return False
    if len(header) < 84:
        return False
    faces = int.from_bytes(header[80:84], "little")
    return size == 84 + 50 * faces and 1 <= faces <= MAX_STL_FACES  # ASCII STL is not read


def _frames_in_joints(model: pin.Model) -> dict[str, tuple[int, np.ndarray]]:
    """Parent joint and origin (joint frame) of each frame name but movable joints' frames."""
    out: dict[str, tuple[int, np.ndarray]] = {}
    for frame in model.frames:
        if frame.name not in out and frame.type != pin.FrameType.JOINT:
            out[frame.name] = (frame.parentJoint, np.array(frame.placement.translation))
    return out


def _inside(geom_type: mujoco.mjtGeom, size: list[float], point: np.ndarray) -> bool:
    """Whether ``point`` (geom frame) lies inside or on the surface of a primitive."""
    tol = 1e-6 * max(1.0, max(abs(s) for s in size))
    x, y, z = (float(c) for c in point)
    if geom_type == mujoco.mjtGeom.mjGEOM_SPHERE:
        return math.sqrt(x * x + y * y + z * z) <= size[0] + tol
    if geom_type == mujoco.mjtGeom.mjGEOM_BOX:
        return all(abs(c) <= s + tol for c, s in zip((x, y, z), size, strict=True))
    if geom_type == mujoco.mjtGeom.mjGEOM_CYLINDER:
        return math.hypot(x, y) <= size[0] + tol and abs(z) <= size[1] + tol
    if geom_type == mujoco.mjtGeom.mjGEOM_CAPSULE:
        zc = min(max(z, -size[1]), size[1])
        return math.sqrt(x * x + y * y + (z - zc) ** 2) <= size[0] + tol
    if geom_type == mujoco.mjtGeom.mjGEOM_ELLIPSOID:
        return (x / size[0]) ** 2 + (y / size[1]) ** 2 + (z / size[2]) ** 2 <= 1.0 + tol
    return False


def add_sites(spec: mujoco.MjSpec, robot: Robot, bodies: list[mujoco.MjsBody]) -> dict[str, str]:
    """Add a site per Pinocchio frame name; return frame name -> site name."""
    sites: dict[str, str] = {}
    for frame in robot.model.frames:
        if frame.name in sites:
            continue
        sites[frame.name] = frame.name
        placement = frame.placement
        site = bodies[frame.parentJoint].add_site(
            name=frame.name,
            pos=np.array(placement.translation, dtype=float),
            quat=quat_wxyz(placement.rotation),
        )
        site.size = [0.005, 0.005, 0.005]
        site.group = SITE_GROUP
    return sites
