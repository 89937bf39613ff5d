"""The pure functions that place the MeshCat scene's shapes.

three.js builds cylinders and cones along their local y axis, so an elongated shape is drawn
with ``[R diag(1, length, 1) | centre]``, ``R`` turning y onto its direction.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

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


def frame_on_plane(normal: np.ndarray, up: Sequence[float] = (0.0, 0.0, 1.0)) -> np.ndarray:
    """Rotation whose z axis is ``normal`` and whose y axis is as close as possible to ``up``."""
    up = np.asarray(up, dtype=float)
    z = np.asarray(normal, dtype=float)
    z = z / np.linalg.norm(z)
    x = np.cross(up, z)
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
