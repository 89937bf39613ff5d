"""Checks of :meth:`Controller.compute`'s per-tick arguments.

Every tick checks its ``limp`` indices and ``active`` names with these functions; a bad value
raises an :class:`~virtual_actuators.InvalidInputError` that names the argument.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..exceptions import InvalidInputError
from ..vocabulary.frames import describe

#: No limp joints.
NO_LIMP = np.zeros(0, dtype=np.intp)


def names_tuple(active: object) -> tuple:
    """``active`` as a tuple, or an :class:`InvalidInputError` naming it."""
    if not isinstance(active, (bytes, Mapping)):
        try:
            return tuple(active)
        except TypeError:
            pass
    raise InvalidInputError(
        f"active must be a sequence of attachment names (or one name), got {describe(active)}."
    )


def check_active(names: tuple) -> None:
    """``active``'s entries are attachment names (str), none repeated.

    Raises:
        InvalidInputError: An entry that is not a str (a list, a number), or a repeated name.

    """
    for i, name in enumerate(names):
        if not isinstance(name, str):
            raise InvalidInputError(
                f"active[{i}] must be an attachment name (str), got {describe(name)}."
            )
    if len(set(names)) != len(names):
        raise InvalidInputError(f"active names an attachment twice: {names}.")


def check_same_velocity(v: object, own: np.ndarray) -> None:
    """``compute(snapshot, v)``: ``v`` must equal the snapshot's velocity (never ignored).

    Raises:
        InvalidInputError: ``v`` differs from ``own`` (or is not an array of numbers).

    """
    try:
        same = np.array_equal(np.asarray(v), own)
    except (TypeError, ValueError):
        same = False
    if not same:
        raise InvalidInputError(
            "compute(snapshot, v): v differs from the velocity the snapshot was built with; "
            "omit v (the snapshot's is used) or build the snapshot with this v."
        )


def check_limp(limp: object, nv: int) -> np.ndarray:
    """``limp`` as an integer index array with every entry in ``[0, nv)``.

    Raises:
        InvalidInputError: Not a 1-D collection of integers in range.

    """
    expected = f"velocity indices, integers in [0, {nv}) (see Controller.joint_indices)"
    if isinstance(limp, (str, bytes, Mapping)) or limp is None:
        raise InvalidInputError(f"limp must be {expected}, got {describe(limp)}.")
    try:
        index = np.asarray(limp)
    except (TypeError, ValueError):
        raise InvalidInputError(f"limp must be {expected}, got {describe(limp)}.") from None
    if index.size == 0:
        return NO_LIMP
    if index.dtype.kind not in "iu" or index.ndim != 1:
        raise InvalidInputError(f"limp must be {expected}, got {describe(limp)}.")
    if index.min() < 0 or index.max() >= nv:
        raise InvalidInputError(f"limp must be {expected}, got {index.tolist()}.")
    return index


__all__ = ["NO_LIMP", "check_active", "check_limp", "check_same_velocity", "names_tuple"]
