"""The point contact: a friction pyramid about the contact normal, and a least normal force.

Rows ``>= 0`` on a contact's force: ``n . f >= min_normal`` (left out with a pyramid and no least
normal force: the faces imply it, ``(mu n - t) + (mu n + t) = 2 mu n``), then the four faces
``mu n . f -+ t_1 . f``, ``mu n . f -+ t_2 . f``, the tangents fixed in the world (from the world
x axis, y when the normal is near x) and turned into {O}. The numpy rows (`pyramid`) are
the reference; the njit ones (`face_rows`, `force_row`) build the compiled path's.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..kinematics.kernels import njit
from .constraint import Constraint, Contact, cross, force_entries

#: the most rows of one contact: the least normal force and four faces
MAX_ROWS = 5


def ball_axes(rotation_axes: np.ndarray) -> np.ndarray:
    """A point transmits no moment about its origin: every selected rotational axis (0-2)."""
    return rotation_axes


def faces(friction: float | None, normal_row: bool) -> int:
    """How many rows a contact's pyramid has."""
    return int(normal_row) + (4 if friction is not None else 0)


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


def parameters(contact: Contact) -> np.ndarray:
    """The float row `kernel_rows` reads.

    Friction (< 0 for none), least normal force, 1 for the normal row, 1 for a frame normal,
    then the world normal.
    """
    friction = -1.0 if contact.friction is None else contact.friction
    with_normal = normal_row(contact.friction, contact.min_normal)
    flags = (float(with_normal), float(contact.frame_normal))
    return np.array([friction, contact.min_normal, *flags, *contact.normal], dtype=float)


def contact_rows(
    contact: Contact,
    frame_world: np.ndarray,
    rotation_o: np.ndarray,
    offset_o: np.ndarray,
    axes: Sequence[str],
) -> Constraint:
    """The contact's rows ``>= lows`` over its chain's force ``F_i`` (``n`` entries, in {O}).

    Args:
        contact: The declaration.
        frame_world: ``(3, 3)`` the reaction frame's rotation in the world.
        rotation_o: ``(3, 3)`` {O}'s rotation in the world.
        offset_o: ``(3,)`` from the reaction frame's origin to {B}'s, in {O} (unused).
        axes: The actuator's axes.

    """
    normal = frame_world[:, 2] if contact.frame_normal else np.asarray(contact.normal, float)
    with_normal = normal_row(contact.friction, contact.min_normal)
    vectors = pyramid(normal[None], (normal @ rotation_o)[None], rotation_o, contact.friction,
                      with_normal)[0]  # fmt: skip
    positions, components = force_entries(axes)
    G = np.zeros((len(vectors), len(axes)))
    G[:, positions] = vectors[:, components]
    lows = np.zeros(len(vectors))
    lows[:with_normal] = contact.min_normal
    row_names = names(contact.reaction, contact.friction, contact.min_normal, with_normal)
    return Constraint(G, lows, np.full(len(lows), np.inf), row_names)


@njit(cache=True)
def face_rows(normal: np.ndarray, friction: float, with_normal: bool, out: np.ndarray) -> int:
    """The pyramid's rows (``>= 0``, in the world) about ``normal``: returns how many.

    Tangents from the world x axis (y when the normal is near x): fixed in the world.
    """
    count = 0
    if with_normal:
        out[0, :] = normal
        count = 1
    if friction < 0.0:
        return count
    helper = (1.0, 0.0, 0.0) if abs(normal[0]) < 0.9 else (0.0, 1.0, 0.0)
    t1 = np.empty(3)
    t1[0] = normal[1] * helper[2] - normal[2] * helper[1]
    t1[1] = normal[2] * helper[0] - normal[0] * helper[2]
    t1[2] = normal[0] * helper[1] - normal[1] * helper[0]
    t1 /= np.sqrt(t1[0] ** 2 + t1[1] ** 2 + t1[2] ** 2)
    t2 = np.empty(3)
    t2[0] = normal[1] * t1[2] - normal[2] * t1[1]
    t2[1] = normal[2] * t1[0] - normal[0] * t1[2]
    t2[2] = normal[0] * t1[1] - normal[1] * t1[0]
    for face in range(4):
        tangent = t1 if face < 2 else t2
        sign = -1.0 if face % 2 == 0 else 1.0
        for c in range(3):
            out[count, c] = friction * normal[c] + sign * tangent[c]
        count += 1
    return count


@njit(cache=True)
def to_o(rot_o: np.ndarray, rows: np.ndarray, count: int) -> None:
    """``rows[:count]`` (world vectors) into {O}'s axes in place: ``R_O^T v`` for each row."""
    for f in range(count):
        v0, v1, v2 = rows[f, 0], rows[f, 1], rows[f, 2]
        for c in range(3):
            rows[f, c] = rot_o[0, c] * v0 + rot_o[1, c] * v1 + rot_o[2, c] * v2


@njit(cache=True)
def force_row(
    vector: np.ndarray,
    axis_rows: np.ndarray,
    chain_x0: np.ndarray,
    chain_basis: np.ndarray,
    out: np.ndarray,
    lows: np.ndarray,
    row: int,
    low: float,
) -> None:
    """``vector . f_i >= low`` over ``z_i``: the row into ``out``, the bound into ``lows``.

    With ``f_i = x0_i + N_i z_i`` (the chain's particular force and free basis).
    """
    constant = 0.0
    for a in range(axis_rows.shape[0]):
        component = axis_rows[a]
        if component >= 3:
            continue
        weight = vector[component]
        constant += weight * chain_x0[a]
        for j in range(chain_basis.shape[1]):
            out[j] += weight * chain_basis[a, j]
    lows[row] = low - constant


@njit(cache=True)
def kernel_rows(
    parameters: np.ndarray,
    placement: np.ndarray,
    rot_o: np.ndarray,
    offset_o: np.ndarray,
    axis_rows: np.ndarray,
    out: np.ndarray,
    lows: np.ndarray,
) -> int:
    """`contact_rows` compiled: the rows over ``F_i`` into ``out``, bounds into ``lows``.

    ``parameters`` is `parameters`' row, ``placement`` the reaction frame's row of the
    snapshot's frames (``R.ravel()`` first), ``axis_rows`` the component (0-5) of each axis;
    returns how many rows.
    """
    normal = np.empty(3)
    for c in range(3):  # a frame normal: its z axis in the world, column 2 of its rotation
        normal[c] = placement[3 * c + 2] if parameters[3] > 0.0 else parameters[4 + c]
    faces = np.empty((MAX_ROWS, 3))
    with_normal = parameters[2] > 0.0
    count = face_rows(normal, parameters[0], with_normal, faces)
    to_o(rot_o, faces, count)
    n = axis_rows.shape[0]
    particular, basis = np.zeros(n), np.eye(n)
    for f in range(count):
        low = parameters[1] if with_normal and f == 0 else 0.0
        force_row(faces[f], axis_rows, particular, basis, out[f], lows, f, low)
    return count


__all__ = [
    "MAX_ROWS",
    "ball_axes",
    "contact_rows",
    "face_rows",
    "faces",
    "force_row",
    "kernel_rows",
    "names",
    "normal_row",
    "parameters",
    "pyramid",
    "to_o",
]
