"""Shapes for the MeshCat scene: materials, the geometries MeshCat 0.3.2 lacks, their placements.

`Cone`, `Plane` and `TextTexture` are in three.js r132's JSON format; `Placed` gives a geometry a
fixed offset in its node. three.js builds cylinders and cones along their local y axis, so an
elongated shape is drawn with ``[R diag(1, length, 1) | centre]``, ``R`` turning y onto its
direction.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import meshcat.geometry as mg
import numpy as np

#: Shortest arrow drawn [m]; shorter vectors (zero wrenches) hide their arrow.
MIN_LENGTH = 1e-6

#: Offset between the two heads of a moment arrow, as a fraction of the head length.
HEAD_SPACING = 0.6


def rotation_y_to(direction: Sequence[float] | np.ndarray) -> np.ndarray:
    """The smallest rotation that turns the y axis onto ``direction``.

    Args:
        direction: A non-zero 3-vector (normalised here).

    Returns:
        ``(3, 3)`` rotation matrix ``R`` with ``R @ [0, 1, 0] == direction / |direction|``.

    Raises:
        ValueError: If ``direction`` is zero or not finite.
    """
    d = np.asarray(direction, dtype=float)
    norm = math.sqrt(float(d @ d))
    if not (norm > 0.0 and math.isfinite(norm)):
        raise ValueError(f"rotation_y_to needs a non-zero finite direction, got {d}.")
    x, c, z = d / norm
    if c < -1.0 + 1e-12:  # y onto -y: half a turn about x
        return np.diag([1.0, -1.0, -1.0])
    k = 1.0 / (1.0 + c)  # Rodrigues with the axis y x d = (z, 0, -x)
    return np.array(
        [[1.0 - k * x * x, x, -k * x * z], [-x, c, -z], [-k * x * z, z, 1.0 - k * z * z]]
    )


def span_matrix(start: np.ndarray, end: np.ndarray, rotation: np.ndarray | None = None):
    """Placement of a unit-length y-aligned shape stretched from ``start`` to ``end``.

    Args:
        start: 3-vector [m].
        end: 3-vector [m].
        rotation: ``rotation_y_to(end - start)`` if already known.

    Returns:
        ``(4, 4)`` matrix ``[R diag(1, L, 1) | (start + end) / 2]``, or None when the two points
        are closer than `MIN_LENGTH`.
    """
    start, end = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    delta = end - start
    length = math.sqrt(float(delta @ delta))
    if length < MIN_LENGTH:
        return None
    rot = rotation_y_to(delta) if rotation is None else rotation
    matrix = np.eye(4)
    matrix[:3, :3] = rot * [1.0, length, 1.0]
    matrix[:3, 3] = 0.5 * (start + end)
    return matrix


def arrow_matrices(
    origin: np.ndarray, vector: np.ndarray, head_length: float, heads: int = 1
) -> list[np.ndarray] | None:
    """Placements of an arrow's shaft and heads so that its tip is at ``origin + vector``.

    Heads shrink uniformly on an arrow shorter than ``(heads + 1) * head_length``; a second
    head sits `HEAD_SPACING` head lengths behind the first.

    Args:
        origin: Tail of the arrow [m].
        vector: Arrow from tail to tip, scaled [m].
        head_length: Nominal head length [m].
        heads: 1 (forces) or 2 (moments).

    Returns:
        ``[shaft, head, (second head)]`` ``(4, 4)`` matrices, or None for a vector shorter than
        `MIN_LENGTH`.
    """
    origin, vector = np.asarray(origin, dtype=float), np.asarray(vector, dtype=float)
    length = math.sqrt(float(vector @ vector))
    if length < MIN_LENGTH:
        return None
    direction = vector / length
    rot = rotation_y_to(direction)
    head = min(head_length, length / (heads + 1))
    scale = head / head_length
    shaft_length = length - head
    tip = origin + vector
    shaft = span_matrix(origin, origin + direction * shaft_length, rot)
    if shaft is None:  # a degenerate shaft (cannot happen for heads >= 1): keep a zero-length one
        shaft = np.eye(4)
        shaft[:3, :3] = rot @ np.diag([1.0, 0.0, 1.0])
        shaft[:3, 3] = origin
    out = [shaft]
    for k in range(heads):
        matrix = np.eye(4)
        matrix[:3, :3] = rot * scale
        matrix[:3, 3] = tip - direction * head * (0.5 + HEAD_SPACING * k)
        out.append(matrix)
    return out


def frame_on_plane(normal: np.ndarray) -> np.ndarray:
    """Rotation whose z axis is ``normal`` and whose y axis is as close as possible to world z."""
    z = np.asarray(normal, dtype=float)
    z = z / np.linalg.norm(z)
    x = np.cross(np.array([0.0, 0.0, 1.0]), z)
    if np.linalg.norm(x) < 1e-9:
        x = np.cross(np.array([0.0, 1.0, 0.0]), z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    return np.column_stack((x, y, z))


def translation(position: np.ndarray, scale: float = 1.0) -> np.ndarray:
    """``(4, 4)`` matrix of a uniform scale then a translation."""
    matrix = np.eye(4)
    if scale != 1.0:
        matrix[0, 0] = matrix[1, 1] = matrix[2, 2] = scale
    matrix[:3, 3] = position
    return matrix


def y_to_z() -> np.ndarray:
    """``(4, 4)`` rotation turning three.js's y-aligned shapes onto z (URDF cylinders)."""
    matrix = np.eye(4)
    matrix[:3, :3] = rotation_y_to([0.0, 0.0, 1.0])
    return matrix


def terrain_boxes(
    segments: Sequence[tuple[tuple[float, float], tuple[float, float]]],
    width: float,
    thickness: float = 0.05,
) -> list[tuple[np.ndarray, np.ndarray]]:
    """Boxes whose top faces follow a planar ground profile.

    Args:
        segments: ``((x0, z0), (x1, z1))`` pieces of the profile in the x-z plane [m].
        width: Extent along y [m].
        thickness: Thickness of the slabs [m].

    Returns:
        ``(lengths (3,), placement (4, 4))`` per segment, for a ``Box(lengths)``.
    """
    out = []
    for (x0, z0), (x1, z1) in segments:
        dx, dz = x1 - x0, z1 - z0
        length = math.hypot(dx, dz)
        if length < MIN_LENGTH:
            continue
        angle = math.atan2(dz, dx)  # slope about -y
        c, s = math.cos(angle), math.sin(angle)
        rot = np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]])
        centre = np.array([(x0 + x1) / 2, 0.0, (z0 + z1) / 2]) - rot[:, 2] * (thickness / 2 + 1e-3)
        matrix = np.eye(4)
        matrix[:3, :3] = rot
        matrix[:3, 3] = centre
        out.append((np.array([length, width, thickness]), matrix))
    return out


def to_hex(rgba: Sequence[float]) -> int:
    """Pack the first three entries of an RGB(A) colour in ``[0, 1]`` into ``0xRRGGBB``."""
    r, g, b = (min(255, max(0, int(round(float(c) * 255.0)))) for c in rgba[:3])
    return (r << 16) | (g << 8) | b


def material(color: int, opacity: float = 1.0, **properties: object) -> mg.MeshPhongMaterial:
    """A shaded material of one colour; ``opacity < 1`` makes it translucent."""
    return mg.MeshPhongMaterial(color=int(color), opacity=float(opacity), **properties)


class Cone(mg.Geometry):
    """A cone along the local y axis, centred on the origin, apex at ``+height / 2``.

    Args:
        height: Length along y [m].
        radius: Radius of the base [m].
    """

    def __init__(self, height: float, radius: float) -> None:
        super().__init__()
        self.height, self.radius = float(height), float(radius)

    def lower(self, object_data: object) -> dict:
        """The three.js ``ConeGeometry`` JSON."""
        return {
            "uuid": self.uuid,
            "type": "ConeGeometry",
            "radius": self.radius,
            "height": self.height,
            "radialSegments": 24,
            "heightSegments": 1,
            "openEnded": False,
        }

    def __repr__(self) -> str:
        return f"Cone(height={self.height:g}, radius={self.radius:g})"


class Plane(mg.Geometry):
    """A rectangle in the local x-y plane, centred on the origin, facing +z.

    Args:
        width: Size along x [m].
        height: Size along y [m].
    """

    def __init__(self, width: float, height: float) -> None:
        super().__init__()
        self.width, self.height = float(width), float(height)

    def lower(self, object_data: object) -> dict:
        """The three.js ``PlaneGeometry`` JSON."""
        return {
            "uuid": self.uuid,
            "type": "PlaneGeometry",
            "width": self.width,
            "height": self.height,
            "widthSegments": 1,
            "heightSegments": 1,
        }

    def __repr__(self) -> str:
        return f"Plane(width={self.width:g}, height={self.height:g})"


class TextTexture(mg.Texture):
    """One line of black text, centred on a 256 x 256 transparent canvas (MeshCat's ``_text``).

    Args:
        text: The line of text.
        font_size: Font size in canvas pixels (the canvas is 256 pixels wide), sans-serif.
    """

    def __init__(self, text: str, font_size: int = 28) -> None:
        super().__init__()
        self.text, self.font_size = str(text), int(font_size)

    def lower(self, object_data: object) -> dict:
        """The ``_text`` texture JSON of MeshCat's viewer."""
        return {
            "uuid": self.uuid,
            "type": "_text",
            "text": self.text,
            "font_size": self.font_size,
            "font_face": "sans-serif",
        }

    def __repr__(self) -> str:
        return f"TextTexture({self.text!r}, font_size={self.font_size})"


class Placed(mg.Geometry):
    """A geometry with a fixed placement inside its node (a rotated cylinder, an offset box).

    Args:
        geometry: The geometry.
        matrix: ``(4, 4)`` placement of the geometry in its node's frame.
    """

    def __init__(self, geometry: mg.Geometry, matrix: np.ndarray) -> None:
        super().__init__()
        self.geometry = geometry
        self.matrix = np.array(matrix, dtype=float)
        self.uuid = geometry.uuid

    def lower(self, object_data: object) -> dict:
        """The wrapped geometry's JSON."""
        return self.geometry.lower(object_data)

    def intrinsic_transform(self) -> np.ndarray:
        """The placement, transposed: MeshCat flattens it row by row, three.js reads columns."""
        return self.matrix.T

    def __repr__(self) -> str:
        return f"Placed({self.geometry!r})"


def text_faces(text: str, size: float, font_size: int = 28) -> list[tuple[str, mg.Mesh]]:
    """``text`` on two single-sided square planes of side ``size`` [m], back to back.

    The ``"front"`` plane faces its node's +z and the ``"back"`` one -z, so the text reads left
    to right from either side; transparent texels are discarded (``alphaTest``).

    Returns:
        ``(name, mesh)`` for the front and the back plane.
    """
    texture = TextTexture(text, font_size=font_size)
    front_side = 0  # three.js FrontSide
    material = mg.MeshBasicMaterial(map=texture, alphaTest=0.5, side=front_side)
    half_turn = np.diag([-1.0, 1.0, -1.0, 1.0])  # about +y: x -> -x, z -> -z
    return [
        ("front", mg.Mesh(Plane(size, size), material)),
        ("back", mg.Mesh(Placed(Plane(size, size), half_turn), material)),
    ]


def triad_parts(length: float, radius: float) -> list[tuple[str, Placed, int]]:
    """Three thin cylinders from the origin along x, y and z (red, green, blue).

    Returns:
        ``(axis name, placed geometry, colour)`` for each axis.
    """
    parts = []
    for index, (axis, color) in enumerate(zip("xyz", (0xE53935, 0x2E9E3E, 0x1E5BD8), strict=True)):
        direction = np.zeros(3)
        direction[index] = 1.0
        matrix = span_matrix(np.zeros(3), direction * length)  # unit cylinder, stretched
        parts.append((axis, Placed(mg.Cylinder(1.0, radius), matrix), color))
    return parts


def coil_mesh(radius: float = 1.0) -> mg.TriangularMeshGeometry:
    """A helical spring of 7 coils of unit length along y (from -0.5 to 0.5) around the y axis.

    Args:
        radius: Coil radius (the placement's x and z scale it; the wire's is 0.08 of it) [m].

    Returns:
        A triangle mesh (a tube swept along the helix, straight leads at both ends).
    """
    turns, wire = 7, 0.08
    samples = turns * 16
    lead = 0.08
    t = np.linspace(0.0, 1.0, samples + 1)
    centre = np.column_stack(
        (
            radius * np.cos(2 * np.pi * turns * t),
            -0.5 + lead + (1.0 - 2 * lead) * t,
            radius * np.sin(2 * np.pi * turns * t),
        )
    )
    centre = np.vstack(([0.0, -0.5, 0.0], [radius, -0.5 + lead, 0.0], centre[1:], [0.0, 0.5, 0.0]))
    sides = 6
    k = np.arange(len(centre))
    tangent = centre[np.minimum(k + 1, k[-1])] - centre[np.maximum(k - 1, 0)]
    tangent /= np.linalg.norm(tangent, axis=1, keepdims=True)
    normal = np.cross(tangent, [0.0, 1.0, 0.0])
    normal[np.linalg.norm(normal, axis=1) < 1e-9] = [1.0, 0.0, 0.0]
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    binormal = np.cross(tangent, normal)
    angles = 2 * np.pi * np.arange(sides) / sides
    circle = np.cos(angles)[:, None] * normal[:, None] + np.sin(angles)[:, None] * binormal[:, None]
    vertices = (centre[:, None] + wire * radius * circle).reshape(-1, 3)  # a ring per point
    a = (np.arange(len(centre) - 1)[:, None] * sides + np.arange(sides)).ravel()
    b = a - a % sides + (a + 1) % sides
    faces = np.column_stack((a, b, b + sides, a, b + sides, a + sides)).reshape(-1, 3)
    return mg.TriangularMeshGeometry(vertices.astype(np.float32), faces.astype(np.uint32))
