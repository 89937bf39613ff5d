"""Frame a recording on the robot over the whole run: the box holding its bodies in every frame."""

from __future__ import annotations

import math

import numpy as np
from meshcat.commands import SetProperty, SetTransform
from meshcat.path import Path as MeshcatPath

from .scene import Scene
from .shape_placement import translation

#: Vertical field of view of MeshCat's default camera [deg].
CAMERA_FOV_DEG = 75.0

#: What a recording is framed on: the robot's bodies.
FRAMED = ("robot/",)


class RunBounds:
    """Bounding box of what the recorded frames show, in the view's coordinates [m].

    Attributes:
        low: Smallest ``x y z`` of a visible node's origin over the frames (None: no frame).
        high: Largest ``x y z``.
    """

    def __init__(self) -> None:
        self.low: np.ndarray | None = None
        self.high: np.ndarray | None = None

    def add(self, scene: Scene) -> None:
        """Grow the box with the robot's visible bodies in their current pose."""
        points = visible_points(scene, FRAMED)
        if len(points) == 0:
            return
        low, high = points.min(axis=0), points.max(axis=0)
        self.low = low if self.low is None else np.minimum(self.low, low)
        self.high = high if self.high is None else np.maximum(self.high, high)

    def __repr__(self) -> str:
        if self.low is None:
            return "RunBounds(empty)"
        return f"RunBounds(low={np.round(self.low, 3)}, high={np.round(self.high, 3)})"


def visible_points(scene: Scene, under: tuple[str, ...]) -> np.ndarray:
    """Origins ``(n, 3)`` of the placed nodes, none of whose parents is hidden, in view axes.

    Args:
        scene: The scene.
        under: Only the nodes whose names start so.
    """
    matrices, visible = scene.matrices, scene.visible
    root = matrices.get("", np.eye(4))
    composed: dict[str, np.ndarray | None] = {"": root}

    def pose(name: str) -> np.ndarray | None:
        if name in composed:
            return composed[name]
        parent, _, _ = name.rpartition("/")
        above = pose(parent)
        if above is None or visible.get(name) is False:
            result = None
        else:
            own = matrices.get(name)
            result = above if own is None else above @ own
        composed[name] = result
        return result

    poses = [pose(name) for name in matrices if name and name.startswith(under)]
    points = [matrix[:3, 3] for matrix in poses if matrix is not None]
    return np.array(points) if points else np.zeros((0, 3))


#: MeshCat's camera object, and the node above every drawn scene (shifted to centre the run).
CAMERA_PATH = MeshcatPath(("Cameras", "default", "rotated", "<object>"))
SCENES_PATH = MeshcatPath(("meshcat",))


def framing_commands(bounds: RunBounds, view: np.ndarray, margin: float) -> list[object]:
    """Commands that centre the run's box on the origin and fit a sphere around it in view.

    Args:
        bounds: The run's box.
        view: Unit vector from the target to the camera (world axes).
        margin: Added around the box [m].

    Returns:
        ``SetTransform`` of ``/meshcat`` and ``SetProperty`` of the camera's position (none
        for an empty box).
    """
    if bounds.low is None or bounds.high is None:
        return []
    centre = (bounds.low + bounds.high) / 2.0
    radius = 0.5 * float(np.linalg.norm(bounds.high - bounds.low)) + margin
    distance = max(0.8, radius / math.sin(math.radians(CAMERA_FOV_DEG) / 2.0))
    offset = view * distance  # world axes; three.js is y-up
    local = [float(offset[0]), float(offset[2]), float(-offset[1])]
    return [
        SetTransform(translation(-centre), SCENES_PATH),
        SetProperty("position", local, CAMERA_PATH),
    ]
