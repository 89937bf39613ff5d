"""Shapes for the MeshCat scene: materials, the geometries MeshCat 0.3.2 lacks, their placements.

`ThreeGeometry` is in three.js r132's JSON format; `Placed` gives a geometry a fixed offset in
its node. three.js builds cylinders and cones along their local y axis, so an
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
    return placement(rot * [1.0, length, 1.0], 0.5 * (start + end))


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
    if shaft is None:  # shorter than MIN_LENGTH (an arrow of a few MIN_LENGTH): a zero-length one
        shaft = placement(rot @ np.diag([1.0, 0.0, 1.0]), origin)
    centres = [tip - direction * head * (0.5 + HEAD_SPACING * k) for k in range(heads)]
    return [shaft, *(placement(rot * scale, centre) for centre in centres)]


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


def placement(rotation: np.ndarray, position: np.ndarray) -> np.ndarray:
    """``(4, 4)`` matrix ``[rotation | position]`` (the ``(3, 3)`` block may hold a scale too)."""
    matrix = np.eye(4)
    matrix[:3, :3] = rotation
    matrix[:3, 3] = position
    return matrix


def translation(position: np.ndarray, scale: float = 1.0) -> np.ndarray:
    """``(4, 4)`` matrix of a uniform scale then a translation."""
    return placement(np.eye(3) * scale, position)


def y_to_z() -> np.ndarray:
    """``(4, 4)`` rotation turning three.js's y-aligned shapes onto z (URDF cylinders)."""
    return placement(rotation_y_to([0.0, 0.0, 1.0]), np.zeros(3))


def terrain_boxes(
    segments: Sequence[tuple[tuple[float, float], tuple[float, float]]], width: float
) -> list[tuple[np.ndarray, np.ndarray]]:
    """Slabs 5 cm thick whose top faces follow a planar ground profile.

    Args:
        segments: ``((x0, z0), (x1, z1))`` pieces of the profile in the x-z plane [m].
        width: Extent along y [m].

    Returns:
        ``(lengths (3,), placement (4, 4))`` per segment, for a ``Box(lengths)``.
    """
    out, thickness = [], 0.05
    for (x0, z0), (x1, z1) in segments:
        dx, dz = x1 - x0, z1 - z0
        length = math.hypot(dx, dz)
        if length < MIN_LENGTH:
            continue
        angle = math.atan2(dz, dx)  # slope about -y
        c, s = math.cos(angle), math.sin(angle)
        rot = np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]])
        centre = np.array([(x0 + x1) / 2, 0.0, (z0 + z1) / 2]) - rot[:, 2] * (thickness / 2 + 1e-3)
        out.append((np.array([length, width, thickness]), placement(rot, centre)))
    return out


def to_hex(rgba: Sequence[float]) -> int:
    """Pack the first three entries of an RGB(A) colour in ``[0, 1]`` into ``0xRRGGBB``."""
    r, g, b = (min(255, max(0, int(round(float(c) * 255.0)))) for c in rgba[:3])
    return (r << 16) | (g << 8) | b


def material(color: int, opacity: float = 1.0, **properties: object) -> mg.MeshPhongMaterial:
    """A shaded material of one colour; ``opacity < 1`` makes it translucent."""
    return mg.MeshPhongMaterial(color=int(color), opacity=float(opacity), **properties)


class ThreeGeometry(mg.Geometry):
    """A three.js r132 geometry that MeshCat 0.3.2 lacks, given by its JSON type and fields.

    Args:
        kind: The three.js type (``"ConeGeometry"``, ``"PlaneGeometry"``).
        fields: Its parameters, as three.js names them.
    """

    def __init__(self, kind: str, **fields: object) -> None:
        super().__init__()
        self.kind, self.fields = kind, fields

    def lower(self, object_data: object) -> dict:
        """The geometry's three.js JSON."""
        return {"uuid": self.uuid, "type": self.kind, **self.fields}

    def __repr__(self) -> str:
        return f"ThreeGeometry({self.kind!r}, {self.fields})"


def cone(height: float, radius: float) -> ThreeGeometry:
    """A cone along the local y axis, centred on the origin, apex at ``+height / 2``.

    Args:
        height: Length along y [m].
        radius: Radius of the base [m].
    """
    return ThreeGeometry(
        "ConeGeometry",
        radius=float(radius),
        height=float(height),
        radialSegments=24,
        heightSegments=1,
        openEnded=False,
    )


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
    texture = mg.GenericTexture(  # MeshCat's: the line centred on a 256 x 256 transparent canvas
        {"type": "_text", "text": str(text), "font_size": int(font_size), "font_face": "sans-serif"}
    )
    front_side = 0  # three.js FrontSide
    material = mg.MeshBasicMaterial(map=texture, alphaTest=0.5, side=front_side)
    half_turn = np.diag([-1.0, 1.0, -1.0, 1.0])  # about +y: x -> -x, z -> -z
    planes = [ThreeGeometry("PlaneGeometry", width=size, height=size) for _ in range(2)]
    return [
        ("front", mg.Mesh(planes[0], material)),
        ("back", mg.Mesh(Placed(planes[1], half_turn), material)),
    ]


def triad_parts(length: float, radius: float) -> list[tuple[str, Placed, int]]:
    """Three thin cylinders from the origin along x, y and z (red, green, blue).

    Returns:
        ``(axis name, placed geometry, colour)`` for each axis.
    """
    parts = []
    for index, (axis, color) in enumerate(zip("xyz", (0xE53935, 0x2E9E3E, 0x1E5BD8), strict=True)):
        matrix = span_matrix(np.zeros(3), np.eye(3)[index] * length)  # unit cylinder, stretched
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
