"""Joint-space terms in a controller: [`Posture`][] under a name."""

from __future__ import annotations

from ..components.posture import Posture
from ..exceptions import InvalidInputError

__all__ = ["add_posture", "tick_names"]


def add_posture(controller: object, name: object, posture: Posture, components: object) -> Posture:
    """Bind ``posture`` to the controller's robot and keep it under ``name``.

    ``controller.compute`` then evaluates it like an attachment (``active`` may name it), and
    ``controller.reset`` resets it.

    Raises:
        InvalidInputError: The name is not a str or is taken, or components were given.
        JointNotFoundError: A joint of the posture that the robot lacks (with close matches).

    """
    if not isinstance(name, str) or name in controller.attachments or name in controller.postures:
        raise InvalidInputError(
            f"Posture {name!r}: the name must be a str not taken by another attachment."
        )
    if components not in ((), None, []):
        raise InvalidInputError(f"Posture {name!r} takes no components: it is one.")
    controller.postures[name] = posture.bind(controller.robot)
    return posture


def tick_names(attachments: dict, postures: dict) -> tuple[str, ...]:
    """Every attachment's name, then every posture's: what ``compute`` evaluates by default."""
    return (*attachments, *postures) if postures else tuple(attachments)
