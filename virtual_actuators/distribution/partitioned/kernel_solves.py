"""The two compiled solves of the distribution, on the rows `kernels.distribute` built.

- `minimum_norm` (mode 0): the least ``sum ||F_i||^2`` through the ``(k + s)`` KKT system
  of the chains' projectors (`kernel_batch.full_rank_batch` computes those of many chains
  of full column rank side by side);
- `partitioned_solve` (mode 1): the Partitioned Actuator Set method with the declaration's
  sets.
"""

from __future__ import annotations

import numpy as np

from ...kinematics.kernels import njit
from ..tolerances import ILL_CONDITIONED
from .kernel_linalg import inverse_into, invert, mm, mv, scaled_condition
from .kernel_tables import D_FREE, L_ROWS, START


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
    solution (from `kernel_batch.full_rank_batch`); the others get them here from their rows.
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


__all__ = ["minimum_norm", "partitioned_solve"]
