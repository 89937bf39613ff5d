"""The point contact: a friction pyramid about the contact normal, and a least normal force.

Rows ``>= 0``: ``n . f >= min_normal`` (left out with faces and no least normal force), then the
faces ``mu n . f -+ t_1 . f``, ``mu n . f -+ t_2 . f``, the tangents fixed in the world (from
world x, y when the normal is near x) and turned into {O}.
"""

from __future__ import annotations

import numpy as np

from .constraint import cross


def ball_axes(rotation_axes: np.ndarray) -> np.ndarray:
    """A point transmits no moment about its origin: every selected rotational axis (0-2)."""
    return rotation_axes


def names(reaction: str, friction: float | None, min_normal: float, normal_row: bool) -> list[str]:
    """The pyramid's row names of one contact, in the order `pyramid` builds them."""
    out = [f"{reaction}: normal >= {min_normal:g} N"] if normal_row else []
    if friction is not None:
        out += [f"{reaction}: friction {w}" for w in ("+t1", "-t1", "+t2", "-t2")]
    return out


def pyramid(
    normals_world: np.ndarray,
    normals_o: np.ndarray,
    rotation_o: np.ndarray,
    friction: float | None,
    normal_row: bool,
) -> np.ndarray:
    """``(p, faces, 3)``: each contact's pyramid rows over its force, in {O}'s axes.

    Args:
        normals_world: ``(p, 3)`` unit contact normals in the world.
        normals_o: ``(p, 3)`` the same in {O} (``R_O^T n`` per row).
        rotation_o: ``(3, 3)`` {O}'s rotation in the world.
        friction: Friction coefficient ``mu``, or None for no faces.
        normal_row: Whether the normal row comes first.
    """
    helper = np.where(np.abs(normals_world[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    tangent1 = cross(normals_world, helper)
    tangent1 /= np.linalg.norm(tangent1, axis=1, keepdims=True)
    tangent2 = cross(normals_world, tangent1) @ rotation_o
    tangent1 = tangent1 @ rotation_o
    vectors = [normals_o] if normal_row else []
    if friction is not None:
        mu_normal = friction * normals_o
        vectors += [mu_normal - tangent1, mu_normal + tangent1]
        vectors += [mu_normal - tangent2, mu_normal + tangent2]
    return np.stack(vectors, axis=1)


def normal_row(friction: float | None, min_normal: float) -> bool:
    """Whether the rows start with ``n . f >= min_normal`` (the faces imply ``n . f >= 0``)."""
    return friction is None or min_normal > 0.0


def parameters(
    friction: float | None, min_normal: float, frame_normals: np.ndarray, normals_world: np.ndarray
) -> np.ndarray:
    """``(p, 7)`` the core's rows: friction (< 0: none), min normal, normal row, frame normal, n."""
    with_normal = float(normal_row(friction, min_normal))
    head = np.tile(
        (-1.0 if friction is None else friction, min_normal, with_normal), (len(frame_normals), 1)
    )
    return np.column_stack((head, frame_normals, normals_world))
