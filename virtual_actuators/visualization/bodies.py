"""The robot's bodies in the scene: its URDF visuals, or a skeleton of its kinematic tree.

Every shape is a `Part` attached to a Pinocchio joint; its world matrix is
``data.oMi[joint].homogeneous @ placement``.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import meshcat.geometry as mg
import numpy as np
import pinocchio as pin

from ..exceptions import InvalidInputError, RobotDescriptionError
from ..models.robot import Robot
from .legend import desaturate, rgb
from .meshes import MeshCache, TriangleMesh
from .shapes import Placed, cone, material, span_matrix, to_hex, translation, y_to_z

GEOMETRY_MODES = ("auto", "urdf", "skeleton")

#: Side of the grid cells a mesh is decimated on, relative to the robot's typical link length.
MESH_TOLERANCE = 0.02

# skeleton colours
BASE_COLOR = 0x37474F
LINK_COLOR = 0x90A4AE
JOINT_COLOR = 0x455A64
TIP_COLOR = 0x263238


@dataclass(repr=False)
class Part:
    """One shape of the robot.

    Attributes:
        name: Node name under the robot's node.
        joint: Pinocchio joint id it moves with (0: the world).
        placement: ``(4, 4)`` placement in the joint's frame, scale included.
        geometry: The MeshCat geometry (None for meshes that Pinocchio loads).
        color: ``0xRRGGBB``.
        opacity: In ``[0, 1]``.
        source: The Pinocchio geometry object of a URDF visual, or None.
    """

    name: str
    joint: int
    placement: np.ndarray
    geometry: object | None = None
    color: int = LINK_COLOR
    opacity: float = 1.0
    source: object | None = None

    def __repr__(self) -> str:
        return f"Part({self.name!r}, joint={self.joint})"


def _mesh(geometry_object: pin.GeometryObject) -> list[tuple[object, np.ndarray]] | None:
    """The MeshCat geometry of a mesh file (in the part's colour), or None for another file."""
    path = str(geometry_object.meshPath)
    loaders = {".stl": mg.StlMeshGeometry, ".obj": mg.ObjMeshGeometry, ".dae": mg.DaeMeshGeometry}
    loader = loaders.get(path[-4:].lower())
    if loader is None:
        return None
    try:
        return [(loader.from_file(path), np.eye(4))]
    except (OSError, UnicodeDecodeError) as error:
        warnings.warn(f"Cannot read the mesh {path}: {error}; left out.", stacklevel=4)
        return []


def _primitive(shape: object) -> list[tuple[object, np.ndarray]] | None:
    """MeshCat geometry (with an offset inside the part) for a coal primitive, or None."""
    kind = type(shape).__name__
    if kind == "Box":
        return [(mg.Box((2.0 * np.asarray(shape.halfSide)).tolist()), np.eye(4))]
    if kind == "Sphere":
        return [(mg.Sphere(float(shape.radius)), np.eye(4))]
    if kind == "Ellipsoid":
        return [(mg.Ellipsoid(np.asarray(shape.radii, dtype=float)), np.eye(4))]
    if kind == "Cylinder":
        return [(Placed(mg.Cylinder(2.0 * shape.halfLength, shape.radius), y_to_z()), np.eye(4))]
    if kind == "Cone":
        return [(Placed(cone(2.0 * shape.halfLength, shape.radius), y_to_z()), np.eye(4))]
    if kind == "Capsule":
        half, radius = float(shape.halfLength), float(shape.radius)
        return [
            (Placed(mg.Cylinder(2.0 * half, radius), y_to_z()), np.eye(4)),
            (mg.Sphere(radius), translation([0.0, 0.0, half])),
            (mg.Sphere(radius), translation([0.0, 0.0, -half])),
        ]
    return None


def visual_model(robot: Robot) -> pin.GeometryModel | None:
    """The robot's visual geometry from its URDF, or None when it has no URDF source.

    Raises:
        RobotDescriptionError: Pinocchio cannot build the visual model (a missing mesh...).
    """
    model, visual, dirs = robot.model, pin.GeometryType.VISUAL, list(robot.package_dirs)
    try:
        if robot.urdf_string:
            return pin.buildGeomFromUrdfString(model, robot.urdf_string, visual, package_dirs=dirs)
        if robot.urdf_path is not None:
            return pin.buildGeomFromUrdf(model, str(robot.urdf_path), visual, package_dirs=dirs)
    except (RuntimeError, ValueError, OSError) as error:
        raise RobotDescriptionError(
            f"Cannot load the visual geometry of {robot.name!r}: {error}"
        ) from error
    return None


def _urdf_parts(geometry_model: pin.GeometryModel, meshes: MeshCache) -> list[Part]:
    """Parts for the URDF's visual geometry objects, in their desaturated URDF colours."""
    parts = []
    for geometry_object in geometry_model.geometryObjects:
        scale = np.diag([*np.asarray(geometry_object.meshScale, dtype=float), 1.0])
        base = geometry_object.placement.homogeneous @ scale
        color = np.asarray(geometry_object.meshColor, dtype=float)
        opacity = float(color[3]) if color.size > 3 else 1.0
        color = desaturate(to_hex(color))
        name = f"visuals/{geometry_object.name}"
        joint = int(geometry_object.parentJoint)
        mesh = meshes.get(geometry_object)
        if mesh is not None:  # the loaded triangles are scaled already
            placement = geometry_object.placement.homogeneous
            parts.append(Part(name, joint, placement, mesh, color, opacity, geometry_object))
            continue
        pieces = _mesh(geometry_object)
        if pieces is None:  # another geometry: Pinocchio's MeshcatVisualizer loads it
            pieces = _primitive(geometry_object.geometry) or [(None, np.eye(4))]
        for k, (geometry, offset) in enumerate(pieces):
            label = name if k == 0 else f"{name}_{k}"
            parts.append(
                Part(label, joint, base @ offset, geometry, color, opacity, geometry_object)
            )
    return parts


def _skeleton_parts(model: pin.Model, detail: float, floating: bool) -> list[Part]:
    """A sphere per joint, a cylinder to each child and tip frame, a box around a free base."""
    link_radius = min(0.03, max(0.003, 0.07 * detail))
    joint_radius = 1.6 * link_radius
    parts: list[Part] = []
    children: dict[int, list[np.ndarray]] = {}
    for j in range(1, model.njoints):
        name = model.names[j]
        parent = int(model.parents[j])
        offset = np.asarray(model.jointPlacements[j].translation, dtype=float)
        children.setdefault(parent, []).append(offset)
        parts.append(
            Part(f"skeleton/joint_{name}", j, np.eye(4), mg.Sphere(joint_radius), JOINT_COLOR)
        )
        if np.linalg.norm(offset) > 1e-6 and (parent > 0 or not floating):
            link = mg.Cylinder(1.0, link_radius)
            matrix = span_matrix(np.zeros(3), offset)
            parts.append(Part(f"skeleton/link_{name}", parent, matrix, link, LINK_COLOR))
    for frame in _tip_frames(model):
        joint = int(frame.parentJoint)
        offset = np.asarray(frame.placement.translation, dtype=float)
        children.setdefault(joint, []).append(offset)
        link, tip = mg.Cylinder(1.0, link_radius), mg.Sphere(1.3 * link_radius)
        matrix = span_matrix(np.zeros(3), offset)
        parts.append(Part(f"skeleton/tip_link_{frame.name}", joint, matrix, link, LINK_COLOR))
        parts.append(Part(f"skeleton/tip_{frame.name}", joint, translation(offset), tip, TIP_COLOR))
    if floating and model.njoints > 1:
        parts.append(_base_part(children.get(1, [np.zeros(3)]), joint_radius))
    return parts


def _tip_frames(model: pin.Model) -> list[pin.Frame]:
    """The frames away from their joint (feet, tools), one per point: BODY, else OP, else FIXED."""
    priority = {pin.FrameType.BODY: 0, pin.FrameType.OP_FRAME: 1, pin.FrameType.FIXED_JOINT: 2}
    tips: dict[tuple, pin.Frame] = {}
    for frame in model.frames:
        joint = int(frame.parentJoint)
        offset = np.asarray(frame.placement.translation, dtype=float)
        if frame.type not in priority or joint == 0 or np.linalg.norm(offset) < 1e-6:
            continue
        key = (joint, *np.round(offset, 6))
        if key not in tips or priority[frame.type] < priority[tips[key].type]:
            tips[key] = frame
    return list(tips.values())


def _base_part(children: list[np.ndarray], joint_radius: float) -> Part:
    """A box around a floating base's joint and the origins of its children."""
    points = np.array([*children, np.zeros(3)])
    low, high = points.min(axis=0), points.max(axis=0)
    size = np.maximum(high - low, 2.0 * joint_radius) + joint_radius
    centre = translation((low + high) / 2.0)
    return Part("skeleton/base", 1, centre, mg.Box(size.tolist()), BASE_COLOR)


class RobotBodies:
    """The robot's shapes: built once, placed after each forward-kinematics pass.

    Args:
        robot: The robot.
        geometry: ``"auto"`` (the URDF's visuals if it has any, else a skeleton), ``"urdf"`` or
            ``"skeleton"``.
        detail: Typical link length [m] (skeleton radii; meshes decimated on
            ``MESH_TOLERANCE * detail`` cells).

    Raises:
        InvalidInputError: Unknown ``geometry``.
        RobotDescriptionError: ``geometry="urdf"`` and the robot has no visual geometry, or
            Pinocchio cannot load it.
    """

    def __init__(self, robot: Robot, geometry: str = "auto", detail: float = 0.2) -> None:
        if geometry not in GEOMETRY_MODES:
            raise InvalidInputError(f"geometry must be one of {GEOMETRY_MODES}, got {geometry!r}.")
        self.robot = robot
        self.kind = "skeleton"
        self.visual_model: pin.GeometryModel | None = None
        parts: list[Part] = []
        if geometry != "skeleton":
            try:
                self.visual_model = visual_model(robot)
            except RobotDescriptionError as error:
                if geometry == "urdf":
                    raise
                warnings.warn(f"{error}; drawing a skeleton instead.", stacklevel=3)
            if self.visual_model is not None and self.visual_model.ngeoms > 0:
                parts = _urdf_parts(self.visual_model, MeshCache(MESH_TOLERANCE * detail))
                self.kind = "urdf"
            elif geometry == "urdf":
                raise RobotDescriptionError(
                    f"The robot {robot.name!r} has no <visual> geometry in its URDF; use "
                    "geometry='skeleton' or 'auto'."
                )
        if not parts:
            model = robot.model
            floating = model.njoints > 1 and model.joints[1].shortname() == "JointModelFreeFlyer"
            parts = _skeleton_parts(model, detail, floating)
        self.parts = parts
        self._joints = np.array([p.joint for p in parts], dtype=int)
        self._placements = np.array([p.placement for p in parts]) if parts else np.zeros((0, 4, 4))

    def create(self, scene: object, node: str = "robot") -> None:
        """Send every part's object to the scene (under ``node``)."""
        meshes = [p for p in self.parts if p.geometry is None]
        if meshes:
            from pinocchio.visualize import MeshcatVisualizer

            loader = MeshcatVisualizer(self.robot.model, None, self.visual_model)
            loader.viewer = scene.node(node)
            loader.viewerRootNodeName = node
            loader.viewerVisualGroupName = "visuals"  # Pinocchio's node: visuals/<geometry name>
            for part in meshes:
                rgba = np.array([*rgb(part.color), part.opacity])
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", UserWarning)
                    loader.loadViewerGeometryObject(part.source, pin.GeometryType.VISUAL, rgba)
        for part in self.parts:
            if part.geometry is not None:
                flat = {"flatShading": True} if isinstance(part.geometry, TriangleMesh) else {}
                scene.create(
                    f"{node}/{part.name}", part.geometry, material(part.color, part.opacity, **flat)
                )

    def matrices(self, data: pin.Data) -> np.ndarray:
        """World matrices ``(len(parts), 4, 4)`` after forward kinematics in ``data``."""
        frames = np.array([m.homogeneous for m in data.oMi])
        return frames[self._joints] @ self._placements

    def __repr__(self) -> str:
        return f"RobotBodies({self.robot.name!r}, {self.kind}, {len(self.parts)} parts)"


def typical_link_length(model: pin.Model) -> float:
    """Median distance between a joint and its parent joint (and fixed frames) [m]."""
    lengths = [
        float(np.linalg.norm(model.jointPlacements[j].translation)) for j in range(1, model.njoints)
    ]
    lengths += [
        float(np.linalg.norm(f.placement.translation))
        for f in model.frames
        if f.type in (pin.FrameType.OP_FRAME, pin.FrameType.FIXED_JOINT)
    ]
    lengths = [x for x in lengths if x > 1e-4 and math.isfinite(x)]
    return float(np.median(lengths)) if lengths else 0.2
