"""One attachment's share of a tick (`run_attachment`) and its failure policy (``on_failure``)."""

from __future__ import annotations

import numpy as np

from ..actuators import VirtualActuator
from ..exceptions import (
    ConstraintError,
    InadmissibleWrenchError,
    InvalidInputError,
    SingularConfigurationError,
    VirtualActuatorError,
)
from ..kinematics.snapshot import Snapshot
from .attachment import Attachment
from .contact_limits import enforce_unilateral
from .tick import AttachmentFailure, TickSums

#: The values of ``Controller(on_failure=...)``.
FAILURE_POLICIES = ("raise", "skip", "fallback")

#: What a policy catches; other exceptions (a TypeError from a bug) always propagate.
CAUGHT = (VirtualActuatorError, ArithmeticError)
_REASONS = (
    (SingularConfigurationError, "singular"),
    (InadmissibleWrenchError, "inadmissible"),
    (ConstraintError, "constraint"),
)


def run_attachment(
    name: str,
    attachment: Attachment,
    snapshot: Snapshot,
    time: float,
    sums: TickSums,
    on_failure: str,
    limits: tuple[np.ndarray, np.ndarray],
) -> None:
    """Sense, sum the components, map to efforts (or recover from a failure) into ``sums``.

    ``limits`` are the controller's ``(lower, upper)`` effort limits (for ``"fallback"``).

    Raises:
        VirtualActuatorError: With ``on_failure="raise"``, the attachment's failure.
    """
    spring, wrench, solution = attachment.spring_tick, None, None
    try:
        if spring is not None:  # and a parallel actuator's distribution, in one call
            buffer, solution = spring.run_solve(attachment.components, snapshot, time)
        else:
            buffer = None
        if buffer is not None:  # spring-dampers: sensing and wrench in one compiled call
            at_position, at_velocity, at_wrench, at_efforts = spring.slices
            sums.positions[name] = buffer[at_position]
            sums.velocities[name] = buffer[at_velocity]
            wrench = sums.wrenches[name] = buffer[at_wrench]
            if at_efforts is not None:  # and a serial actuator's efforts
                sums.produced[name] = wrench
                sums.add(name, buffer[at_efforts], fresh=True)
                return
        else:
            sensor = attachment.sensor
            jacobian, position, velocity = sensor.kinematics.sense(snapshot, velocity=True)
            sums.positions[name], sums.velocities[name] = position, velocity
            wrench = attachment.wrench(position, velocity, time)
            sums.wrenches[name] = wrench
        one_call = attachment.snapshot_solve  # a parallel actuator's compiled solve
        if solution is None and one_call is not None:
            solution = one_call(snapshot, wrench)
        if solution is None:
            actuator = attachment.actuator
            if isinstance(actuator, VirtualActuator):
                jacobian_act = jacobian if actuator is sensor else actuator.jacobian(snapshot)
                sums.add(name, jacobian_act.T @ wrench, fresh=True)
                sums.produced[name] = wrench
                return
            # free axes, method and weights checked at add(); the wrench by Attachment.wrench
            solution = actuator.solve_checked(snapshot, wrench, attachment.plan)[0]
        if attachment.yield_mask is not None:
            solution = enforce_unilateral(attachment, snapshot, wrench, solution)
    except CAUGHT as error:
        if on_failure == "raise":
            raise
        solution, effort = recover(
            on_failure, attachment, snapshot, wrench, reason_of(error, wrench), error, limits, sums
        )
        if effort is None:
            return
    else:
        effort = solution.tau
    sums.solutions[name], sums.produced[name] = solution, solution.wrench
    sums.add(name, effort, fresh=False)


def check_policy(on_failure: object, on_singular: object) -> str:
    """The controller's policy: ``on_failure``, else ``on_singular``, else ``"raise"``.

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
    return next((reason for kind, reason in _REASONS if isinstance(error, kind)), "distribution")


def recover(
    policy: str,
    attachment: Attachment,
    snapshot: Snapshot,
    wrench: np.ndarray | None,
    reason: str,
    error: BaseException,
    limits: tuple[np.ndarray, np.ndarray],
    sums: TickSums,
) -> tuple[object | None, np.ndarray | None]:
    """Apply ``policy`` (``"skip"`` or ``"fallback"``) to one attachment's failure.

    ``wrench`` is None when the components failed; ``sums.failures`` and ``sums.failed`` are
    updated.

    Returns:
        ``(solution, tau)``: with a working fallback, its [`Solution`][] (unclipped) and its
        clipped, finite ``(nv,)`` efforts; else ``(None, None)``.
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
                    sums.failures[name] = AttachmentFailure(reason, error_name, message, "fallback")
                    return solution, tau
                why = "fallback failed: non-finite efforts"
            except CAUGHT as fallback_error:
                why = f"fallback failed: {type(fallback_error).__name__}: {fallback_error}"
    sums.failures[name] = AttachmentFailure(reason, error_name, message, "skip", why)
    sums.failed[name] = message
    return None, None


def drop_non_finite(controller: object, snapshot: Snapshot, sums: TickSums) -> np.ndarray:
    """A tick's efforts again, the policy applied to the attachments with non-finite ones.

    Called when the sum is not finite (a finite wrench too large for float64); the tick's
    ``sums`` are updated.

    Raises:
        InvalidInputError: With ``on_failure="raise"``, naming the first such attachment.
    """
    tau = np.zeros(controller.robot.model.nv)
    limits = (-controller.effort_limits, controller.effort_limits)
    wrenches, produced, solutions = sums.wrenches, sums.produced, sums.solutions
    policy = controller.on_failure
    for name, effort in sums.parts:
        if np.isfinite(effort).all():
            tau += effort
            continue
        error = InvalidInputError(
            f"Attachment {name!r}: non-finite joint efforts from the finite wrench "
            f"{wrenches[name].tolist()} (too large for float64)."
        )
        if policy == "raise":
            raise error
        solutions.pop(name, None)
        produced.pop(name, None)
        attachment = controller.attachments[name]
        solution, effort = recover(
            policy, attachment, snapshot, wrenches[name], "effort", error, limits, sums
        )
        if effort is not None:  # a fallback's efforts are finite
            solutions[name], produced[name] = solution, solution.wrench
            tau += effort
    return tau
