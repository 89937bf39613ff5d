"""Contacts as declared: the kind per reaction frame, the contact normals, reaction lookup."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import NamedTuple

import numpy as np

from ..exceptions import ConstraintError, InvalidInputError
from ..vocabulary.arguments import as_float_array, check_name, describe

#: ``normals[reaction]`` value: the contact normal is the reaction frame's own z axis.
FRAME = "frame"
#: ``normals`` value: every contact's normal is its reaction frame's z axis.
FRAMES = "frames"


class Normals(NamedTuple):
    """The contact normals of ``p`` reactions, as declared."""

    #: ``(p, 3)`` unit normals in the world (world z unless declared; ignored where ``frame``)
    world: np.ndarray
    #: ``(p,)`` whether each normal is its reaction frame's z axis (read every tick)
    frame: np.ndarray


def check_contact(contact: object) -> str | dict[str, object]:
    """``contact`` as ``"point"``, ``"flat"`` or a dict keyed by reaction names (str).

    Raises:
        ConstraintError: Neither a string nor a mapping, or a key that is not a name.
    """
    if isinstance(contact, str):
        return contact
    if not isinstance(contact, Mapping):
        raise ConstraintError(
            "contact must be 'point', 'flat' or a dict {reaction_frame: 'point' | 'flat'}, "
            f"got {describe(contact)}."
        )
    for name in contact:
        check_name(name, "contact: a key (a reaction frame name)", ConstraintError)
    return dict(contact)


def reaction_index(name: object, reactions: Sequence[str], what: str) -> int:
    """The position of reaction frame ``name`` (``what`` names the argument in the error).

    Raises:
        InvalidInputError: ``name`` is not a reaction frame.
    """
    if name not in reactions:
        raise InvalidInputError(
            f"{what} names {name!r}, not a reaction frame; reactions are {list(reactions)}."
        )
    return list(reactions).index(name)


def parse_normals(
    normals: Mapping[str, Sequence[float] | str] | str | None, reactions: Sequence[str]
) -> Normals:
    """The contact normals: world z by default, a world vector or ``"frame"`` by reaction.

    Args:
        normals: None (world z), ``"frames"`` (every reaction frame's z axis) or a mapping by
            reaction frame of a nonzero world 3-vector (normalised) or ``"frame"``.
        reactions: The reaction frames' names.

    Raises:
        InvalidInputError: Another string, a zero or non-finite vector, an unknown reaction.
    """
    world = np.tile([0.0, 0.0, 1.0], (len(reactions), 1))
    frame = np.zeros(len(reactions), dtype=bool)
    if isinstance(normals, str):
        if normals != FRAMES:
            raise InvalidInputError(
                f"normals must be {FRAMES!r} (every reaction frame's z axis) or a mapping "
                f"by reaction frame, got {normals!r}."
            )
        normals = dict.fromkeys(reactions, FRAME)
    elif normals is not None and not isinstance(normals, Mapping):
        raise InvalidInputError(
            f"normals must be None, {FRAMES!r} or a mapping by reaction frame, got {normals!r}."
        )
    for name, normal in dict(normals or {}).items():
        index = reaction_index(name, reactions, "normals")
        if isinstance(normal, str):
            if normal != FRAME:
                raise InvalidInputError(
                    f"normals[{name!r}] must be {FRAME!r} (the frame's z axis) or a nonzero "
                    f"3-vector (world frame), got {normal!r}."
                )
            frame[index] = True
            continue
        valid = f"a nonzero 3-vector (world frame) or {FRAME!r}"
        vector = as_float_array(normal, f"normals[{name!r}]", valid).reshape(-1)
        size = float(np.linalg.norm(vector)) if vector.shape == (3,) else 0.0
        if not size or not np.isfinite(size):
            raise InvalidInputError(
                f"normals[{name!r}] must be a nonzero 3-vector (world frame) or {FRAME!r}, "
                f"got {normal!r}."
            )
        world[index] = vector / size
    return Normals(world, frame)
