"""Contact limits of a parallel attachment: unilateral minima and friction pyramids.

The distribution is linear in the wrench, so a request that would make a chain pull or slip is
scaled down on the attachment's yield axes by one extra solve and a ratio test
(:func:`enforce_unilateral`), against the linear conditions of :func:`constraint_rows`.
"""

from __future__ import annotations

import numpy as np

from ..distribution.solution import Solution
from ..kinematics.kernels import HAVE_NUMBA, njit
from ..kinematics.snapshot import Snapshot
from .attachment import Attachment


@njit(cache=True)
def _least_margin(
    frames: np.ndarray,
    orientation_rows: np.ndarray,
    pyramid: np.ndarray,
    force_columns: np.ndarray,
    force_components: np.ndarray,
    forces: np.ndarray,
    bound_rows: np.ndarray,
    lows: np.ndarray,
    cones: bool,
) -> float:
    """Smallest ``rows @ forces.ravel() - lows`` of :func:`constraint_rows`, without the rows.

    ``frames`` is the snapshot's frame table, ``orientation_rows`` the rows of {O} then of each
    reaction frame; the cone rows are ``pyramid @ (R_O^T R_A)[force_components].T`` per chain.
    """
    p, n = forces.shape
    worst = np.inf
    bound = bound_rows.shape[0]
    for r in range(bound):
        total = 0.0
        for j in range(p * n):
            total += bound_rows[r, j] * forces[j // n, j % n]
        worst = min(worst, total - lows[r])
    if not cones:
        return worst
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
            worst = min(worst, total - lows[bound + 5 * c + k])
    return worst


def least_margin(attachment: Attachment, snapshot: Snapshot, forces: np.ndarray) -> float | None:
    """Smallest margin of the chains' shares ``forces`` over :func:`constraint_rows`' conditions.

    One compiled call (None when numba is missing or the snapshot's frame table lacks a frame
    the conditions read: then build the rows).
    """
    kinematics = attachment.actuator.kinematics
    frames = snapshot.frame_table
    rows = kinematics.orientation_rows
    if not HAVE_NUMBA or frames.shape[0] < kinematics.orientation_rows_end:
        return None
    cones = attachment.friction is not None
    return _least_margin(
        frames,
        rows,
        attachment.pyramid if cones else _NO_PYRAMID,
        attachment.force_columns,
        attachment.force_components,
        forces,
        attachment.bound_rows,
        attachment.cone_lows if cones else attachment.bound_lows,
        cones,
    )


_NO_PYRAMID = np.zeros((5, 3))


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


def enforce_unilateral(
    attachment: Attachment, q: Snapshot, wrench: np.ndarray, solution: Solution
) -> Solution:
    """Scale the request on the yield axes until every chain's share is feasible.

    Feasible: ``unilateral`` minima and the friction cone (see ``Controller.add``). The
    distribution is linear in the wrench, so the shares are ``base + alpha (full - base)``
    with ``base`` the request without its yield axes: the largest feasible ``alpha`` in
    ``[0, 1]`` comes from one extra solve and a ratio test.
    """
    margin = least_margin(attachment, q, solution.forces)
    if margin is not None and margin >= -1e-9:  # the usual tick: nothing to scale
        return solution
    rows, lows = constraint_rows(attachment, q)
    full = rows @ solution.forces.ravel()
    if np.all(full >= lows - 1e-9):
        return solution
    base = np.where(attachment.yield_mask, 0.0, wrench)
    fallback = attachment.actuator.solve(q, base, free=attachment.free)
    start = rows @ fallback.forces.ravel()
    slope = full - start
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = (lows - start) / slope
    upper = np.where(slope < 0.0, ratio, np.inf).min(initial=1.0)
    lower = np.where(slope > 0.0, ratio, -np.inf).max(initial=0.0)
    stuck = np.any((slope == 0.0) & (start < lows))  # no alpha helps that condition
    alpha = 0.0 if stuck or lower > upper else float(min(upper, 1.0))
    if alpha <= 0.0:
        return fallback
    return attachment.actuator.solve(
        q, np.where(attachment.yield_mask, alpha * wrench, wrench), free=attachment.free
    )


__all__ = ["constraint_rows", "enforce_unilateral"]
