"""One attachment's share of a tick (`run_attachment`), its failure policy (``on_failure``).

The yield policy of a parallel attachment's contact limits (unilateral minima, cones) is here too.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..actuators import VirtualActuator
from ..core import CORE, has
from ..distribution.result import Solution, label
from ..exceptions import (
    ConstraintError,
    InadmissibleWrenchError,
    InvalidInputError,
    SingularConfigurationError,
    VirtualActuatorError,
)
from ..kinematics.snapshot import Snapshot
from .attachment import Attachment
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
    attachment: Attachment,
    snapshot: Snapshot,
    time: float,
    sums: TickSums,
    on_failure: str,
    limits: np.ndarray,
) -> None:
    """Sense, sum the components, map to efforts (or recover from a failure) into ``sums``.

    ``limits`` are the controller's effort limits (for ``"fallback"``).

    Raises:
        VirtualActuatorError: With ``on_failure="raise"``, the attachment's failure.
    """
    name, spring, wrench, solution = attachment.name, attachment.spring_tick, None, None
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
        reason = "wrench" if wrench is None else next(  # no wrench: the components failed
            (why for kind, why in _REASONS if isinstance(error, kind)), "distribution"
        )
        solution, effort = recover(
            on_failure, attachment, snapshot, wrench, reason, error, limits, sums
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


def recover(
    policy: str,
    attachment: Attachment,
    snapshot: Snapshot,
    wrench: np.ndarray | None,
    reason: str,
    error: BaseException,
    limits: np.ndarray,
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
                    tau = np.minimum(np.maximum(solution.tau, -limits), limits)
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
    tau, limits = np.zeros(controller.robot.model.nv), controller.effort_limits
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


def least_margin(attachment: Attachment, snapshot: Snapshot, forces: np.ndarray) -> float | None:
    """Smallest margin ``G @ forces.ravel() - lows`` of the contact rows (compiled), or None."""
    frames = _frame_table(attachment, snapshot)
    if frames is None:
        return None
    rows = attachment.actuator.kinematics.orientation_rows
    return CORE.contact_least_margin(frames, rows, forces, *attachment.margins)


def _frame_table(attachment: Attachment, snapshot: Snapshot) -> np.ndarray | None:
    """The snapshot's frame table if the compiled margins can read it, else None."""
    frames = snapshot.frame_table
    kinematics = attachment.actuator.kinematics
    if (
        not has("contact_least_margin")
        or attachment.margins is None
        or frames.shape[0] < kinematics.orientation_rows_end
    ):
        return None
    return frames


def constraint_rows(attachment: Attachment, snapshot: Snapshot) -> tuple[np.ndarray, np.ndarray]:
    """``(G, lows)``: the attachment's contact rows ``G @ forces.ravel() >= lows``.

    ``unilateral`` gives one row per chain and axis; a friction cone the faces
    ``mu n.f -+ t.f >= 0`` of a pyramid about the contact normal and ``n.f >= min_normal``.
    """
    rotation_o, rotations = attachment.actuator.kinematics.rotations(snapshot)
    rows = attachment.contacts.rows(rotation_o, rotations)
    return rows.G, rows.lows


def largest_scale(
    attachment: Attachment, snapshot: Snapshot, full: np.ndarray, base: np.ndarray
) -> float:
    """The largest ``alpha`` in ``[0, 1]`` (or 0) with ``base + alpha (full - base)`` feasible."""
    frames = _frame_table(attachment, snapshot)
    if frames is None:
        rows, lows = constraint_rows(attachment, snapshot)
        return ratio_test(rows @ full.ravel(), rows @ base.ravel(), lows)
    rows = attachment.actuator.kinematics.orientation_rows
    return CORE.contact_largest_scale(frames, rows, full, base, *attachment.margins)


def ratio_test(at_full: np.ndarray, at_base: np.ndarray, lows: np.ndarray) -> float:
    """The largest alpha in [0, 1] (or 0) with ``at_base + alpha (at_full - at_base) >= lows``."""
    slope = at_full - at_base
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = (lows - at_base) / slope
    upper = np.where(slope < 0.0, ratio, np.inf).min(initial=1.0)
    lower = np.where(slope > 0.0, ratio, -np.inf).max(initial=0.0)
    stuck = np.any((slope == 0.0) & (at_base < lows))  # no alpha helps that condition
    return 0.0 if stuck or lower > upper else float(min(upper, 1.0))


def enforce_unilateral(
    attachment: Attachment, q: Snapshot, wrench: np.ndarray, solution: Solution
) -> Solution:
    """Scale the request on the yield axes until every chain's share is feasible.

    The distribution is affine in the wrench, so one extra solve of ``base`` (the request
    without its yield axes) and a ratio test find the largest feasible ``alpha`` in ``[0, 1]``.
    """
    margin = least_margin(attachment, q, solution.forces)
    if margin is not None and margin >= -1e-9:  # the usual tick: nothing to scale
        return solution
    if margin is None:  # no compiled conditions: the rows in numpy, built once
        rows, lows = constraint_rows(attachment, q)
        at_full = rows @ solution.forces.ravel()
        if np.all(at_full >= lows - 1e-9):
            return solution
    base = np.where(attachment.yield_mask, 0.0, wrench)
    request = dataclasses.replace(attachment.plan, weights=None)  # the declaration's weights
    fallback = attachment.actuator.solve_checked(q, base, request)[0]
    if margin is None:
        alpha = ratio_test(at_full, rows @ fallback.forces.ravel(), lows)
    else:
        alpha = largest_scale(attachment, q, solution.forces, fallback.forces)
    if alpha <= 0.0:
        return fallback
    return interpolate(fallback, solution, alpha)


def interpolate(start: Solution, end: Solution, alpha: float) -> Solution:
    """The solution of the request ``start + alpha (end - start)`` of one actuator.

    Exact for distributions affine in the request (every method but ``"qp"``); the residual is
    that of the interpolated request, labelled by ``Solution.admissible``'s rule.
    """
    mixed = {
        field: getattr(start, field) + alpha * (getattr(end, field) - getattr(start, field))
        for field in ("tau", "forces", "wrench", "requested", "base_effort", "tolerance")
    }
    residual = float(np.linalg.norm(mixed["wrench"] - mixed["requested"]))
    return dataclasses.replace(
        end,
        **mixed,
        residual=residual,
        method=label(end.method, residual <= mixed["tolerance"]),
        compiled=start.compiled and end.compiled,
    )
