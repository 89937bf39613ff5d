"""Linear inequalities over the stacked reaction forces, with a name per row."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np


@dataclass(frozen=True, slots=True)
class Constraint:
    """``lows <= G x <= uppers`` over ``x = forces.ravel()`` (``p n`` entries), a name a row.

    Attributes:
        G: ``(m, p n)`` the rows.
        lows: ``(m,)`` their lower bounds.
        uppers: ``(m,)`` their upper bounds (``INFINITY`` for one-sided rows).
        names: ``m`` names, one per row (what the conflict error reports).
    """

    G: np.ndarray
    lows: np.ndarray
    uppers: np.ndarray
    names: Sequence[str]


def force_entries(axes: Sequence[str]) -> tuple[list[int], list[int]]:
    """The positions of the force axes among ``axes``, and which of x, y, z each is (0-2)."""
    positions = [i for i, axis in enumerate(axes) if axis in ("x", "y", "z")]
    return positions, ["xyz".index(axes[i]) for i in positions]


def moment_entries(axes: Sequence[str]) -> tuple[list[int], list[int]]:
    """The positions of the moment axes among ``axes``, and which of rx, ry, rz each is."""
    moments = ("rx", "ry", "rz")
    positions = [i for i, axis in enumerate(axes) if axis in moments]
    return positions, [moments.index(axes[i]) for i in positions]


class Entries(NamedTuple):
    """Where one contact's force and moment entries sit in ``x = forces.ravel()``."""

    #: positions in ``x`` of the contact's force entries
    force: np.ndarray
    #: positions in ``x`` of its moment entries
    moment: np.ndarray
    #: which of x, y, z each force entry is (0-2)
    force_components: list[int]
    #: which of rx, ry, rz each moment entry is (0-2)
    moment_components: list[int]
    #: the length of ``x`` (``p n``)
    width: int


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise cross products of ``(..., 3)`` arrays (np.cross costs ~10 us a call)."""
    return np.stack(
        (
            a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
            a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
            a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0],
        ),
        axis=-1,
    )
