"""Contact limits of a parallel attachment: unilateral minima and friction pyramids.

The distribution is linear in the wrench, so a request that would make a chain pull or slip is
scaled down on the attachment's yield axes by one extra solve and a ratio test
(:func:`enforce_unilateral`), against the linear conditions of :func:`constraint_rows`; the
compiled kernels evaluate those conditions from the snapshot's frame table without building
the rows.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..distribution.result import Solution, label
from ..kinematics.kernels import HAVE_NUMBA, njit
from ..kinematics.snapshot import Snapshot
from .attachment import Attachment


@njit(cache=True)
def _row_values(
    frames: np.ndarray,
    orientation_rows: np.ndarray,
    forces: np.ndarray,
    pyramid: np.ndarray,
    force_columns: np.ndarray,
    force_components: np.ndarray,
    bound_rows: np.ndarray,
    cones: bool,
    out: np.ndarray,
) -> None:
    """``rows @ forces.ravel()`` of :func:`constraint_rows` into ``out``, without the rows.

    ``frames`` is the snapshot's frame table, ``orientation_rows`` the rows of {O} then of each
    reaction frame; the cone rows are ``pyramid @ (R_O^T R_A)[force_components].T`` per chain.
    """
    p, n = forces.shape
    bound = bound_rows.shape[0]
    for r in range(bound):
        total = 0.0
        for j in range(p * n):
            total += bound_rows[r, j] * forces[j // n, j % n]
        out[r] = total
    if not cones:
        return
    o = orientation_rows[0]
    for c in range(p):
        a = orientation_rows[1 + c]
        for k in range(5):
            total = 0.0
            for i in range(force_columns.shape[0]):
                row = force_components[i]
                vector = 0.0
                for axis in range(3):
                    entry = 0.0  # (R_O^T R_A)[row, axis]
                    for m in range(3):
                        entry += frames[o, 3 * m + row] * frames[a, 3 * m + axis]
                    vector += pyramid[k, axis] * entry
                total += vector * forces[c, force_columns[i]]
            out[bound + 5 * c + k] = total


@njit(cache=True)
def _least_margin(
    frames: np.ndarray,
    orientation_rows: np.ndarray,
    forces: np.ndarray,
    pyramid: np.ndarray,
    force_columns: np.ndarray,
    force_components: np.ndarray,
    bound_rows: np.ndarray,
    lows: np.ndarray,
    cones: bool,
) -> float:
    """Smallest ``rows @ forces.ravel() - lows`` of :func:`constraint_rows`."""
    values = np.empty(lows.shape[0])
    _row_values(
        frames, orientation_rows, forces, pyramid, force_columns, force_components, bound_rows,
        cones, values,
    )  # fmt: skip
    worst = np.inf
    for r in range(lows.shape[0]):
        worst = min(worst, values[r] - lows[r])
    return worst


@njit(cache=True)
def _largest_scale(
    frames: np.ndarray,
    orientation_rows: np.ndarray,
    full: np.ndarray,
    base: np.ndarray,
    pyramid: np.ndarray,
    force_columns: np.ndarray,
    force_components: np.ndarray,
    bound_rows: np.ndarray,
    lows: np.ndarray,
    cones: bool,
) -> float:
    """The ratio test of :func:`enforce_unilateral` on the shares ``base`` and ``full``.

    The largest ``alpha`` in ``[0, 1]`` with ``rows @ (base + alpha (full - base)) >= lows``
    on every row, 0 when none is (see :func:`ratio_test`, its numpy twin).
    """
    count = lows.shape[0]
    at_full, at_base = np.empty(count), np.empty(count)
    tables = (pyramid, force_columns, force_components, bound_rows, cones)
    _row_values(frames, orientation_rows, full, *tables, at_full)
    _row_values(frames, orientation_rows, base, *tables, at_base)
    upper, lower = 1.0, 0.0
    for r in range(count):
        slope = at_full[r] - at_base[r]
        if slope == 0.0:
            if at_base[r] < lows[r]:
                return 0.0  # no alpha helps that condition
            continue
        ratio = (lows[r] - at_base[r]) / slope
        if slope < 0.0:
            upper = min(upper, ratio)
        else:
            lower = max(lower, ratio)
    return 0.0 if lower > upper else min(upper, 1.0)


def least_margin(attachment: Attachment, snapshot: Snapshot, forces: np.ndarray) -> float | None:
    """Smallest margin of the chains' shares ``forces`` over :func:`constraint_rows`' conditions.

    One compiled call (None when numba is missing or the snapshot's frame table lacks a frame
    the conditions read: then build the rows).
    """
    frames = _frame_table(attachment, snapshot)
    if frames is None:
        return None
    rows = attachment.actuator.kinematics.orientation_rows
    return _least_margin(frames, rows, forces, *attachment.limit_tables)


def _frame_table(attachment: Attachment, snapshot: Snapshot) -> np.ndarray | None:
    """The snapshot's frame table if the compiled conditions can read it, else None."""
    frames = snapshot.frame_table
    if not HAVE_NUMBA or frames.shape[0] < attachment.actuator.kinematics.orientation_rows_end:
        return None
    return frames


def constraint_rows(attachment: Attachment, snapshot: Snapshot) -> tuple[np.ndarray, np.ndarray]:
    """Linear conditions ``rows @ forces.ravel() >= lows`` on the chains' shares.

    ``unilateral`` gives one row per chain and axis (built at declaration); a friction
    cone gives, per chain, the normal force (the reaction frame's z in {O}) ``>=
    min_normal`` and ``mu n.f -+ t.f >= 0`` for both tangents (a pyramid; a tangent outside
    the actuator's force axes gives a row implied by the normal one). The reaction frames'
    orientations are read from the tick's snapshot.
    """
    if attachment.friction is None:
        return attachment.bound_rows, attachment.bound_lows
    rotation_o, rotations = attachment.actuator.kinematics.rotations(snapshot)
    # reaction frames' axes (columns t1, t2, n) in {O}, on the actuator's force axes: (p, m, 3)
    frames_o = (rotation_o.T @ rotations)[:, attachment.force_components, :]
    vectors = attachment.pyramid @ frames_o.transpose(0, 2, 1)  # (p, 5, m)
    rows = attachment.cone_template.copy()
    rows.flat[attachment.cone_index] = vectors.ravel()
    return rows, attachment.cone_lows


def largest_scale(
    attachment: Attachment, snapshot: Snapshot, full: np.ndarray, base: np.ndarray
) -> float:
    """The largest ``alpha`` in ``[0, 1]`` for which the shares meet the contact conditions.

    The shares are ``base + alpha (full - base)``, the conditions :func:`constraint_rows`'; 0
    when no ``alpha`` meets them. One compiled call when the snapshot's frame table holds the
    frames the conditions read; else the rows are built and :func:`ratio_test` answers.
    """
    frames = _frame_table(attachment, snapshot)
    if frames is None:
        rows, lows = constraint_rows(attachment, snapshot)
        return ratio_test(rows @ full.ravel(), rows @ base.ravel(), lows)
    rows = attachment.actuator.kinematics.orientation_rows
    return _largest_scale(frames, rows, full, base, *attachment.limit_tables)


def ratio_test(at_full: np.ndarray, at_base: np.ndarray, lows: np.ndarray) -> float:
    """The largest ``alpha`` in ``[0, 1]`` with ``at_base + alpha (at_full - at_base) >= lows``.

    The conditions' values at the full request and at its base (no yield axes); 0 when no
    ``alpha`` meets them all.
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

    Feasible: ``unilateral`` minima and the friction cone (see ``Controller.add``). The
    distribution is affine in the wrench (linear, plus what passive springs contribute), so
    the solution at ``base + alpha (wrench - base)``, ``base`` the request without its yield
    axes, is ``base``'s solution plus ``alpha`` times the difference: one extra solve and a
    ratio test find the largest feasible ``alpha`` in ``[0, 1]``, and the two solutions give
    the answer (:func:`interpolate`).
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

    Exact for distributions affine in the request (every method but ``"qp"``): forces,
    efforts, produced and requested wrenches are interpolated; the residual is that of the
    interpolated request (``requested`` equals ``wrench`` on free axes), its tolerance the
    interpolated tolerance (the residual is at most the interpolation of the two), and the method
    the end's, labelled by the one admissibility rule (``Solution.admissible``).
    """
    forces = start.forces + alpha * (end.forces - start.forces)
    produced = start.wrench + alpha * (end.wrench - start.wrench)
    requested = start.requested + alpha * (end.requested - start.requested)
    residual = float(np.linalg.norm(produced - requested))
    limit = start.tolerance + alpha * (end.tolerance - start.tolerance)
    return Solution(  # positional (a tick's cost): the fields in declaration order
        start.tau + alpha * (end.tau - start.tau),
        forces,
        produced,
        end.sets,
        residual,
        label(end.method, residual <= limit),
        requested,
        end.reactions,
        end.axes,
        end.free,
        end.tau_passive,
        start.base_effort + alpha * (end.base_effort - start.base_effort),
        end.solver,
        end.systems,
        start.compiled and end.compiled,
        end.active,
        limit,
    )


__all__ = [
    "constraint_rows",
    "enforce_unilateral",
    "interpolate",
    "largest_scale",
    "least_margin",
    "ratio_test",
]
