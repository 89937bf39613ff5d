"""What the controller computed in one tick, and the names of the velocity entries."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..distribution.solution import Solution
from ..models.robot import Robot
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


__all__ = ["ControlOutput", "velocity_names"]
