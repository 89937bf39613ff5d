"""The yield policy of a parallel attachment's contact limits (unilateral minima, cones)."""

from __future__ import annotations

import dataclasses

import numpy as np

from ..core import CORE, has
from ..distribution.result import Solution, label
from ..kinematics.snapshot import Snapshot
from .attachment import Attachment


def least_margin(attachment: Attachment, snapshot: Snapshot, forces: np.ndarray) -> float | None:
    """Smallest margin ``G @ forces.ravel() - lows`` of the attachment's contact rows.

    One compiled call, or None (no core, sole rows, or frames the table lacks).
    """
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
    """The largest ``alpha`` in ``[0, 1]`` for which the shares meet the contact rows.

    The shares are ``base + alpha (full - base)``; 0 when no ``alpha`` meets them.
    """
    frames = _frame_table(attachment, snapshot)
    if frames is None:
        rows, lows = constraint_rows(attachment, snapshot)
        return ratio_test(rows @ full.ravel(), rows @ base.ravel(), lows)
    rows = attachment.actuator.kinematics.orientation_rows
    return CORE.contact_largest_scale(frames, rows, full, base, *attachment.margins)


def ratio_test(at_full: np.ndarray, at_base: np.ndarray, lows: np.ndarray) -> float:
    """The largest ``alpha`` in ``[0, 1]`` with ``at_base + alpha (at_full - at_base) >= lows``.

    0 when no ``alpha`` meets them all.
    """
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
    if margin is None:  # no compiled conditions: the rows, once
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
    forces = start.forces + alpha * (end.forces - start.forces)
    produced = start.wrench + alpha * (end.wrench - start.wrench)
    requested = start.requested + alpha * (end.requested - start.requested)
    residual = float(np.linalg.norm(produced - requested))
    limit = start.tolerance + alpha * (end.tolerance - start.tolerance)
    return dataclasses.replace(
        end,
        tau=start.tau + alpha * (end.tau - start.tau),
        forces=forces,
        wrench=produced,
        residual=residual,
        method=label(end.method, residual <= limit),
        requested=requested,
        base_effort=start.base_effort + alpha * (end.base_effort - start.base_effort),
        compiled=start.compiled and end.compiled,
        tolerance=limit,
    )
