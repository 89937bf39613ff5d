"""Compiled per-tick force distribution: natural constraints, solve and torques in one call.

:func:`distribute` does at one configuration what
:class:`~virtual_actuators.distribution.problem.DistributionProblem` (``evaluate``) and
:class:`~virtual_actuators.distribution.partitioner.PartitionedSolver` do with numpy, for the two
regular cases, on tables built once from the declaration (see :mod:`.compiled`):

- ``mode 0``, fewer constraints than unknowns: the minimum of ``sum ||F_i||^2`` through the
  ``(k + s)`` KKT system of the chains' projectors (VAC 2.5.2);
- ``mode 1``, as many: the Partitioned Actuator Set method with the declaration's sets, one
  ``l x l`` elimination of the Constrained Force Set per chain, the Redundant Force Set by the
  design rows and one ``k x k`` solve for the Minimum Force Set (VAC 2.5.1).

It never raises: a nonzero status hands the tick to the numpy path, which re-picks sets, falls
back to least squares or raises the typed error with its message (status 1: a chain is singular
or nearly so, or its Jacobian is below :data:`JACOBIAN_FLOOR`; status 2: an elimination block
or the final system is ill-conditioned, or the answer misses an exact row by more than
:data:`CONSTRAINT_TOL` of its scale; status 3: a result overflowed).
"""

from __future__ import annotations

import numpy as np

from ..kinematics.kernels import njit
from .linalg import CONSTRAINT_TOL, JACOBIAN_FLOOR, ROUNDING

#: Same thresholds as the numpy path (a kernel status hands the decision to it).
ILL_CONDITIONED = 1e10
NEAR_SINGULAR = 1e-7
#: Fewest chains for which mode 0 runs the chains of full column rank side by side
#: (:func:`_full_rank_batch`); with fewer, its fixed cost outweighs what it saves.
BATCH_CHAINS = 8

# columns of the per-chain integer table
K_COLS, C_CON, NB_BALL, RANK, L_ROWS, D_FREE, START = 0, 1, 2, 3, 4, 5, 6
HEADER = 7


@njit(cache=True)
def _mm(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Small matrix product with plain loops (no BLAS: tiny sizes, no SciPy needed)."""
    rows, inner = a.shape
    cols = b.shape[1]
    out = np.zeros((rows, cols))
    for r in range(rows):
        for k in range(inner):
            value = a[r, k]
            if value != 0.0:
                for c in range(cols):
                    out[r, c] += value * b[k, c]
    return out


@njit(cache=True)
def _mv(a: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Small matrix-vector product with plain loops."""
    out = np.zeros(a.shape[0])
    for r in range(a.shape[0]):
        acc = 0.0
        for k in range(a.shape[1]):
            acc += a[r, k] * x[k]
        out[r] = acc
    return out


@njit(cache=True)
def _inverse(matrix: np.ndarray) -> tuple[np.ndarray, float]:
    """Inverse by Gauss-Jordan with partial pivoting and ``||A||_inf ||A^-1||_inf``."""
    m = matrix.shape[0]
    inv = np.empty((m, m))
    cond = _inverse_into(matrix, m, np.empty((m, m)), inv)
    return inv, cond


@njit(cache=True)
def _inverse_into(matrix: np.ndarray, m: int, a: np.ndarray, inv: np.ndarray) -> float:
    """Invert the leading ``m x m`` block of ``matrix`` into ``inv`` (``a``: scratch).

    Returns the condition estimate ``||A||_inf ||A^-1||_inf`` (inf when exactly singular).
    """
    for i in range(m):
        for j in range(m):
            a[i, j] = matrix[i, j]
            inv[i, j] = 1.0 if i == j else 0.0
    norm = 0.0
    for i in range(m):
        row = 0.0
        for j in range(m):
            row += abs(matrix[i, j])
        norm = max(norm, row)
    for col in range(m):
        pivot = col
        for r in range(col + 1, m):
            if abs(a[r, col]) > abs(a[pivot, col]):
                pivot = r
        if a[pivot, col] == 0.0:
            return np.inf
        if pivot != col:
            for j in range(m):
                a[col, j], a[pivot, j] = a[pivot, j], a[col, j]
                inv[col, j], inv[pivot, j] = inv[pivot, j], inv[col, j]
        scale = 1.0 / a[col, col]
        for j in range(m):
            a[col, j] *= scale
            inv[col, j] *= scale
        for r in range(m):
            if r != col and a[r, col] != 0.0:
                factor = a[r, col]
                for j in range(m):
                    a[r, j] -= factor * a[col, j]
                    inv[r, j] -= factor * inv[col, j]
    norm_inv = 0.0
    for i in range(m):
        row = 0.0
        for j in range(m):
            row += abs(inv[i, j])
        norm_inv = max(norm_inv, row)
    estimate = norm * norm_inv
    if not np.isfinite(estimate):
        estimate = np.inf
    return estimate


@njit(cache=True)
def _null_rows(
    full: np.ndarray,
    rank: int,
    out: np.ndarray,
    work: np.ndarray,
    basis: np.ndarray,
    used: np.ndarray,
    vec: np.ndarray,
    best_vec: np.ndarray,
) -> float:
    """Orthonormal rows spanning the left null space of ``full`` (n x c) into ``out``.

    Pivoted modified Gram-Schmidt on the columns (``rank`` steps), then the unit vectors with the
    largest residuals complete the basis. Returns the rank-revealing ratio of the last pivot to
    the first (0 for an exactly singular chain).
    """
    n, c = full.shape
    for r in range(n):
        for j in range(c):
            work[r, j] = full[r, j]
    used[:c] = False
    first, last = 0.0, 0.0
    for step in range(rank):
        best, best_norm = -1, -1.0
        for j in range(c):
            if not used[j]:
                s = 0.0
                for r in range(n):
                    s += work[r, j] * work[r, j]
                if s > best_norm:
                    best, best_norm = j, s
        norm = np.sqrt(best_norm)
        if step == 0:
            first = norm
        last = norm
        used[best] = True
        if norm <= JACOBIAN_FLOOR:  # this direction is produced by nothing (absolute floor)
            return 0.0
        for r in range(n):
            basis[r, step] = work[r, best] / norm
        for j in range(c):
            if not used[j]:
                dot = 0.0
                for r in range(n):
                    dot += basis[r, step] * work[r, j]
                for r in range(n):
                    work[r, j] -= dot * basis[r, step]
    for step in range(rank, n):
        best_norm = -1.0
        for e in range(n):
            vec[:] = 0.0
            vec[e] = 1.0
            for b in range(step):
                dot = basis[e, b]
                for r in range(n):
                    vec[r] -= dot * basis[r, b]
            s = 0.0
            for r in range(n):
                s += vec[r] * vec[r]
            if s > best_norm:
                best_norm = s
                best_vec[:] = vec
        norm = np.sqrt(best_norm)
        for r in range(n):
            basis[r, step] = best_vec[r] / norm
            out[step - rank, r] = basis[r, step]
    return last / first if first > 0.0 else 0.0


@njit(cache=True, error_model="numpy")
def _full_rank_batch(
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
    - ``ratio`` (B,): a lower bound of the rank-revealing ratio of :func:`_null_rows`
      (``sigma_min >= 1 / ||R^-1||_F`` over its first pivot, the largest column norm; 0 for a
      pivot under :data:`JACOBIAN_FLOOR` or a non-finite value);
    - ``bound`` (B,): an upper bound of the condition estimate of the rows' Gram matrix that
      :func:`_minimum_norm` compares with :data:`ILL_CONDITIONED` (``l max(||C||_F^2, 1)
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
def _minimum_norm(
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

    Chains whose ``state`` is -2 come with their projector and particular solution (from
    :func:`_full_rank_batch`); the others get them here from their rows.
    """
    p, n = forces.shape
    s = hard.shape[0]
    k = kept.shape[0]
    width = rows.shape[1]
    gram = np.empty((width, width))
    gram_inv = np.empty((width, width))
    scratch = np.empty((width, width))
    pseudo = np.empty((n, width))
    for i in range(p):
        if state[i] == -2:
            continue
        l_i = chain_ints[i, L_ROWS]
        projector = projectors[i]
        for a in range(n):
            particular[i, a] = 0.0
        for r in range(n):
            for c in range(n):
                projector[r, c] = 1.0 if r == c else 0.0
        if l_i == 0:
            continue
        for r in range(l_i):
            for c in range(l_i):
                acc = 0.0
                for a in range(n):
                    acc += rows[i, r, a] * rows[i, c, a]
                gram[r, c] = acc
        if _inverse_into(gram, l_i, scratch, gram_inv) > ILL_CONDITIONED:
            return 2
        for a in range(n):  # pseudo = G^T (G G^T)^-1
            for c in range(l_i):
                acc = 0.0
                for r in range(l_i):
                    acc += rows[i, r, a] * gram_inv[r, c]
                pseudo[a, c] = acc
        for r in range(n):  # P = I - pseudo G, particular = pseudo t
            acc_t = 0.0
            for c in range(l_i):
                acc_t += pseudo[r, c] * rhs[i, c]
                value = pseudo[r, c]
                for a in range(n):
                    projector[r, a] -= value * rows[i, c, a]
            particular[i, r] = acc_t
    size = k + s
    kkt = np.zeros((size, size))
    target = np.zeros(size)
    for r in range(k):
        target[r] = wrench[kept[r]]
    for t in range(s):
        target[k + t] = hard_rhs[t]
    # sum of the projectors and the particular solutions over the chains (in chain order, so
    # the same sums as entry by entry), then the kept block
    sums = np.zeros((n + 1, n))  # rows: the projectors' sum, then the wrench left
    for r in range(k):
        sums[n, kept[r]] = wrench[kept[r]]
    for i in range(p):
        for a in range(n):
            sums[n, a] -= particular[i, a]
            for c in range(n):
                sums[a, c] += projectors[i, a, c]
    for r in range(k):
        target[r] = sums[n, kept[r]]
        for c in range(k):
            kkt[r, c] = sums[kept[r], kept[c]]
    hp = np.zeros((p, s, n))  # C_i P_i
    for i in range(p if s else 0):
        proj = projectors[i]
        for t in range(s):
            for a in range(n):
                acc = 0.0
                for b in range(n):
                    acc += hard[t, i, b] * proj[b, a]
                hp[i, t, a] = acc
                target[k + t] -= hard[t, i, a] * particular[i, a]
            for r in range(k):
                value = hp[i, t, kept[r]]  # (P C^T)[kept r, t] by symmetry of P
                kkt[r, k + t] += value
                kkt[k + t, r] += value
            for u in range(s):
                acc = 0.0
                for a in range(n):
                    acc += hp[i, t, a] * hard[u, i, a]
                kkt[k + t, k + u] += acc
    if size == 0:
        forces[:, :] = particular
        return 0
    kkt_inv, cond = _inverse(kkt)
    if cond > ILL_CONDITIONED:
        return 2
    multipliers = _mv(kkt_inv, target)
    for i in range(p):
        for a in range(n):
            value = particular[i, a]
            for r in range(k):
                value += projectors[i, a, kept[r]] * multipliers[r]
            for t in range(s):
                value += hp[i, t, a] * multipliers[k + t]
            forces[i, a] = value
    return 0


@njit(cache=True)
def _partitioned(
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
    """The Partitioned Actuator Set solve with the declaration's CFS, RFS and MFS."""
    p, n = forces.shape
    s = hard.shape[0]
    k = kept.shape[0]
    m = plan.shape[0]
    transforms = np.zeros((p, n, n))  # F_i = T_i f_i + w_i, T_i (n, d_i) padded to n columns
    offsets = np.zeros((p, n))
    width = rows.shape[1]
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
                    block[r, c] = rows[i, r, cfs[c]]
            if _inverse_into(block, l_i, scratch, inverse) > ILL_CONDITIONED:
                return 2
            for r in range(l_i):  # Q = -G_b^-1 G_a, u = G_b^-1 t
                acc = 0.0
                for c in range(l_i):
                    acc += inverse[r, c] * rhs[i, c]
                offsets[i, cfs[r]] = acc
                for c in range(d_i):
                    acc = 0.0
                    for t in range(l_i):
                        acc += inverse[r, t] * rows[i, t, free[c]]
                    transforms[i, cfs[r], c] = -acc
    a_rows = np.zeros((k, m))
    a_rhs = np.empty(k)
    for r in range(k):
        a_rhs[r] = wrench[kept[r]]
    h_rows = np.zeros((s, m))
    h_rhs = hard_rhs.copy()
    for i in range(p):
        d_i, start = chain_ints[i, D_FREE], chain_ints[i, START]
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
        h_inv, cond = _inverse(h_r)
        if cond > ILL_CONDITIONED:
            return 2
        gain = -_mm(h_inv, h_m)
        bias = _mv(h_inv, h_rhs)
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
    system_inv, cond = _inverse(system)
    if cond > ILL_CONDITIONED:
        return 2
    f_m = _mv(system_inv, target)
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


@njit(cache=True)
def _constraint_error(
    rows: np.ndarray,
    rhs: np.ndarray,
    hard: np.ndarray,
    hard_rhs: np.ndarray,
    forces: np.ndarray,
) -> float:
    """Largest miss of an exact row (natural or hard), relative to ``|row| |F| + |rhs|``."""
    p, n = forces.shape
    peak = 0.0
    for i in range(p):
        for a in range(n):
            peak = max(peak, abs(forces[i, a]))
    worst = 0.0
    for i in range(p):
        for r in range(rows.shape[1]):
            acc, size = -rhs[i, r], abs(rhs[i, r])
            for a in range(n):
                acc += rows[i, r, a] * forces[i, a]
                size = max(size, abs(rows[i, r, a]) * peak)
            if size > 0.0:
                worst = max(worst, abs(acc) / size)
    for t in range(hard.shape[0]):
        acc, size = -hard_rhs[t], abs(hard_rhs[t])
        for i in range(p):
            for a in range(n):
                acc += hard[t, i, a] * forces[i, a]
                size = max(size, abs(hard[t, i, a]) * peak)
        if size > 0.0:
            worst = max(worst, abs(acc) / size)
    return worst


@njit(cache=True)
def distribute(
    jacobian_world: np.ndarray,
    frames: np.ndarray,
    q: np.ndarray,
    wrench: np.ndarray,
    keep: np.ndarray,
    mode: int,
    axis_rows: np.ndarray,
    frame_rows: np.ndarray,
    chain_ints: np.ndarray,
    chain_signs: np.ndarray,
    springs: np.ndarray,
    const_rows: np.ndarray,
    const_rhs: np.ndarray,
    torque_rows: np.ndarray,
    torque_signs: np.ndarray,
    plan: np.ndarray,
    layout: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, int, float, int]:
    """One tick of the force distribution (see the module docstring).

    Args:
        jacobian_world: ``(6, nv)`` world joint Jacobian of the snapshot.
        frames: ``(nf, 12)`` frame placements of the snapshot.
        q: ``(nq,)`` configuration (passive spring angles).
        wrench: ``(n,)`` requested wrench.
        keep: ``(n,)`` 1 for prescribed axes, 0 for free ones.
        mode: 0 minimum norm, 1 partitioned (square).
        axis_rows: ``(n,)`` rows of the selected axes among ``x y z rx ry rz``.
        frame_rows: ``(2 + p,)`` rows of {B}, {O} and each {A_i} in ``frames``.
        chain_ints: ``(p, HEADER + K + C + 3 + L + D)`` per chain: the header (columns, own
            constrained joints, ball axes, rank, natural rows, free entries, start of its free
            entries in the reduced unknowns), then its velocity columns, the positions of its
            constrained joints among them, its ball axes (0-2), its CFS and its free entries.
        chain_signs: ``(p, K)`` +1/-1 of each chain column.
        springs: ``(nv, 5)`` per velocity index: stiffness, rest angle, ``idx_q`` (-1: no
            spring), 1 for a (cos, sin) joint, and 1 if the joint is actuated (0: limp or
            passive, its effort is zeroed).
        const_rows: ``(s0, p, n)`` constant design rows.
        const_rhs: ``(s0,)`` their right-hand sides.
        torque_rows: ``(s1, 3)`` torque rows: joint a, joint b (-1: none), kind (0: shared
            limp/passive joint, ahead of the constant rows; 1: equal torques, after them).
        torque_signs: ``(s1, 2, p)`` chain signs at joints a and b.
        plan: ``(m,)`` mode 1: the RFS indices first (``s`` of them), then the MFS.
        layout: ``(4,)`` widths K, C, L, D of the column blocks of ``chain_ints``.

    Returns:
        ``(forces (p, n), tau (nv, 0 at limp and passive joints), passive (nv), produced (n),
        requested (n, free axes: produced), residual, |wrench| on prescribed axes, status,
        worst chain ratio, worst chain)``.

    """
    n = axis_rows.shape[0]
    p = chain_ints.shape[0]
    nv = jacobian_world.shape[1]
    K = chain_signs.shape[1]
    forces = np.zeros((p, n))
    tau = np.zeros(nv)
    passive = np.zeros(nv)
    # -- the tick's kinematics, in {O} at {B}'s origin ---------------------------------------
    b, o = frame_rows[0], frame_rows[1]
    rot_o = np.empty((3, 3))
    for r in range(3):
        for c in range(3):
            rot_o[r, c] = frames[o, 3 * r + c]
    x, y, z = frames[b, 9], frames[b, 10], frames[b, 11]
    shift = np.array(((0.0, z, -y), (-z, 0.0, x), (y, -x, 0.0)))
    transform = np.zeros((6, 6))
    for r in range(3):
        for c in range(3):
            transform[r, c] = rot_o[c, r]
            transform[3 + r, 3 + c] = rot_o[c, r]
            s = 0.0
            for k in range(3):
                s += rot_o[k, r] * shift[k, c]
            transform[r, 3 + c] = s
    jac_t = np.empty((nv, n))  # the Jacobian in {O}, one row per velocity index
    for v in range(nv):
        for a in range(n):
            row = axis_rows[a]
            s = 0.0
            for k in range(6):
                s += transform[row, k] * jacobian_world[k, v]
            jac_t[v, a] = s
    for v in range(nv):
        if springs[v, 2] >= 0:
            iq = int(springs[v, 2])
            angle = np.arctan2(q[iq + 1], q[iq]) if springs[v, 3] > 0 else q[iq]
            passive[v] = -springs[v, 0] * (angle - springs[v, 1])
    # -- natural constraint rows per chain -----------------------------------------------------
    rows = np.zeros((p, max(layout[2], 1), n))
    rhs = np.zeros((p, max(layout[2], 1)))
    worst, worst_chain = np.inf, -1
    columns = np.zeros((K + 3, n))  # a chain's columns, one per row
    null_buffer = np.zeros((n, n))
    column = np.zeros(6)
    work = np.empty((n, K + 3))
    basis = np.empty((n, n))
    used = np.zeros(K + 3, dtype=np.bool_)
    vec = np.empty(n)
    best_vec = np.empty(n)
    # mode 0, chains of full column rank: projector and particular solution from one QR, the
    # chains of one shape (columns, constraint columns) side by side in _full_rank_batch
    projectors = np.empty((p, n, n))
    particular = np.zeros((p, n))
    state = np.full(p, -1, dtype=np.int64)  # -1 general, key >= 0 awaiting batch, -2 done
    batch = mode == 0 and p >= BATCH_CHAINS
    batch_size = p if batch else 0
    # fast chains: columns in QR order, chains last; row K + 3: right-hand sides of the rows
    fulls = np.empty((K + 4, n, batch_size))
    for i in range(p):
        k_i = chain_ints[i, K_COLS]
        c_i = chain_ints[i, C_CON]
        nb = chain_ints[i, NB_BALL]
        rank = chain_ints[i, RANK]
        for j in range(k_i):
            v, sign = chain_ints[i, HEADER + j], chain_signs[i, j]
            for a in range(n):
                columns[j, a] = jac_t[v, a] * sign
        # offset from {A_i} to {B} in {O}
        a_row = frame_rows[2 + i]
        dx = frames[b, 9] - frames[a_row, 9]
        dy = frames[b, 10] - frames[a_row, 10]
        dz = frames[b, 11] - frames[a_row, 11]
        d0 = rot_o[0, 0] * dx + rot_o[1, 0] * dy + rot_o[2, 0] * dz
        d1 = rot_o[0, 1] * dx + rot_o[1, 1] * dy + rot_o[2, 1] * dz
        d2 = rot_o[0, 2] * dx + rot_o[1, 2] * dy + rot_o[2, 2] * dz
        con_start = HEADER + K
        ball_start = con_start + layout[1]
        for j in range(nb):
            axis = chain_ints[i, ball_start + j]
            for a in range(6):
                column[a] = 0.0
            # e_axis x d
            if axis == 0:
                column[1], column[2] = -d2, d1
            elif axis == 1:
                column[0], column[2] = d2, -d0
            else:
                column[0], column[1] = -d1, d0
            column[3 + axis] = 1.0
            for a in range(n):
                columns[k_i + j, a] = column[axis_rows[a]]
        ratio = 1.0
        fast = batch and rank > 0 and rank == k_i + nb
        if fast:  # QR order: own constrained joints, ball axes, then the free joints
            m_c = c_i + nb
            for j in range(c_i):
                position = chain_ints[i, con_start + j]
                for a in range(n):
                    fulls[j, a, i] = columns[position, a]
                fulls[K + 3, j, i] = passive[chain_ints[i, HEADER + position]]
            for j in range(nb):
                for a in range(n):
                    fulls[c_i + j, a, i] = columns[k_i + j, a]
                fulls[K + 3, c_i + j, i] = 0.0
            at = m_c
            for j in range(k_i):
                constrained = False
                for jj in range(c_i):
                    if chain_ints[i, con_start + jj] == j:
                        constrained = True
                if not constrained and at < rank:
                    for a in range(n):
                        fulls[at, a, i] = columns[j, a]
                    at += 1
            fast = at == rank
        if fast:
            state[i] = rank * (K + 4) + m_c
            ratio = 1.0  # from the batch below
        elif rank > 0:
            null = null_buffer[: n - rank]
            full = columns[: k_i + nb].T
            ratio = _null_rows(full, rank, null, work, basis, used, vec, best_vec)
        if not fast and ratio < worst:
            worst, worst_chain = ratio, i
        # rows: own constrained joints, ball axes, null directions
        for j in range(c_i):
            position = chain_ints[i, con_start + j]
            for a in range(n):
                rows[i, j, a] = columns[position, a]
            rhs[i, j] = passive[chain_ints[i, HEADER + position]]
        for j in range(nb):
            for a in range(n):
                rows[i, c_i + j, a] = columns[k_i + j, a]
        if not fast:
            for j in range(n - rank):
                for a in range(n):
                    rows[i, c_i + nb + j, a] = null_buffer[j, a]
    ill = False
    for i in range(batch_size):
        key = state[i]
        if key < 0:
            continue
        count = 0
        for i2 in range(i, p):
            count += state[i2] == key
        members = np.empty(count, dtype=np.int64)
        count = 0
        for i2 in range(i, p):
            if state[i2] == key:
                members[count] = i2
                count += 1
        c_b = chain_ints[i, RANK]
        m_c = chain_ints[i, C_CON] + chain_ints[i, NB_BALL]
        if count == p:
            q_b = fulls  # every chain: no copy (overwritten by the QR)
        else:
            q_b = np.empty((c_b, n, count))
            for j in range(c_b):
                for a in range(n):
                    for b in range(count):
                        q_b[j, a, b] = fulls[j, a, members[b]]
        t_b = np.empty((m_c, count))
        for j in range(m_c):
            for b in range(count):
                t_b[j, b] = fulls[K + 3, j, members[b]]
        ratio_b = np.empty(count)
        bound_b = np.empty(count)
        proj_b = np.empty((n, n, count))
        part_b = np.empty((n, count))
        null_b = np.empty((n - c_b, n, count))
        _full_rank_batch(q_b, c_b, m_c, t_b, ratio_b, bound_b, proj_b, part_b, null_b)
        for b in range(count):
            chain = members[b]
            state[chain] = -2
            if ratio_b[b] < worst:
                worst, worst_chain = ratio_b[b], chain
            if bound_b[b] > ILL_CONDITIONED:
                ill = True
            for r in range(n):
                particular[chain, r] = part_b[r, b]
                for a in range(n):
                    projectors[chain, r, a] = proj_b[r, a, b]
            for j in range(n - c_b):
                for a in range(n):
                    rows[chain, m_c + j, a] = null_b[j, a, b]
    if worst < NEAR_SINGULAR:
        empty = np.zeros(n)
        return forces, tau, passive, empty, empty, 0.0, 0.0, 0.0, 1, worst, worst_chain
    # -- hard rows: shared joints, constant design rows, equal torques --------------------------
    s0 = const_rows.shape[0]
    s1 = torque_rows.shape[0]
    s = s0 + s1
    hard = np.zeros((s, p, n))
    hard_rhs = np.zeros(s)
    index = 0
    for kind in range(2):
        if kind == 1:
            for t in range(s0):
                hard[index] = const_rows[t]
                hard_rhs[index] = const_rhs[t]
                index += 1
        for t in range(s1):
            if torque_rows[t, 2] != kind:
                continue
            va, vb = torque_rows[t, 0], torque_rows[t, 1]
            for i in range(p):
                for a in range(n):
                    value = torque_signs[t, 0, i] * jac_t[va, a]
                    if vb >= 0:
                        value -= torque_signs[t, 1, i] * jac_t[vb, a]
                    hard[index, i, a] = value
            hard_rhs[index] = passive[va] if kind == 0 else 0.0
            index += 1
    kept = np.flatnonzero(keep)
    if ill:
        status = 2  # a chain's rows are ill-conditioned: numpy decides
    elif mode == 0:
        status = _minimum_norm(
            rows,
            rhs,
            chain_ints,
            hard,
            hard_rhs,
            wrench,
            kept,
            forces,
            projectors,
            particular,
            state,
        )
    else:
        cfs_start = HEADER + K + layout[1] + 3
        free_start = cfs_start + layout[2]
        status = _partitioned(
            rows, rhs, chain_ints, cfs_start, free_start, hard, hard_rhs, wrench, kept, plan, forces
        )
    if status == 0 and _constraint_error(rows, rhs, hard, hard_rhs, forces) > CONSTRAINT_TOL:
        status = 2  # an ill-conditioned elimination lost an exact row: numpy decides
    produced = np.zeros(n)
    requested = np.zeros(n)
    if status != 0:
        return forces, tau, passive, produced, requested, 0.0, 0.0, 0.0, status, worst, worst_chain
    for i in range(p):
        k_i = chain_ints[i, K_COLS]
        for j in range(k_i):
            v = chain_ints[i, HEADER + j]
            acc = 0.0
            for a in range(n):
                acc += jac_t[v, a] * forces[i, a]
            tau[v] += chain_signs[i, j] * acc * springs[v, 4]
        for a in range(n):
            produced[a] += forces[i, a]
    # scale-free norms (no overflow or underflow at any magnitude of the request)
    peak, force_peak = 0.0, 0.0
    for a in range(n):
        if keep[a]:
            peak = max(peak, abs(wrench[a]), abs(produced[a]), abs(produced[a] - wrench[a]))
            requested[a] = wrench[a]
        else:
            requested[a] = produced[a]
    for i in range(p):
        for a in range(n):
            force_peak = max(force_peak, abs(forces[i, a]))
    if not (np.isfinite(peak) and np.isfinite(force_peak)):
        return forces, tau, passive, produced, requested, 0.0, 0.0, 0.0, 3, worst, worst_chain
    residual, request, output = 0.0, 0.0, 0.0
    if peak > 0.0:
        for a in range(n):
            if keep[a]:
                error = (produced[a] - wrench[a]) / peak
                residual += error * error
                request += (wrench[a] / peak) ** 2
                output += (produced[a] / peak) ** 2
    residual = peak * np.sqrt(residual)
    # what the residual is compared with: tol times the request or what was produced,
    # whichever is larger, plus the rounding of chain forces that cancel each other
    scale = peak * np.sqrt(max(request, output))
    return (
        forces,
        tau,
        passive,
        produced,
        requested,
        residual,
        scale,
        ROUNDING * force_peak,
        0,
        worst,
        worst_chain,
    )
