"""The flat contact: a sole whose centre of pressure stays inside it, with a bounded yaw moment.

With the sole ``(half_length, half_width)`` [m] along its frame's x and y axes ``e_c`` in {O} and
``d`` from {A_i} to {B}, the moment about the frame's origin ``e_c . m_A = e_c . m_B + f . (e_c x
d)`` is bounded by ``half_c (e_z . f)``: ``half_width`` about x, ``half_length`` about y,
``mu min(half_length, half_width)`` about z (six rows ``>= 0``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ..exceptions import InvalidInputError
from ..vocabulary.arguments import as_float_array
from .constraint import Entries, cross, force_entries, moment_entries, reaction_index


def ball_axes(rotation_axes: np.ndarray) -> np.ndarray:
    """A sole transmits moments: no natural-constraint column."""
    return np.array([], dtype=int)


def parse_soles(
    soles: Mapping[str, Sequence[float]] | None, reactions: Sequence[str], kinds: Sequence[str]
) -> dict[int, tuple[float, float]]:
    """``{reaction index: (half_length, half_width)}`` in chain order (the rows' order).

    Args:
        soles: ``(half_length, half_width)`` [m] by reaction frame, or None.
        reactions: The reaction frames' names.
        kinds: ``"point"`` or ``"flat"`` per reaction.

    Raises:
        InvalidInputError: Not two positive finite numbers, an unknown reaction, a point sole.
    """
    parsed: dict[int, tuple[float, float]] = {}
    for name, sole in dict(soles or {}).items():
        index = reaction_index(name, reactions, "soles")
        valid = "(half_length, half_width) > 0 [m]"
        values = as_float_array(sole, f"soles[{name!r}]", valid).reshape(-1)
        if values.shape != (2,) or not np.all(np.isfinite(values)) or np.any(values <= 0):
            raise InvalidInputError(
                f"soles[{name!r}] must be (half_length, half_width) > 0 [m], got {sole!r}."
            )
        if kinds[index] != "flat":
            raise InvalidInputError(
                f"soles[{name!r}]: {name!r} is a point contact; a sole needs contact='flat'."
            )
        parsed[index] = (float(values[0]), float(values[1]))
    return dict(sorted(parsed.items()))


def names(reaction: str, sole: tuple[float, float], friction: float | None) -> list[str]:
    """The sole's six row names, in the order `rows` builds them."""
    half_length, half_width = sole
    mu = friction if friction is not None else 0.0
    out = []
    for label, half in (("x", half_width), ("y", half_length), ("z", mu * min(sole))):
        out.append(f"{reaction}: moment {label} <= {half:g} f_n")
        out.append(f"{reaction}: moment {label} >= -{half:g} f_n")
    return out


def rows(
    sole: tuple[float, float],
    friction: float | None,
    frame_o: np.ndarray,
    offset: np.ndarray,
    entries: Entries,
) -> np.ndarray:
    """``(6, p n)``: the sole's rows ``>= 0`` over ``x = forces.ravel()``.

    Args:
        sole: ``(half_length, half_width)`` [m].
        friction: Friction coefficient ``mu`` (the yaw bound), or None (no yaw moment).
        frame_o: ``(3, 3)`` columns: the reaction frame's x, y, z axes in {O}.
        offset: ``(3,)`` from the reaction frame's origin to {B}'s, in {O}.
        entries: Where the contact's force and moment entries sit in ``x``.
    """
    half_length, half_width = sole
    normal_row = np.zeros(entries.width)  # the force along the sole's normal (its frame's z)
    normal_row[entries.force] = frame_o[entries.force_components, 2]
    mu = friction if friction is not None else 0.0
    out = []
    for column, half in ((0, half_width), (1, half_length), (2, mu * min(sole))):
        axis_o = frame_o[:, column]
        row = np.zeros(entries.width)  # axis . m_A = axis . m_B + f . (axis x d)
        row[entries.moment] = axis_o[entries.moment_components]
        row[entries.force] += cross(axis_o, offset)[entries.force_components]
        out += [half * normal_row - row, half * normal_row + row]
    return np.array(out)


def entries(axes: Sequence[str], chain: int, p: int) -> Entries:
    """Where chain ``chain``'s force and moment entries sit in ``x = forces.ravel()``."""
    n = len(axes)
    force, force_components = force_entries(axes)
    moment, moment_components = moment_entries(axes)
    return Entries(
        chain * n + np.array(force, dtype=int), chain * n + np.array(moment, dtype=int),
        force_components, moment_components, p * n,
    )  # fmt: skip


def active(soles: Mapping[int, tuple[float, float]], axes: Sequence[str]) -> bool:
    """Whether the soles give rows: they bound moments, so they need moment axes."""
    return bool(soles) and bool(moment_entries(axes)[0])


def declared_names(
    soles: Mapping[int, tuple[float, float]],
    reactions: Sequence[str],
    friction: float | None,
    axes: Sequence[str],
) -> list[str]:
    """Every sole's row names, in the order `block` builds the rows."""
    if not active(soles, axes):
        return []
    return [name for i, sole in soles.items() for name in names(reactions[i], sole, friction)]


def block(
    soles: Mapping[int, tuple[float, float]],
    friction: float | None,
    rotation_o: np.ndarray,
    rotation_a: np.ndarray,
    offsets_o: np.ndarray,
    axes: Sequence[str],
) -> np.ndarray:
    """``(6 s, p n)``: every sole's rows ``>= 0`` over ``x = forces.ravel()``, in chain order.

    Args:
        soles: ``{reaction index: (half_length, half_width)}``.
        friction: The yaw bound's ``mu``, or None.
        rotation_o: ``(3, 3)`` {O}'s rotation in the world.
        rotation_a: ``(p, 3, 3)`` the reaction frames' rotations in the world.
        offsets_o: ``(p, 3)`` from each reaction frame's origin to {B}'s, in {O}.
        axes: The actuator's axes.
    """
    p = len(rotation_a)
    return np.vstack([
        rows(sole, friction, rotation_o.T @ rotation_a[i], offsets_o[i], entries(axes, i, p))
        for i, sole in soles.items()
    ])  # fmt: skip


def table(soles: Mapping[int, tuple[float, float]], p: int) -> np.ndarray:
    """``(p, 3)`` the compiled path's table: 1 for a sole, its half length and half width."""
    out = np.zeros((p, 3))
    for i, sole in soles.items():
        out[i] = (1.0, *sole)
    return out
