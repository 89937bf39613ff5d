"""The two compiled solves of the distribution, on the rows :func:`.kernels.distribute` built.

- :func:`minimum_norm` (mode 0): the least ``sum ||F_i||^2`` through the ``(k + s)`` KKT system
  of the chains' projectors; :func:`full_rank_batch` computes the projectors of many chains of
  full column rank side by side (one unpivoted QR each);
- :func:`partitioned_solve` (mode 1): the Partitioned Actuator Set method with the declaration's
  sets.
"""

from __future__ import annotations

import numpy as np

from ...kinematics.kernels import njit
from ..linalg import JACOBIAN_FLOOR
from .kernel_linalg import ILL_CONDITIONED, inverse_into, invert, mm, mv, scaled_condition

# columns of the per-chain integer table
K_COLS, C_CON, NB_BALL, RANK, L_ROWS, D_FREE, START = 0, 1, 2, 3, 4, 5, 6
HEADER = 7
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
    - ``ratio`` (B,): a lower bound of the rank-revealing ratio of :func:`null_rows`
      (``sigma_min >= 1 / ||R^-1||_F`` over its first pivot, the largest column norm; 0 for a
      pivot under :data:`JACOBIAN_FLOOR` or a non-finite value);
    - ``bound`` (B,): an upper bound of the condition estimate of the rows' Gram matrix that
      :func:`minimum_norm` compares with :data:`ILL_CONDITIONED` (``l max(||C||_F^2, 1)
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


@njit(cache=True)
def minimum_norm(
    rows: np.ndarray,
    rhs: np.ndarray,
    chain_ints: np.ndarray,
    hard: np.ndarray,
    hard_rhs: np.ndarray,
    wrench: np.ndarray,
    kept: np.ndarray,
    forces: np.ndarray,
    projectors: np.ndarray,
    particular: np.ndarray,
    state: np.ndarray,
) -> int:
    """Least ``sum ||F_i||^2`` meeting every constraint: projectors and one KKT solve.

    ``rows`` (l, n, p), ``rhs`` (l, p), ``projectors`` (n, n, p) and ``particular`` (n, p) have
    the chain index last. Chains whose ``state`` is -2 come with their projector and particular
    solution (from :func:`full_rank_batch`); the others get them here from their rows.
    """
    p, n = forces.shape
    s = hard.shape[0]
    k = kept.shape[0]
    width = rows.shape[0]
    gram = np.empty((width, width))
    gram_inv = np.empty((width, width))
    scratch = np.empty((width, width))
    pseudo = np.empty((n, width))
    for i in range(p):
        if state[i] == -2:
            continue
        l_i = chain_ints[i, L_ROWS]
        for a in range(n):
            particular[a, i] = 0.0
        for r in range(n):
            for c in range(n):
                projectors[r, c, i] = 1.0 if r == c else 0.0
        if l_i == 0:
            continue
        for r in range(l_i):
            for c in range(l_i):
                acc = 0.0
                for a in range(n):
                    acc += rows[r, a, i] * rows[c, a, i]
                gram[r, c] = acc
        if inverse_into(gram, l_i, scratch, gram_inv) > ILL_CONDITIONED:
            return 2
        for a in range(n):  # pseudo = G^T (G G^T)^-1
            for c in range(l_i):
                acc = 0.0
                for r in range(l_i):
                    acc += rows[r, a, i] * gram_inv[r, c]
                pseudo[a, c] = acc
        for r in range(n):  # P = I - pseudo G, particular = pseudo t
            acc_t = 0.0
            for c in range(l_i):
                acc_t += pseudo[r, c] * rhs[c, i]
                value = pseudo[r, c]
                for a in range(n):
                    projectors[r, a, i] -= value * rows[c, a, i]
            particular[r, i] = acc_t
    size = k + s
    kkt = np.zeros((size, size))
    target = np.zeros(size)
    # the kept block of the projectors' sum over the chains, and the wrench left by the
    # particular solutions (four partial sums over the chains, then in order)
    for r in range(k):
        a = kept[r]
        target[r] = wrench[a] - _chain_sum(particular[a])
        for c in range(r, k):
            value = _chain_sum(projectors[a, kept[c]])
            kkt[r, c] = value
            kkt[c, r] = value
    for t in range(s):
        target[k + t] = hard_rhs[t]
    hp = np.zeros((s, n, p))  # C_i P_i
    for i in range(p if s else 0):
        for t in range(s):
            for a in range(n):
                acc = 0.0
                for b in range(n):
                    acc += hard[t, i, b] * projectors[b, a, i]
                hp[t, a, i] = acc
                target[k + t] -= hard[t, i, a] * particular[a, i]
            for r in range(k):
                value = hp[t, kept[r], i]  # (P C^T)[kept r, t] by symmetry of P
                kkt[r, k + t] += value
                kkt[k + t, r] += value
            for u in range(s):
                acc = 0.0
                for a in range(n):
                    acc += hp[t, a, i] * hard[u, i, a]
                kkt[k + t, k + u] += acc
    if size == 0:
        forces[:, :] = particular.T
        return 0
    kkt_inv, cond = invert(kkt)
    if cond > ILL_CONDITIONED:
        return 2
    multipliers = mv(kkt_inv, target)
    value = np.empty(p)
    for a in range(n):  # side by side over the chains
        value[:] = particular[a]
        for r in range(k):
            m = multipliers[r]
            proj = projectors[a, kept[r]]
            for i in range(p):
                value[i] += proj[i] * m
        for t in range(s):
            m = multipliers[k + t]
            for i in range(p):
                value[i] += hp[t, a, i] * m
        for i in range(p):
            forces[i, a] = value[i]
    return 0


@njit(cache=True)
def _chain_sum(values: np.ndarray) -> float:
    """Sum of ``values`` in four interleaved partial sums (independent additions)."""
    count = values.shape[0]
    s0, s1, s2, s3 = 0.0, 0.0, 0.0, 0.0
    end = count - count % 4
    for i in range(0, end, 4):
        s0 += values[i]
        s1 += values[i + 1]
        s2 += values[i + 2]
        s3 += values[i + 3]
    for i in range(end, count):
        s0 += values[i]
    return (s0 + s1) + (s2 + s3)


@njit(cache=True)
def partitioned_solve(
    rows: np.ndarray,
    rhs: np.ndarray,
    chain_ints: np.ndarray,
    cfs_start: int,
    free_start: int,
    hard: np.ndarray,
    hard_rhs: np.ndarray,
    wrench: np.ndarray,
    kept: np.ndarray,
    plan: np.ndarray,
    forces: np.ndarray,
) -> int:
    """The Partitioned Actuator Set solve with the declaration's CFS, RFS and MFS.

    Returns 2 (numpy decides) for an ill-conditioned block, the RFS block included when it is
    well conditioned only relative to itself: measured against the hard rows' size before the
    CFS was eliminated, a row that the natural constraints imply here is rounding.
    """
    p, n = forces.shape
    s = hard.shape[0]
    k = kept.shape[0]
    m = plan.shape[0]
    transforms = np.zeros((p, n, n))  # F_i = T_i f_i + w_i, T_i (n, d_i) padded to n columns
    offsets = np.zeros((p, n))
    width = rows.shape[0]
    block = np.empty((width, width))
    scratch = np.empty((width, width))
    inverse = np.empty((width, width))
    for i in range(p):
        l_i, d_i = chain_ints[i, L_ROWS], chain_ints[i, D_FREE]
        cfs = chain_ints[i, cfs_start : cfs_start + l_i]
        free = chain_ints[i, free_start : free_start + d_i]
        for j in range(d_i):
            transforms[i, free[j], j] = 1.0
        if l_i:
            for r in range(l_i):
                for c in range(l_i):
                    block[r, c] = rows[r, cfs[c], i]
            if inverse_into(block, l_i, scratch, inverse) > ILL_CONDITIONED:
                return 2
            for r in range(l_i):  # Q = -G_b^-1 G_a, u = G_b^-1 t
                acc = 0.0
                for c in range(l_i):
                    acc += inverse[r, c] * rhs[c, i]
                offsets[i, cfs[r]] = acc
                for c in range(d_i):
                    acc = 0.0
                    for t in range(l_i):
                        acc += inverse[r, t] * rows[t, free[c], i]
                    transforms[i, cfs[r], c] = -acc
    a_rows = np.zeros((k, m))
    a_rhs = np.empty(k)
    for r in range(k):
        a_rhs[r] = wrench[kept[r]]
    h_rows = np.zeros((s, m))
    h_rhs = hard_rhs.copy()
    h_scale = np.zeros(s)  # sum_i |c_i|_1 max|T_i|: what cancels in a reduced hard row
    for i in range(p):
        d_i, start = chain_ints[i, D_FREE], chain_ints[i, START]
        if s:
            t_max = 0.0
            for a in range(n):
                for j in range(d_i):
                    t_max = max(t_max, abs(transforms[i, a, j]))
            for t in range(s):
                acc = 0.0
                for a in range(n):
                    acc += abs(hard[t, i, a])
                h_scale[t] += acc * t_max
        for r in range(k):
            a_rhs[r] -= offsets[i, kept[r]]
            for j in range(d_i):
                a_rows[r, start + j] = transforms[i, kept[r], j]
        for t in range(s):
            for a in range(n):
                h_rhs[t] -= hard[t, i, a] * offsets[i, a]
            for j in range(d_i):
                acc = 0.0
                for a in range(n):
                    acc += hard[t, i, a] * transforms[i, a, j]
                h_rows[t, start + j] = acc
    rfs, mfs = plan[:s], plan[s:]
    f = np.zeros(m)
    if s:
        h_r = np.empty((s, s))
        h_m = np.empty((s, m - s))
        for t in range(s):
            for c in range(s):
                h_r[t, c] = h_rows[t, rfs[c]]
            for c in range(m - s):
                h_m[t, c] = h_rows[t, mfs[c]]
        h_inv, cond = invert(h_r)
        if cond > ILL_CONDITIONED or scaled_condition(h_r, h_inv, h_scale) > ILL_CONDITIONED:
            return 2  # singular here, or hard rows the natural ones imply: numpy decides
        gain = -mm(h_inv, h_m)
        bias = mv(h_inv, h_rhs)
    else:
        gain = np.zeros((0, m))
        bias = np.zeros(0)
    system = np.empty((k, m - s))
    target = a_rhs.copy()
    for r in range(k):
        for c in range(m - s):
            value = a_rows[r, mfs[c]]
            for t in range(s):
                value += a_rows[r, rfs[t]] * gain[t, c]
            system[r, c] = value
        for t in range(s):
            target[r] -= a_rows[r, rfs[t]] * bias[t]
    system_inv, cond = invert(system)
    if cond > ILL_CONDITIONED:
        return 2
    f_m = mv(system_inv, target)
    for c in range(m - s):
        f[mfs[c]] = f_m[c]
    for t in range(s):
        value = bias[t]
        for c in range(m - s):
            value += gain[t, c] * f_m[c]
        f[rfs[t]] = value
    for i in range(p):
        d_i, start = chain_ints[i, D_FREE], chain_ints[i, START]
        for a in range(n):
            value = offsets[i, a]
            for j in range(d_i):
                value += transforms[i, a, j] * f[start + j]
            forces[i, a] = value
    return 0


__all__ = [
    "BATCH_CHAINS",
    "HEADER",
    "full_rank_batch",
    "minimum_norm",
    "partitioned_solve",
]
