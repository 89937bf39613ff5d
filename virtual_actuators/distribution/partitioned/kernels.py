"""Compiled per-tick force distribution: natural constraints, solve and torques in one call.

`distribute` does at one configuration what
`DistributionProblem` (``evaluate``) and
`PartitionedSolver` do with numpy,
for the two
regular cases, on tables built once from the declaration (see `compiled`):

- ``mode 0``, fewer constraints than unknowns: the minimum of ``sum ||F_i||^2`` through the
  ``(k + s)`` KKT system of the chains' projectors (VAC 2.5.2);
- ``mode 1``, as many: the Partitioned Actuator Set method with the declaration's sets, one
  ``l x l`` elimination of the Constrained Force Set per chain, the Redundant Force Set by the
  design rows and one ``k x k`` solve for the Minimum Force Set (VAC 2.5.1).

It never raises: a nonzero status hands the tick to the numpy path, which re-picks sets, falls
back to least squares or raises the typed error with its message (status 1: a chain is singular
or nearly so, or its Jacobian is below `JACOBIAN_FLOOR`; status 2: an elimination block
or the final system is ill-conditioned, a design or coupling row is (nearly) implied by the
natural constraints at this configuration, judged against the row's size before the
elimination, or the answer misses an exact row by more than `CONSTRAINT_TOL` of its
scale; status 3: a result overflowed).

numba's on-disk cache of `distribute` does not follow edits of the kernels it calls from
other modules (`kernel_solves`, `kernel_batch`, `kernel_linalg`, the tail
in `virtual_actuators.distribution.result`): an edit there goes with an edit of this file,
so that the cache is rebuilt.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ...kinematics.kernels import njit
from ..result import close_norms
from ..tolerances import CONSTRAINT_TOL, ILL_CONDITIONED, NEAR_SINGULAR
from .kernel_batch import BATCH_CHAINS, full_rank_batch
from .kernel_linalg import (
    ball_entry,
    constraint_error,
    null_rows,
    offset_in_o,
    passive_torques,
    shared_ball_columns,
    wrench_transform,
)
from .kernel_solves import minimum_norm, partitioned_solve
from .kernel_tables import C_CON, HEADER, K_COLS, NB_BALL, PACK_HEADER, RANK


class Distributed(NamedTuple):
    """What `distribute` hands back.

    The tick's buffer and norms (`TickResult.from_buffer`), its status (0, or why the
    numpy path decides, see the module docstring) and the worst chain's condition ratio.
    """

    out: np.ndarray
    residual: float
    scale: float
    rounding: float
    status: int
    worst: float
    worst_chain: int


@njit(cache=True)
def distribute(
    jacobian_world: np.ndarray,
    frames: np.ndarray,
    q: np.ndarray,
    wrench: np.ndarray,
    ints: np.ndarray,
    floats: np.ndarray,
) -> Distributed:
    """One tick of the force distribution (see the module docstring).

    Args:
        jacobian_world: ``(6, nv)`` world joint Jacobian of the snapshot.
        frames: ``(nf, 12)`` frame placements of the snapshot.
        q: ``(nq,)`` configuration (passive spring angles).
        wrench: ``(n,)`` requested wrench.
        ints: The declaration-time integers of `pack_arguments`.
        floats: Its declaration-time floats.

    Returns:
        The `Distributed` tick (its tail by
        `close_norms`).

    """
    mode, n, p, width, s1, m, K, nv_springs, s0 = ints[:PACK_HEADER]
    at = PACK_HEADER
    keep = ints[at : at + n]
    at += n
    axis_rows = ints[at : at + n]
    at += n
    frame_rows = ints[at : at + 2 + p]
    at += 2 + p
    chain_ints = ints[at : at + p * width].reshape((p, width))
    at += p * width
    torque_rows = ints[at : at + 3 * s1].reshape((s1, 3))
    at += 3 * s1
    plan = ints[at : at + m]
    layout = ints[at + m : at + m + 4]
    chain_signs = floats[: p * K].reshape((p, K))
    at = p * K
    springs = floats[at : at + 5 * nv_springs].reshape((nv_springs, 5))
    at += 5 * nv_springs
    const_rows = floats[at : at + s0 * p * n].reshape((s0, p, n))
    at += s0 * p * n
    const_rhs = floats[at : at + s0]
    torque_signs = floats[at + s0 : at + s0 + 2 * p * s1].reshape((s1, 2, p))
    nv = jacobian_world.shape[1]
    # one output buffer (one array to hand back): forces, tau, passive, produced, requested
    out = np.zeros(p * n + 2 * nv + 2 * n)
    forces = out[: p * n].reshape((p, n))
    tau = out[p * n : p * n + nv]
    passive = out[p * n + nv : p * n + 2 * nv]
    produced = out[p * n + 2 * nv : p * n + 2 * nv + n]
    requested = out[p * n + 2 * nv + n :]
    # -- the tick's kinematics, in {O} at {B}'s origin ---------------------------------------
    b, o = frame_rows[0], frame_rows[1]
    rot_o, transform = wrench_transform(frames, b, o)
    jac_t = np.empty((n, nv))  # the Jacobian in {O}, one row per selected axis
    for a in range(n):
        row = axis_rows[a]
        t0, t1, t2 = transform[row, 0], transform[row, 1], transform[row, 2]
        t3, t4, t5 = transform[row, 3], transform[row, 4], transform[row, 5]
        for v in range(nv):
            jac_t[a, v] = (
                t0 * jacobian_world[0, v]
                + t1 * jacobian_world[1, v]
                + t2 * jacobian_world[2, v]
                + t3 * jacobian_world[3, v]
                + t4 * jacobian_world[4, v]
                + t5 * jacobian_world[5, v]
            )
    passive_torques(springs, q, passive)
    # -- natural constraint rows per chain (chain index last, like the batch) -----------------
    width = max(layout[2], 1)
    rows = np.zeros((width, n, p))
    rhs = np.zeros((width, p))
    worst, worst_chain = np.inf, -1
    columns = np.zeros((K + 3, n))  # a chain's columns, one per row
    null_buffer = np.zeros((n, n))
    work = np.empty((n, K + 3))
    basis = np.empty((n, n))
    used = np.zeros(K + 3, dtype=np.bool_)
    vec = np.empty(n)
    best_vec = np.empty(n)
    # mode 0, chains of full column rank: projector and particular solution from one QR, the
    # chains of one shape (columns, constraint columns) side by side in full_rank_batch
    projectors = np.empty((n, n, p))
    particular = np.zeros((n, p))
    state = np.full(p, -1, dtype=np.int64)  # -1 general, key >= 0 awaiting batch, -2 done
    batch = mode == 0 and p >= BATCH_CHAINS
    batch_size = p if batch else 0
    # fast chains: columns in QR order, chains last; row K + 3: right-hand sides of the rows
    fulls = np.empty((K + 4, n, batch_size))
    con_start = HEADER + K
    ball_start = con_start + layout[1]
    # every chain fast with the same constrained count and ball axes: the ball columns are
    # written side by side over the chains after the loop, from the offsets
    shared = batch
    for i in range(p if batch else 0):
        nb = chain_ints[i, NB_BALL]
        if not (
            chain_ints[i, RANK] == chain_ints[i, K_COLS] + nb
            and chain_ints[i, C_CON] == chain_ints[0, C_CON]
            and nb == chain_ints[0, NB_BALL]
        ):
            shared = False
            break
        for j in range(nb):
            if chain_ints[i, ball_start + j] != chain_ints[0, ball_start + j]:
                shared = False
    offsets = np.empty((3, p if shared else 0))
    for i in range(p):
        k_i = chain_ints[i, K_COLS]
        c_i = chain_ints[i, C_CON]
        nb = chain_ints[i, NB_BALL]
        rank = chain_ints[i, RANK]
        fast = batch and rank > 0 and rank == k_i + nb
        d0, d1, d2 = 0.0, 0.0, 0.0
        if nb:  # offset from {A_i} to {B} in {O}
            d0, d1, d2 = offset_in_o(frames, b, frame_rows[2 + i], rot_o)
        if fast:
            # QR order: own constrained joints, ball axes, then the free joints; the
            # constraint columns are also the chain's first rows
            m_c = c_i + nb
            at = m_c
            for j in range(k_i):
                v, sign = chain_ints[i, HEADER + j], chain_signs[i, j]
                slot = -1
                for jj in range(c_i):
                    if chain_ints[i, con_start + jj] == j:
                        slot = jj
                if slot < 0:
                    slot = at
                    at += 1
                else:
                    value = passive[v]
                    rhs[slot, i] = value
                    fulls[K + 3, slot, i] = value
                for a in range(n):
                    value = jac_t[a, v] * sign
                    fulls[slot, a, i] = value
                    if slot < c_i:
                        rows[slot, a, i] = value
            if shared:
                offsets[0, i], offsets[1, i], offsets[2, i] = d0, d1, d2
                state[i] = rank * (K + 4) + m_c
                continue
            for j in range(nb):
                axis = chain_ints[i, ball_start + j]
                fulls[K + 3, c_i + j, i] = 0.0
                for a in range(n):
                    value = ball_entry(axis, axis_rows[a], d0, d1, d2)
                    fulls[c_i + j, a, i] = value
                    rows[c_i + j, a, i] = value
            state[i] = rank * (K + 4) + m_c
            continue
        for j in range(k_i):
            v, sign = chain_ints[i, HEADER + j], chain_signs[i, j]
            for a in range(n):
                columns[j, a] = jac_t[a, v] * sign
        for j in range(nb):
            axis = chain_ints[i, ball_start + j]
            for a in range(n):
                columns[k_i + j, a] = ball_entry(axis, axis_rows[a], d0, d1, d2)
        # rows: own constrained joints, ball axes, null directions
        for j in range(c_i):
            position = chain_ints[i, con_start + j]
            rhs[j, i] = passive[chain_ints[i, HEADER + position]]
            for a in range(n):
                rows[j, a, i] = columns[position, a]
        for j in range(nb):
            for a in range(n):
                rows[c_i + j, a, i] = columns[k_i + j, a]
        ratio = 1.0
        if rank > 0:
            null = null_buffer[: n - rank]
            full = columns[: k_i + nb].T
            ratio = null_rows(full, rank, null, work, basis, used, vec, best_vec)
        if ratio < worst:
            worst, worst_chain = ratio, i
        for j in range(n - rank):
            for a in range(n):
                rows[c_i + nb + j, a, i] = null_buffer[j, a]
    if shared:
        shared_ball_columns(chain_ints[0], ball_start, axis_rows, offsets, fulls, rows)
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
        ratio_b = np.empty(count)
        bound_b = np.empty(count)
        if count == p:  # every chain: in place (fulls is overwritten by the QR)
            full_rank_batch(
                fulls,
                c_b,
                m_c,
                fulls[K + 3],
                ratio_b,
                bound_b,
                projectors,
                particular,
                rows[m_c : m_c + n - c_b],
            )
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
            proj_b = np.empty((n, n, count))
            part_b = np.empty((n, count))
            null_b = np.empty((n - c_b, n, count))
            full_rank_batch(q_b, c_b, m_c, t_b, ratio_b, bound_b, proj_b, part_b, null_b)
            for b in range(count):
                chain = members[b]
                for r in range(n):
                    particular[r, chain] = part_b[r, b]
                    for a in range(n):
                        projectors[r, a, chain] = proj_b[r, a, b]
                for j in range(n - c_b):
                    for a in range(n):
                        rows[m_c + j, a, chain] = null_b[j, a, b]
        for b in range(count):
            chain = members[b]
            state[chain] = -2
            if ratio_b[b] < worst:
                worst, worst_chain = ratio_b[b], chain
            if bound_b[b] > ILL_CONDITIONED:
                ill = True
    if worst < NEAR_SINGULAR:
        return Distributed(out, 0.0, 0.0, 0.0, 1, worst, worst_chain)
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
                    value = torque_signs[t, 0, i] * jac_t[a, va]
                    if vb >= 0:
                        value -= torque_signs[t, 1, i] * jac_t[a, vb]
                    hard[index, i, a] = value
            hard_rhs[index] = passive[va] if kind == 0 else 0.0
            index += 1
    kept = np.flatnonzero(keep)
    if ill:
        status = 2  # a chain's rows are ill-conditioned: numpy decides
    elif mode == 0:
        status = minimum_norm(
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
        status = partitioned_solve(
            rows, rhs, chain_ints, cfs_start, free_start, hard, hard_rhs, wrench, kept, plan, forces
        )
    if status == 0 and constraint_error(rows, rhs, hard, hard_rhs, forces) > CONSTRAINT_TOL:
        status = 2  # an ill-conditioned elimination lost an exact row: numpy decides
    if status != 0:
        return Distributed(out, 0.0, 0.0, 0.0, status, worst, worst_chain)
    for i in range(p):
        k_i = chain_ints[i, K_COLS]
        for j in range(k_i):
            v = chain_ints[i, HEADER + j]
            acc = 0.0
            for a in range(n):
                acc += jac_t[a, v] * forces[i, a]
            tau[v] += chain_signs[i, j] * acc * springs[v, 4]
        for a in range(n):
            produced[a] += forces[i, a]
    residual, scale, rounding = close_norms(keep, wrench, out[: p * n], produced, requested)
    if not (np.isfinite(residual) and np.isfinite(rounding)):
        return Distributed(out, 0.0, 0.0, 0.0, 3, worst, worst_chain)
    return Distributed(out, residual, scale, rounding, 0, worst, worst_chain)

__all__ = ["Distributed", "distribute"]
