"""The projectors of many chains of full column rank side by side (mode 0 of the compiled solve).

`full_rank_batch` runs one unpivoted QR per chain, the chains of one shape interleaved so
that the loops run over them innermost.
"""

from __future__ import annotations

import numpy as np

from ...kinematics.kernels import njit
from ..tolerances import JACOBIAN_FLOOR

#: Fewest chains for which mode 0 runs the chains of full column rank side by side
#: (:func:`full_rank_batch`); with fewer, its fixed cost outweighs what it saves.
BATCH_CHAINS = 8


@njit(cache=True, error_model="numpy")
def full_rank_batch(
    q: np.ndarray,
    c: int,
    m_c: int,
    t: np.ndarray,
    ratio: np.ndarray,
    bound: np.ndarray,
    proj: np.ndarray,
    part: np.ndarray,
    null: np.ndarray,
) -> None:
    """Mode 0 for ``B`` chains of one shape whose ``full`` (n x c) has full column rank.

    ``q`` (>= c, n, B) holds each chain's ``c`` columns, the ``m_c`` constraint columns (own
    constrained joints, then ball axes) first, then the free joints; the chains run side by side
    (last axis) so every loop is over independent chains. Modified Gram-Schmidt gives ``full P =
    Q R`` (``q[:c]`` is overwritten with ``Q^T``), and

    - ``proj`` (n, n, B): the projector ``Q_F Q_F^T`` onto the forces the rows allow (``G F =
      0``, ``G`` the constraint columns and the left null space of ``full``);
    - ``part`` (n, B): the least-norm solution ``Q_C R_CC^-T t`` of the constraint rows
      (right-hand sides ``t`` (m_c, B));
    - ``null`` (n - c, n, B): the left null space (rows kept for the constraint check), ``Q``
      completed by the unit vectors of largest residual;
    - ``ratio`` (B,): a lower bound of the rank-revealing ratio of `null_rows`
      (``sigma_min >= 1 / ||R^-1||_F`` over its first pivot, the largest column norm; 0 for a
      pivot under `JACOBIAN_FLOOR` or a non-finite value);
    - ``bound`` (B,): an upper bound of the condition estimate of the rows' Gram matrix that
      `minimum_norm` compares with `ILL_CONDITIONED` (``l max(||C||_F^2, 1)
      max(||R_CC^-1||_F^2, 1)``, the 1 only with null rows).

    Both bounds err on the side of handing the tick to the numpy path.
    """
    n, count = q.shape[1], q.shape[2]
    first2 = np.zeros(count)
    c_fro = np.zeros(count)
    acc = np.empty(count)
    bad = np.zeros(count, dtype=np.bool_)
    rr = np.empty((c, c, count))
    x = np.empty((c, c, count))
    for j in range(c):
        acc[:] = 0.0
        for r in range(n):
            for i in range(count):
                acc[i] += q[j, r, i] * q[j, r, i]
        for i in range(count):
            first2[i] = max(first2[i], acc[i])
            if j < m_c:
                c_fro[i] += acc[i]
    for j in range(c):
        for b in range(j):
            acc[:] = 0.0
            for r in range(n):
                for i in range(count):
                    acc[i] += q[b, r, i] * q[j, r, i]
            for i in range(count):
                rr[b, j, i] = acc[i]
            for r in range(n):
                for i in range(count):
                    q[j, r, i] -= acc[i] * q[b, r, i]
        acc[:] = 0.0
        for r in range(n):
            for i in range(count):
                acc[i] += q[j, r, i] * q[j, r, i]
        for i in range(count):
            norm = np.sqrt(acc[i])
            rr[j, j, i] = norm
            bad[i] |= not norm > JACOBIAN_FLOOR
            acc[i] = 1.0 / norm
        for r in range(n):
            for i in range(count):
                q[j, r, i] *= acc[i]
    inv_fro = np.zeros(count)
    inv_c = np.zeros(count)
    for j in range(c):  # X = R^-1, column by column
        for i in range(count):
            x[j, j, i] = 1.0 / rr[j, j, i]
        for row in range(j - 1, -1, -1):
            acc[:] = 0.0
            for k in range(row + 1, j + 1):
                for i in range(count):
                    acc[i] += rr[row, k, i] * x[k, j, i]
            for i in range(count):
                x[row, j, i] = -acc[i] / rr[row, row, i]
        for row in range(j + 1):
            for i in range(count):
                inv_fro[i] += x[row, j, i] * x[row, j, i]
                if j < m_c:
                    inv_c[i] += x[row, j, i] * x[row, j, i]
    l_rows = m_c + n - c
    for i in range(count):
        sigma = 1.0 / np.sqrt(inv_fro[i])
        value = sigma / np.sqrt(first2[i])
        if bad[i] or not sigma > JACOBIAN_FLOOR or not np.isfinite(value):
            value = 0.0
        ratio[i] = value
        estimate = 0.0
        if l_rows > 0:
            big, small = c_fro[i], inv_c[i]
            if n > c:
                big, small = max(big, 1.0), max(small, 1.0)
            estimate = l_rows * big * small
            if not estimate < np.inf:
                estimate = np.inf
        bound[i] = estimate
    for r in range(n):
        for a in range(r, n):
            acc[:] = 0.0
            for j in range(m_c, c):
                for i in range(count):
                    acc[i] += q[j, r, i] * q[j, a, i]
            for i in range(count):
                proj[r, a, i] = acc[i]
                proj[a, r, i] = acc[i]
    part[:, :] = 0.0
    for j in range(m_c):
        acc[:] = 0.0
        for k in range(j + 1):
            for i in range(count):
                acc[i] += x[k, j, i] * t[k, i]
        for a in range(n):
            for i in range(count):
                part[a, i] += acc[i] * q[j, a, i]
    if c < n:  # left null space: complete Q with the unit vectors of largest residual
        rows2 = np.zeros((n, count))  # squared row norms of the basis so far
        for j in range(c):
            for e in range(n):
                for i in range(count):
                    rows2[e, i] += q[j, e, i] * q[j, e, i]
        best = np.empty(count, dtype=np.int64)
        best_sum = np.empty(count)
        coef = np.empty((c + n, count))
        for step in range(n - c):
            best[:] = 0
            best_sum[:] = np.inf
            for e in range(n):
                for i in range(count):
                    if rows2[e, i] < best_sum[i]:
                        best[i], best_sum[i] = e, rows2[e, i]
            for i in range(count):
                e = best[i]
                for j in range(c):
                    coef[j, i] = q[j, e, i]
                for b in range(step):
                    coef[c + b, i] = null[b, e, i]
            for a in range(n):
                for i in range(count):
                    null[step, a, i] = 1.0 if a == best[i] else 0.0
                for j in range(c):
                    for i in range(count):
                        null[step, a, i] -= coef[j, i] * q[j, a, i]
                for b in range(step):
                    for i in range(count):
                        null[step, a, i] -= coef[c + b, i] * null[b, a, i]
            acc[:] = 0.0
            for a in range(n):
                for i in range(count):
                    acc[i] += null[step, a, i] * null[step, a, i]
            for i in range(count):
                acc[i] = 1.0 / np.sqrt(acc[i])
            for a in range(n):
                for i in range(count):
                    null[step, a, i] *= acc[i]
                    rows2[a, i] += null[step, a, i] * null[step, a, i]


__all__ = ["BATCH_CHAINS", "full_rank_batch"]
