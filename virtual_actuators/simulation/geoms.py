"""The robot's geoms and sites in the MuJoCo model, from the geometry Pinocchio reads."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Literal, NamedTuple

import mujoco
import numpy as np
import pinocchio as pin

from virtual_actuators.exceptions import notice
from virtual_actuators.models.collada import collada_arrays
from virtual_actuators.models.robot import Robot, read_geometry
from virtual_actuators.simulation.ground import (
    ROBOT_BITS,
    ROBOT_SELF_BITS,
    TERRAIN_PREFIX,
    ContactParameters,
    set_contact,
)

#: Mesh formats MuJoCo reads (STL in binary form only); Collada is read here and handed over.
MESH_FORMATS = (".stl", ".obj")

#: Least half-size of a bounding box standing in for a mesh [m] (a flat mesh: a 1 mm slab).
MIN_BOX_HALF_SIZE = 5e-4

#: Most faces MuJoCo reads from an STL file.
MAX_STL_FACES = 200_000

#: Geom groups of the robot geoms and of the frame sites (MuJoCo's visualiser shows groups
#: 0-2 by default; the terrain stays in group 0).
ROBOT_GROUP = 3
SITE_GROUP = 4

Collisions = Literal["collision", "primitives", "visual", "none"]
COLLISION_CHOICES = ("collision", "primitives", "visual", "none")


def quat_wxyz(rotation: np.ndarray) -> np.ndarray:
    """MuJoCo quaternion ``(w, x, y, z)`` of a rotation matrix."""
    quat = pin.Quaternion(np.asarray(rotation, dtype=float)).coeffs()  # (x, y, z, w)
    return np.array([quat[3], quat[0], quat[1], quat[2]])


class _Shape(NamedTuple):
    """A MuJoCo geom type with its size or mesh name, and a bounding box's ``centre``."""

    geom_type: mujoco.mjtGeom
    size: list[float] | None = None
    mesh: str | None = None
    centre: np.ndarray | None = None


class Added(NamedTuple):
    """What `add_geometry` added: the geoms' owning frames, and what it could not add as it is.

    Attributes:
        owners: Geom name -> the frames owning it.
        skipped: Geometries left out (no MuJoCo counterpart nor bounding box).
        approximated: Meshes simulated as the box bounding their vertices.
    """

    owners: dict[str, tuple[str, ...]]
    skipped: list[str]
    approximated: list[str]


#: MuJoCo primitive and size of each coal shape type.
_PRIMITIVES = {
    "Box": (mujoco.mjtGeom.mjGEOM_BOX, lambda s: list(s.halfSide)),
    "Sphere": (mujoco.mjtGeom.mjGEOM_SPHERE, lambda s: [s.radius, 0.0, 0.0]),
    "Cylinder": (mujoco.mjtGeom.mjGEOM_CYLINDER, lambda s: [s.radius, s.halfLength, 0]),
    "Capsule": (mujoco.mjtGeom.mjGEOM_CAPSULE, lambda s: [s.radius, s.halfLength, 0]),
    "Ellipsoid": (mujoco.mjtGeom.mjGEOM_ELLIPSOID, lambda s: list(s.radii)),
}


def _mesh(
    spec: mujoco.MjSpec, obj: pin.GeometryObject, meshes: dict[tuple[str, tuple], str | None]
) -> _Shape | None:
    """The MuJoCo mesh of a geometry (added once per file and scale), or None if unread."""
    path = Path(obj.meshPath)
    scale = tuple(float(s) for s in obj.meshScale)
    key = (str(path), scale)
    if key not in meshes:
        name, mesh = f"mesh_{len(meshes)}_{path.stem}", None
        if _readable_mesh(path):
            mesh = spec.add_mesh(name=name, file=str(path), scale=list(scale))
        elif path.suffix.lower() == ".dae" and (arrays := collada_arrays(str(path))) is not None:
            vertices, triangles = arrays
            mesh = spec.add_mesh(
                name=name,
                uservert=(vertices * np.asarray(scale)).reshape(-1).tolist(),
                userface=triangles.reshape(-1).tolist(),
            )
        if mesh is not None:  # inertias come from Pinocchio: a surface one compiles for any mesh
            mesh.inertia = mujoco.mjtMeshInertia.mjMESH_INERTIA_SHELL
        meshes[key] = None if mesh is None else name
    name = meshes[key]
    return None if name is None else _Shape(mujoco.mjtGeom.mjGEOM_MESH, mesh=name)


def _bounding_box(obj: pin.GeometryObject) -> _Shape | None:
    """The box bounding a geometry as Pinocchio loaded it (scaled); None if it is not finite."""
    geometry = obj.geometry
    try:
        geometry.computeLocalAABB()
        low, high = np.array(geometry.aabb_local.min_), np.array(geometry.aabb_local.max_)
    except (AttributeError, RuntimeError):
        return None
    if not (np.all(np.isfinite(low)) and np.all(np.isfinite(high)) and np.all(high >= low)):
        return None
    half = np.maximum(0.5 * (high - low), MIN_BOX_HALF_SIZE)
    return _Shape(mujoco.mjtGeom.mjGEOM_BOX, half.tolist(), centre=0.5 * (low + high))


def add_geometry(
    spec: mujoco.MjSpec,
    robot: Robot,
    bodies: list[mujoco.MjsBody],
    contact: ContactParameters,
    collisions: str,
) -> Added:
    """Add the robot's geoms; return their owners and what was left out or approximated.

    Raises:
        RobotDescriptionError: If Pinocchio cannot read the robot's geometry.
    """
    added = Added({}, [], [])
    if collisions == "none":
        return added
    geometry = read_geometry(robot, visual=collisions == "visual")
    model = robot.model
    bits = ROBOT_SELF_BITS if contact.self_collisions else ROBOT_BITS
    frames: dict[str, tuple[int, np.ndarray]] = {}  # parent joint and origin of each frame name
    for frame in model.frames:  # but movable joints' frames
        if frame.name not in frames and frame.type != pin.FrameType.JOINT:
            frames[frame.name] = (frame.parentJoint, np.array(frame.placement.translation))
    meshes: dict[tuple[str, tuple[float, ...]], str | None] = {}
    used = set()
    for obj in geometry.geometryObjects:
        is_mesh = type(obj.geometry).__name__.startswith(("BVHModel", "Convex"))
        if is_mesh and collisions == "primitives":
            continue  # meshes are left out on purpose
        if is_mesh:
            shape = _mesh(spec, obj, meshes)
        else:
            entry = _PRIMITIVES.get(type(obj.geometry).__name__)
            shape = None if entry is None else _Shape(entry[0], entry[1](obj.geometry))
        if shape is None:
            shape = _bounding_box(obj)
            (added.skipped if shape is None else added.approximated).append(obj.name)
            if shape is None:
                continue
        name = obj.name
        while name in used or name.startswith(TERRAIN_PREFIX):
            name = f"robot_{name}"
        used.add(name)
        placement = obj.placement
        if shape.centre is not None:
            placement = placement * pin.SE3(np.eye(3), shape.centre)
        geom = bodies[obj.parentJoint].add_geom(
            name=name,
            type=shape.geom_type,
            pos=np.array(placement.translation, dtype=float),
            quat=quat_wxyz(placement.rotation),
        )
        if shape.size is not None:
            geom.size = np.array(shape.size, dtype=float)
        if shape.mesh is not None:
            geom.meshname = shape.mesh
        set_contact(geom, contact, bits)
        geom.group = ROBOT_GROUP
        geom.rgba = [0.6, 0.6, 0.65, 1.0]
        parent = model.frames[obj.parentFrame].name
        inside = [
            frame
            for frame, (joint, point) in frames.items()
            if joint == obj.parentJoint
            and frame != parent
            and shape.size is not None
            and _inside(shape.geom_type, shape.size, placement.actInv(point))
        ]
        added.owners[name] = (parent, *inside)  # its parent frame, then the frames inside it
    for names, what in (
        (added.approximated, "simulated as bounding boxes, the meshes that neither MuJoCo (OBJ, "
         "binary STL) nor the Collada reader reads"),
        (added.skipped, "left out of the simulation, the geometries of a shape MuJoCo has no "
         "counterpart of and with no finite bounding box"),
    ):  # fmt: skip
        if names:
            notice(f"Robot {robot.name!r}: {what} ({len(names)}): {', '.join(names)}")
    return added


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
    faces = int.from_bytes(header[80:84], "little")  # a short file: its size cannot match
    return size == 84 + 50 * faces and 1 <= faces <= MAX_STL_FACES  # ASCII STL is not read


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
        site.group = SITE_GROUP
    return sites
