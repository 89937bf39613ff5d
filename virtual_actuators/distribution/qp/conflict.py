"""Inequalities of the QP that cannot hold together, named.

The least squared shift of the bounds that lets the rows hold with the equalities,
``min |s|^2`` over ``(x, s)`` subject to ``E x = e``, ``lows <= C x + s <= uppers``, is 0 when
they are consistent, else a Farkas certificate: the rows it moves cannot hold together.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ...exceptions import ConstraintError
from ..tolerances import CONFLICT_SHARE

#: The check gets at most this many ProxQP iterations (charged to the solve's budget), and runs
#: only when at least twice as many are left.
CONFLICT_MAX_ITER = 40


def least_shift_problem(
    equality: np.ndarray, inequality: np.ndarray
) -> tuple[tuple[np.ndarray, np.ndarray], np.ndarray, np.ndarray]:
    """The check's QP over ``(x, s)``: ``((hessian, gradient), equality rows, inequality rows)``."""
    size, m = equality.shape[1], inequality.shape[0]
    hessian = np.zeros((size + m, size + m))
    hessian[size:, size:] = np.eye(m)
    shifted_equality = np.hstack((equality, np.zeros((equality.shape[0], m))))
    shifted_inequality = np.hstack((inequality, np.eye(m)))
    return (hessian, np.zeros(size + m)), shifted_equality, shifted_inequality


def conflict_error(
    shift: np.ndarray, names: Sequence[str], reactions: Sequence[str], tolerance: float
) -> ConstraintError | None:
    """The error naming the rows that the optimal ``shift`` moves, or None if it is ~0.

    Args:
        shift: ``(m,)`` the check's optimal shift of each inequality (scaled).
        names: The inequality rows' names.
        reactions: The actuator's reaction frames (for the message).
        tolerance: A largest shift at or below this means the rows are consistent.
    """
    size = np.abs(shift)
    largest = float(size.max(initial=0.0))
    if not largest > tolerance:
        return None
    moved = np.flatnonzero(size >= CONFLICT_SHARE * largest)
    rank = np.round(size[moved] / largest, 6)  # equal shifts (a symmetric robot): row order
    rows = [names[i] for i in moved[np.argsort(-rank, kind="stable")]]
    return ConstraintError(
        f"No distribution over the chains to {list(reactions)} meets every constraint at this "
        "configuration, whatever the request: these inequalities cannot hold together with the "
        f"natural and design equalities (furthest off first; relax one of them): "
        f"{'; '.join(rows)}."
    )


__all__ = ["CONFLICT_MAX_ITER", "conflict_error", "least_shift_problem"]
