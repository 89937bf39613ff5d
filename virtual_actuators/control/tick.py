"""One tick of the controller: the checks of its arguments and what it computed.

:meth:`Controller.compute` checks its ``limp`` indices and ``active`` names every tick with
:func:`check_limp` and :func:`check_active` (a bad value raises an
:class:`~virtual_actuators.InvalidInputError` that names the argument) and returns a
:class:`ControlOutput`; :func:`velocity_names` names the velocity entries.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from ..distribution.solution import Solution
from ..exceptions import InvalidInputError
from ..models.robot import Robot
from ..vocabulary.frames import describe
from .failures import AttachmentFailure


@dataclass(repr=False, slots=True)
class ControlOutput:
    """What the controller computed in one tick.

    Attributes:
        tau: ``(nv,)`` joint efforts after limp joints and clipping [N m or N].
        tau_requested: ``(nv,)`` before clipping.
        saturated: ``(nv,)`` bool, True where the request exceeds the effort limit (and was
            clipped, unless the controller was built with ``clip=False``).
        wrenches: Requested wrench per active attachment, on its actuator's axes.
        produced: Wrench actually produced per attachment (differs from the request on free axes
            and for inadmissible requests).
        positions: Sensor position per active attachment [m, rad].
        velocities: Sensor velocity per active attachment [m/s, rad/s].
        solutions: Distribution per parallel attachment.
        failed: Attachments that failed and contribute no effort this tick (the controller's
            ``on_failure="skip"``, or a fallback that could not be used), with the error
            message.
        active: Names of the attachments evaluated.
        joint_names: Names of the velocity entries (for reports).
        failures: Every attachment whose failure policy fired this tick: what failed and what
            the controller did (an :class:`~virtual_actuators.control.failures.
            AttachmentFailure`: ``reason``, ``error``, ``message``, ``action`` ``"skip"`` or
            ``"fallback"``). A fallback's unclipped solution is in ``solutions``.

    """

    tau: np.ndarray
    tau_requested: np.ndarray
    saturated: np.ndarray
    wrenches: dict[str, np.ndarray]
    produced: dict[str, np.ndarray]
    positions: dict[str, np.ndarray]
    velocities: dict[str, np.ndarray]
    solutions: dict[str, Solution]
    failed: dict[str, str]
    active: tuple[str, ...]
    joint_names: tuple[str, ...]
    failures: dict[str, AttachmentFailure] = field(default_factory=dict)

    @property
    def saturated_joints(self) -> list[str]:
        """Names of the velocity entries whose effort was clipped."""
        return [self.joint_names[i] for i in np.flatnonzero(self.saturated)]

    def __repr__(self) -> str:
        fallback = [name for name, f in self.failures.items() if f.action == "fallback"]
        return (
            f"ControlOutput(active={self.active}, |tau|={np.linalg.norm(self.tau):.3g}, "
            f"saturated={self.saturated_joints}, failed={list(self.failed)}"
            + (f", fallback={fallback})" if fallback else ")")
        )


def velocity_names(robot: Robot) -> tuple[str, ...]:
    """Name of every velocity entry: the joint's name, with ``[i]`` for multi-dof joints."""
    model = robot.model
    names: list[str] = []
    for joint_id in range(1, model.njoints):
        name, nv = model.names[joint_id], model.joints[joint_id].nv
        names.extend([name] if nv == 1 else [f"{name}[{i}]" for i in range(nv)])
    return tuple(names)


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


__all__ = [
    "NO_LIMP",
    "ControlOutput",
    "check_active",
    "check_limp",
    "check_same_velocity",
    "names_tuple",
    "velocity_names",
]
