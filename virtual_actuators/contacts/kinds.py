"""The contact kinds by name and each reaction's kind (docs/contributing.md: adding a kind)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ..exceptions import ConstraintError
from . import flat, point

#: the contact kinds, by the name ``contact=`` gives them
KINDS = {"point": point, "flat": flat}


def parse_contacts(contact: str | Mapping[str, str], reactions: Sequence[str]) -> tuple[str, ...]:
    """Each reaction's contact kind, ``"point"`` or ``"flat"``.

    Raises:
        ConstraintError: An unknown kind, or a key that is not a reaction frame.
    """
    if isinstance(contact, str):
        if contact not in KINDS:
            raise ConstraintError(
                f"contact must be one of {list(KINDS)} or a dict; got {contact!r}."
            )
        return (contact,) * len(reactions)
    unknown = set(contact) - set(reactions)
    if unknown:
        raise ConstraintError(
            f"contact names {sorted(unknown)} which are not reaction frames; "
            f"reactions are {list(reactions)}."
        )
    out = []
    for name in reactions:
        kind = contact.get(name, "point")
        if kind not in KINDS:
            raise ConstraintError(f"contact[{name!r}] must be one of {list(KINDS)}, got {kind!r}.")
        out.append(kind)
    return tuple(out)


def ball_axes(kind: str, rotation_axes: np.ndarray) -> np.ndarray:
    """The selected rotational axes (0-2) about which a contact of ``kind`` transmits no moment."""
    return KINDS[kind].ball_axes(rotation_axes)
