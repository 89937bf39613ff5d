"""What a controller does when one attachment fails: ``Controller(robot, on_failure=...)``.

An attachment fails in a tick when its components cannot give a wrench (a component raises a
library error or an arithmetic error, or returns a non-finite or malformed wrench), when its
distribution cannot be solved ([`SingularConfigurationError`][]; a
[`ConstraintError`][] from a contact QP that is infeasible or runs out of
iterations; [`InadmissibleWrenchError`][]), or when its joint efforts are
not finite. One policy covers every case:

- ``"raise"``: the typed error leaves [`Controller.compute`][]
  ([`InvalidInputError`][] for a bad wrench or non-finite efforts);
- ``"skip"``: that attachment contributes zero effort for the tick;
- ``"fallback"``: that attachment contributes the partitioned least-squares answer to the same
  request (``actuator.solve(q, wrench, free, method="partitioned")``, never strict), clipped to
  the controller's effort limits; when there is no request to distribute (the components
  failed), a serial actuator, or the fallback fails too, it contributes zero effort.

The tick's [`ControlOutput`][] reports each firing in ``failures`` (an
[`AttachmentFailure`][] per attachment) and lists the attachments left at zero in ``failed``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..exceptions import (
    ConstraintError,
    InadmissibleWrenchError,
    InvalidInputError,
    SingularConfigurationError,
    VirtualActuatorError,
)
from ..kinematics.snapshot import Snapshot
from .attachment import Attachment

#: The values of ``Controller(on_failure=...)``.
FAILURE_POLICIES = ("raise", "skip", "fallback")

#: What a policy catches: the library's typed errors and arithmetic errors (a division by zero
#: in a component). Other exceptions (a TypeError from a bug) always propagate.
CAUGHT = (VirtualActuatorError, ArithmeticError)


@dataclass(frozen=True, slots=True)
class AttachmentFailure:
    """One attachment's failure in a tick and what the controller did.

    Attributes:
        reason: What failed: ``"wrench"`` (the components gave no finite wrench),
            ``"singular"``, ``"constraint"`` (e.g. a contact QP that is infeasible or out of
            iterations), ``"inadmissible"``, ``"distribution"`` (another error of the
            distribution) or ``"effort"`` (non-finite joint efforts).
        error: The exception's type name, e.g. ``"ConstraintError"``.
        message: The exception's message.
        action: ``"skip"`` (the attachment contributed zero effort) or ``"fallback"`` (the
            clipped partitioned least-squares answer; see `failures`).
        fallback_error: Why the fallback was not used (then ``action`` is ``"skip"``), or None.
    """

    reason: str
    error: str
    message: str
    action: str
    fallback_error: str | None = None

    def __str__(self) -> str:
        text = f"{self.reason} ({self.error}: {self.message}) -> {self.action}"
        return text if self.fallback_error is None else f"{text} ({self.fallback_error})"


def check_policy(on_failure: object, on_singular: object) -> str:
    """The controller's policy from ``on_failure`` and its former name ``on_singular``.

    Args:
        on_failure: One of `FAILURE_POLICIES`, or None.
        on_singular: The same (the name before every failure shared one policy), or None.

    Returns:
        ``on_failure``, else ``on_singular``, else ``"raise"``.

    Raises:
        InvalidInputError: A value that is not a policy, or both given and different.
    """
    for what, value in (("on_failure", on_failure), ("on_singular", on_singular)):
        if value is not None and (not isinstance(value, str) or value not in FAILURE_POLICIES):
            raise InvalidInputError(f"{what} must be one of {FAILURE_POLICIES}, got {value!r}.")
    if on_failure is not None and on_singular is not None and on_failure != on_singular:
        raise InvalidInputError(
            f"on_singular is the former name of on_failure; give one of them, got "
            f"on_failure={on_failure!r} and on_singular={on_singular!r}."
        )
    return on_failure or on_singular or "raise"


def reason_of(error: BaseException, wrench: np.ndarray | None) -> str:
    """The `AttachmentFailure.reason` of ``error`` (``wrench`` None: components failed)."""
    if wrench is None:
        return "wrench"
    if isinstance(error, SingularConfigurationError):
        return "singular"
    if isinstance(error, InadmissibleWrenchError):
        return "inadmissible"
    if isinstance(error, ConstraintError):
        return "constraint"
    return "distribution"


def recover(
    policy: str,
    attachment: Attachment,
    snapshot: Snapshot,
    wrench: np.ndarray | None,
    reason: str,
    error: BaseException,
    limits: tuple[np.ndarray, np.ndarray],
    failures: dict[str, AttachmentFailure],
    failed: dict[str, str],
) -> tuple[object | None, np.ndarray | None]:
    """Apply ``policy`` (``"skip"`` or ``"fallback"``) to one attachment's failure.

    Args:
        policy: ``"skip"`` or ``"fallback"``.
        attachment: The attachment that failed.
        snapshot: The tick's snapshot.
        wrench: Its requested wrench, or None when its components failed.
        reason: The failure's reason (see `AttachmentFailure.reason`).
        error: The exception.
        limits: ``(lower, upper)`` effort limits the fallback is clipped to.
        failures: The tick's records, updated: ``failures[name]``.
        failed: The tick's attachments left at zero, updated when no fallback is used.

    Returns:
        ``(solution, tau)``: with a working fallback, its [`Solution`][]
        (unclipped) and its clipped, finite ``(nv,)`` efforts; else ``(None, None)``.
    """
    name, error_name, message = attachment.name, type(error).__name__, str(error)
    why = None
    if policy == "fallback":
        actuator = attachment.actuator
        if wrench is None:
            why = "no fallback: the components gave no wrench"
        elif not hasattr(actuator, "solve_checked"):
            why = "no fallback for a serial actuator"
        else:
            try:
                request = actuator.plan(attachment.free, "partitioned")
                solution = actuator.solve_checked(snapshot, wrench, request)[0]
                if np.isfinite(solution.tau).all():
                    tau = np.minimum(np.maximum(solution.tau, limits[0]), limits[1])
                    failures[name] = AttachmentFailure(reason, error_name, message, "fallback")
                    return solution, tau
                why = "fallback failed: non-finite efforts"
            except CAUGHT as fallback_error:
                why = f"fallback failed: {type(fallback_error).__name__}: {fallback_error}"
    failures[name] = AttachmentFailure(reason, error_name, message, "skip", why)
    failed[name] = message
    return None, None


def drop_non_finite(
    controller: object,
    snapshot: Snapshot,
    parts: list[tuple[str, np.ndarray]],
    wrenches: dict[str, np.ndarray],
    produced: dict[str, np.ndarray],
    solutions: dict[str, object],
    failures: dict[str, AttachmentFailure],
    failed: dict[str, str],
) -> np.ndarray:
    """A tick's efforts again, the policy applied to the attachments with non-finite ones.

    Called when the sum is not finite: a finite wrench too large for float64.

    Args:
        controller: The [`Controller`][].
        snapshot: The tick's snapshot.
        parts: ``(name, efforts)`` of every attachment that contributed.
        wrenches: The tick's requested wrenches.
        produced: The tick's produced wrenches (updated).
        solutions: The tick's solutions (updated).
        failures: The tick's failure records (updated).
        failed: The tick's attachments left at zero (updated).

    Returns:
        The ``(nv,)`` efforts.

    Raises:
        InvalidInputError: With ``on_failure="raise"``, naming the first such attachment.
    """
    tau = np.zeros(controller.robot.model.nv)
    limits = (-controller.effort_limits, controller.effort_limits)
    for name, effort in parts:
        if np.isfinite(effort).all():
            tau += effort
            continue
        error = InvalidInputError(
            f"Attachment {name!r}: non-finite joint efforts from the finite wrench "
            f"{wrenches[name].tolist()} (too large for float64)."
        )
        if controller.on_failure == "raise":
            raise error
        solutions.pop(name, None)
        produced.pop(name, None)
        attachment = controller.attachments[name]
        solution, effort = recover(
            controller.on_failure,
            attachment,
            snapshot,
            wrenches[name],
            "effort",
            error,
            limits,
            failures,
            failed,
        )
        if effort is not None:  # a fallback's efforts are finite
            solutions[name], produced[name] = solution, solution.wrench
            tau += effort
    return tau


__all__ = [
    "CAUGHT",
    "FAILURE_POLICIES",
    "AttachmentFailure",
    "check_policy",
    "drop_non_finite",
    "reason_of",
    "recover",
]
