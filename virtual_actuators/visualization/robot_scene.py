"""The robot in the MeshCat scene, the drawing primitives that overlays share, and `Overlay`.

An overlay draws what is there; the dynamic nodes it does not ``use`` in a frame are hidden.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable
from typing import TYPE_CHECKING

import meshcat.geometry as mg
import numpy as np
import pinocchio as pin

from ..models.robot import Robot
from ..vocabulary.axes import AXES, resolve_frame
from .bodies import RobotBodies, typical_link_length
from .legend import Palette
from .robot_layout import effort_joints, ground_grid, is_planar, marker_sizes, terrain_segments
from .shapes import (
    arrow_matrices,
    cone,
    frame_on_plane,
    material,
    placement,
    span_matrix,
    terrain_boxes,
    translation,
    triad_parts,
)
from .windows import Scene

if TYPE_CHECKING:
    from ..simulation.terrain import Terrain
    from .frame_snapshot import FrameSnapshot

#: Roles of the frames drawn as triads, with their length relative to a typical link.
TRIAD_LENGTHS = {"action": 0.5, "reaction": 0.3, "reference": 0.65, "frame": 0.4}

_CAMERA_SIDE = np.array([0.0, -1.0, 0.25])
_CAMERA_ISO = np.array([0.8, -1.0, 0.55])


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """3-vector cross product (``np.cross`` costs ten times more on 3-vectors)."""
    return np.array(
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    )


def safe(name: str) -> str:
    """A frame or joint name as one MeshCat path element."""
    return str(name).replace("/", "_") or "_"


class RobotScene:
    """The robot drawn under one node of a MeshCat scene.

    Args:
        robot: The robot.
        bodies: Its bodies (URDF visuals or a skeleton).
        nodes: The node bookkeeping to draw into.
        palette: Colours.
        force_scale: Arrow length per newton [m/N].
        moment_scale: Arrow length per newton-metre [m/(N m)].
        effort_reference: Full gauge at joints without an effort limit [N m or N].

    Attributes:
        data: Pinocchio data at the last configuration drawn (`pose`).
        extent: Size of the robot at its neutral configuration [m].
        detail: Typical link length, the unit of every marker's size [m].
        sizes: Sizes of shafts, heads, gauges, coils [m].
        view: Unit vector from the robot's centre to the camera (world axes): from the side
            for a planar robot, else from an oblique (iso) direction.
        planar: Whether every joint moves in the x-z plane.
        follow: Whether the view follows the robot (one with a free or prismatic root joint).
        effort_joints: An `EffortJoint` per actuated 1-dof joint.
        drawn: Keys of what has been drawn so far, which the legend lists (see `mark`).
    """

    def __init__(
        self,
        robot: Robot,
        bodies: RobotBodies,
        nodes: Scene,
        palette: Palette,
        force_scale: float,
        moment_scale: float,
        effort_reference: float,
    ) -> None:
        self.robot = robot
        self.model = robot.model
        self.data = pin.Data(self.model)
        self.bodies = bodies
        self.nodes = nodes
        self.palette = palette
        self.force_scale = force_scale
        self.moment_scale = moment_scale
        self.effort_reference = effort_reference
        self.drawn: set[str] = set()
        self._frame_ids: dict[tuple[str, str], int] = {}
        self._axis_rows: dict[tuple[str, ...], np.ndarray] = {}
        q0 = robot.neutral()
        pin.forwardKinematics(self.model, self.data, q0)
        pin.updateFramePlacements(self.model, self.data)
        self._sizes()
        self.effort_joints = effort_joints(robot, self.data, q0)

    def _sizes(self) -> None:
        model, data = self.model, self.data
        points = np.array([f.translation for f in data.oMf] + [m.translation for m in data.oMi])
        low, high = points.min(axis=0), points.max(axis=0)
        self.extent = max(0.3, float(np.linalg.norm(high - low)))
        self.detail = min(typical_link_length(model), 0.5 * self.extent)
        self._target0 = (low + high) / 2.0
        first = model.joints[1].shortname() if model.njoints > 1 else ""
        floating = first == "JointModelFreeFlyer"
        self._ground = float(low[2]) if floating else 0.0  # feet of a free robot, else z = 0
        self._centroid0 = self._centroid()
        self.sizes = marker_sizes(self.detail)
        self.planar = is_planar(model, data)
        direction = _CAMERA_SIDE if self.planar else _CAMERA_ISO
        self.view = direction / np.linalg.norm(direction)  # from the target to the camera
        self.hud_rotation = frame_on_plane(np.array([self.view[0], self.view[1], 0.0]))
        self.follow = floating or first.startswith("JointModelP")  # a robot that travels

    def _centroid(self) -> np.ndarray:
        if len(self.data.oMi) <= 1:
            return np.zeros(3)
        return np.mean([m.translation for m in self.data.oMi[1:]], axis=0)

    def build(self) -> None:
        """Empty the node, then send the background, the robot's bodies, the ground and camera.

        MeshCat's orbit controls look at the world origin, so the node is shifted to put the
        robot's centre there, with a grid of its own on the robot's ground.
        """
        nodes = self.nodes
        nodes.node("").delete()
        nodes.set_property("/Background", "top_color", [0.98, 0.98, 0.98])
        nodes.set_property("/Background", "bottom_color", [0.78, 0.8, 0.84])
        self.bodies.create(nodes, "robot")
        nodes.place("", translation(-self._target0))
        nodes.place("hud", translation(self._target0))
        nodes.set_property("/Grid", "visible", False)
        nodes.set_property("/Axes", "visible", False)
        nodes.create("ground/grid", ground_grid(self._target0[:2], self._ground))
        distance = max(0.8, 1.5 * self.extent)
        offset = self.view * distance  # from the robot's centre to the camera, world axes
        local = [float(offset[0]), float(offset[2]), float(-offset[1])]  # three.js is y-up
        nodes.set_property("/Cameras/default/rotated/<object>", "position", local)

    def set_terrain(self, terrain: Terrain | np.ndarray, run: float) -> None:
        """Draw a planar ground profile, the terrain's ``width`` (else 1 m) wide, for the grid.

        Raises:
            InvalidInputError: The points are not an ``(n, 2)`` finite array.
        """
        width = float(getattr(terrain, "width", 1.0))
        segments = terrain_segments(terrain, run)
        self.nodes.remove("terrain")
        for k, (lengths, matrix) in enumerate(terrain_boxes(segments, width)):
            name = f"terrain/slab_{k:03d}"
            self.nodes.create(name, mg.Box(lengths.tolist()), material(0xB0A58C))
            self.nodes.place(name, matrix)
        self.nodes.set_property("ground", "visible", False)  # the terrain replaces the grid

    def hud_matrix(self, offset_right: float, offset_up: float) -> np.ndarray:
        """Placement in the HUD plane (facing the camera), beside the robot's centre."""
        rotation = self.hud_rotation
        return placement(rotation, rotation[:, 0] * offset_right + rotation[:, 1] * offset_up)

    def pose(self, q: np.ndarray) -> None:
        """Forward kinematics at ``q`` (checked by the caller); place the bodies and the view."""
        model, data, nodes = self.model, self.data, self.nodes
        pin.forwardKinematics(model, data, q)
        pin.updateFramePlacements(model, data)
        for part, matrix in zip(self.bodies.parts, self.bodies.matrices(data), strict=True):
            nodes.place(f"robot/{part.name}", matrix)
        if self.follow:  # keep the robot at the centre of the view (see build)
            centre = self._target0 + self._centroid() - self._centroid0
            centre[2] = self._target0[2]
            nodes.place("", translation(-centre))
            nodes.place("hud", translation(centre))

    def mark(self, *keys: str) -> None:
        """Record that ``keys`` (`Palette` fields, ``"no_limit"``, ``"frames"``) were drawn."""
        self.drawn.update(keys)

    def frame(self, name: str, role: str) -> int:
        """Id of the frame ``name`` (cached).

        Raises:
            FrameNotFoundError: The robot has no such frame (the message names ``role``).
        """
        key = (name, role)
        frame_id = self._frame_ids.get(key)
        if frame_id is None:
            frame_id = self._frame_ids[key] = resolve_frame(self.model, name, role)
        return frame_id

    def split(self, axes: tuple[str, ...], values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Force and moment 3-vectors (reference axes) of a wrench on ``axes``."""
        rows = self._axis_rows.get(axes)
        if rows is None:
            rows = self._axis_rows[axes] = np.array([AXES.index(a) for a in axes], dtype=int)
        full = np.zeros(6)
        full[rows] = values
        return full[:3], full[3:]

    def arrow(
        self,
        name: str,
        origin: np.ndarray,
        vector: np.ndarray,
        key: str,
        heads: int,
        thin: float = 1.0,
    ) -> None:
        """Show the dynamic arrow ``name`` from ``origin`` along ``vector`` unless it is zero.

        It has the colour of the `Palette` field ``key``, which it `mark`s when drawn.
        """
        head_length = self.sizes["head_length"] * thin
        matrices = arrow_matrices(origin, vector, head_length, heads)
        if matrices is None:
            return
        nodes = self.nodes
        if not nodes.has(f"{name}/shaft"):
            mat = material(getattr(self.palette, key))
            nodes.create(f"{name}/shaft", mg.Cylinder(1.0, self.sizes["shaft"] * thin), mat)
            for k in range(heads):
                nodes.create(
                    f"{name}/head{k}", cone(head_length, self.sizes["head_radius"] * thin), mat
                )
            nodes.declare(name)
        nodes.use(name)
        nodes.place(f"{name}/shaft", matrices[0])
        for k in range(heads):
            nodes.place(f"{name}/head{k}", matrices[k + 1])
        self.drawn.add(key)

    def wrench(
        self,
        name: str,
        origin: np.ndarray,
        rotation: np.ndarray,
        axes: tuple[str, ...],
        values: np.ndarray,
        keys: tuple[str, str],
    ) -> None:
        """A force arrow and a double-headed moment arrow of a wrench on ``axes`` (see `arrow`)."""
        force, moment = self.split(axes, values)
        self.arrow(f"{name}/force", origin, rotation @ force * self.force_scale, keys[0], 1)
        self.arrow(f"{name}/moment", origin, rotation @ moment * self.moment_scale, keys[1], 2)

    def triad(self, role: str, frame: str) -> None:
        """Show the axes of ``frame``, sized by its role (`TRIAD_LENGTHS`).

        Raises:
            FrameNotFoundError: The robot has no such frame.
        """
        frame_id = self.frame(frame, role)
        name = f"frames/{role}/{safe(frame)}"
        nodes = self.nodes
        if not nodes.has(f"{name}/x"):
            length = TRIAD_LENGTHS[role] * self.detail
            for axis, geometry, color in triad_parts(length, self.sizes["triad_radius"]):
                nodes.create(f"{name}/{axis}", geometry, material(color))
            nodes.declare(name)
        nodes.use(name)
        nodes.place(name, self.data.oMf[frame_id].homogeneous)
        self.drawn.add("frames")

    def span(
        self,
        name: str,
        start: np.ndarray,
        end: np.ndarray,
        geometry_factory: Callable[[], object],
        color: int,
        opacity: float = 1.0,
    ) -> None:
        """Show the dynamic unit shape ``name`` stretched from ``start`` to ``end``."""
        matrix = span_matrix(start, end)
        if matrix is not None:
            extra = {"depthWrite": False} if opacity < 1.0 else {}
            self._show(
                name, lambda: (geometry_factory(), material(color, opacity, **extra)), matrix
            )

    def marker(
        self, name: str, make: Callable[[], tuple[object, object]], position: np.ndarray
    ) -> None:
        """Show the dynamic object ``name`` at ``position`` [m].

        ``make()`` gives its ``(geometry, material)`` once, when it is created.
        """
        self._show(name, make, translation(position))

    def _show(self, name: str, make: Callable[[], tuple[object, object]], matrix: np.ndarray):
        """Show the dynamic object ``name`` at ``matrix``, made by ``make()`` the first time."""
        nodes = self.nodes
        if not nodes.has(name):
            nodes.create(name, *make())
            nodes.declare(name)
        nodes.use(name)
        nodes.place(name, matrix)

    def __repr__(self) -> str:
        return (
            f"RobotScene({self.robot.name!r}, {self.bodies.kind}, extent={self.extent:.3g} m, "
            f"camera={'side' if self.planar else 'iso'!r}, follow={self.follow})"
        )


class Overlay(ABC):
    """Something drawn over the robot: subclass it and implement `draw`."""

    def setup(self, scene: RobotScene) -> None:  # noqa: B027 - optional hook
        """Draw what never changes, once, when the overlay joins a viewer (nothing by default)."""

    @abstractmethod
    def draw(self, scene: RobotScene, frame: FrameSnapshot) -> None:
        """Draw one frame: place and ``use`` the overlay's nodes (``scene`` is at ``frame.q``)."""

    def __repr__(self) -> str:
        return f"{type(self).__name__}()"
