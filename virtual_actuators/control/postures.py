"""Joint-space terms in a controller, under a name.

A [`Posture`][] or a [`GravityCompensation`][].
"""

from __future__ import annotations

from ..components.gravity import GravityCompensation
from ..components.posture import Posture
from ..exceptions import InvalidInputError

__all__ = ["JointTerm", "add_posture", "tick_names"]


#: What ``Controller.add`` keeps as a joint-space term (``torques(snapshot)`` each tick).
JointTerm = Posture | GravityCompensation


def add_posture(
    controller: object, name: object, posture: JointTerm, components: object
) -> JointTerm:
    """Bind ``posture`` (or a gravity compensation) to the controller's robot, under ``name``.

    ``controller.compute`` then evaluates it like an attachment (``active`` may name it), and
    ``controller.reset`` resets it.

    Raises:
        InvalidInputError: The name is not a str or is taken, components were given, or a
            gravity compensation of another robot.
        JointNotFoundError: A joint of the posture that the robot lacks (with close matches).
    """
    kind = type(posture).__name__
    if not isinstance(name, str) or name in controller.attachments or name in controller.postures:
        raise InvalidInputError(
            f"{kind} {name!r}: the name must be a str not taken by another attachment."
        )
    if components not in ((), None, []):
        raise InvalidInputError(f"{kind} {name!r} takes no components: it is one.")
    controller.postures[name] = posture.bind(controller.robot)
    return posture


def tick_names(attachments: dict, postures: dict) -> tuple[str, ...]:
    """Every attachment's name, then every posture's: what ``compute`` evaluates by default."""
    return (*attachments, *postures) if postures else tuple(attachments)
