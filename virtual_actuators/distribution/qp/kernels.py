"""Compiled per-tick matrices of the QP distribution, in the chains' free coordinates.

`reduced_qp` builds at one configuration, in one call, the matrices of the QP that
`QPDistribution` solves, with the natural constraints
eliminated instead of kept as equalities. Per chain ``i`` (every chain of full column rank: its
``k_i`` joint columns and ``nb_i`` point-contact columns ``[J_i, ball_i]`` independent), one
modified Gram-Schmidt pass (twice, for orthogonality to rounding) over the columns ordered
constraint columns first (own limp or passive joints, then the ball axes), free joints after,
gives ``Q = [Q_C, Q_F]`` and ``R``; then

- every ``F_i`` that meets the chain's natural rows is ``F_i = x0_i + N_i z_i`` with
  ``N_i = Q_F`` (``n x d_i``, orthonormal) and ``x0_i = Q_C R_CC^-T t_i`` (the least-norm
  solution of the rows, ``t_i`` the spring torques), and ``x0_i`` is orthogonal to ``N_i``, so
  ``|F|^2 = |x0|^2 + |z|^2``: the least-force objective stays the identity in ``z``;
- the request, the constant design rows, the friction pyramids, the soles and the torque limits
  become rows over ``z`` (``d = sum d_i`` unknowns: 12 for solo12 instead of 24, and no
  natural equality rows).

A chain whose Gram-Schmidt pivot falls below ``RANK_TOL`` times its largest column norm makes
the call return status 1: the tick goes to the numpy path (all rows as equalities), which is
also the reference the tests compare this one with.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ...contacts.flat import sole_rows
from ...contacts.point import face_rows, force_row, to_o
from ...kinematics.kernels import njit
from ..partitioned.kernel_linalg import ball_entry, offset_in_o, passive_torques, wrench_transform
from ..tolerances import INFINITY, RANK_TOL

# columns of the per-chain integer table: counts, then the column blocks
K_COLS, C_CON, NB_BALL = 0, 1, 2
HEADER = 3
#: entries of the buffer layout: ten offsets, then d, s + k, m and s
LAYOUT = 14


@njit(cache=True)
def _orthonormalise(columns: np.ndarray, count: int, r: np.ndarray) -> float:
    """Modified Gram-Schmidt, twice, on ``columns[:count]`` (rows are vectors) in place.

    Writes ``R`` into ``r`` and returns the smallest pivot over the largest column norm (0 when
    a column vanishes).
    """
    n = columns.shape[1]
    largest = 0.0
    for j in range(count):
        norm = 0.0
        for a in range(n):
            norm += columns[j, a] * columns[j, a]
        largest = max(largest, np.sqrt(norm))
    worst = np.inf
    for j in range(count):
        for b in range(j + 1):
            r[b, j] = 0.0
        for _ in range(2):
            for b in range(j):
                dot = 0.0
                for a in range(n):
                    dot += columns[b, a] * columns[j, a]
                r[b, j] += dot
                for a in range(n):
                    columns[j, a] -= dot * columns[b, a]
        norm = 0.0
        for a in range(n):
            norm += columns[j, a] * columns[j, a]
        norm = np.sqrt(norm)
        r[j, j] = norm
        if not (norm > 0.0 and largest > 0.0):
            return 0.0
        worst = min(worst, norm / largest)
        for a in range(n):
            columns[j, a] /= norm
    return worst


@njit(cache=True)
def reduced_qp(
    jacobian_world: np.ndarray,
    frames: np.ndarray,
    q: np.ndarray,
    wrench: np.ndarray,
    kept: np.ndarray,
    axis_rows: np.ndarray,
    frame_rows: np.ndarray,
    chain_ints: np.ndarray,
    chain_signs: np.ndarray,
    springs: np.ndarray,
    const_rows: np.ndarray,
    const_rhs: np.ndarray,
    normals_world: np.ndarray,
    frame_normals: np.ndarray,
    settings: np.ndarray,
    soles: np.ndarray,
    limited_v: np.ndarray,
    limits: np.ndarray,
    buffer: np.ndarray,
    layout: np.ndarray,
) -> tuple[int, float, float]:
    """One tick's QP in free coordinates (see the module docstring).

    Args:
        jacobian_world: ``(6, nv)`` world joint Jacobian of the snapshot.
        frames: ``(nf, 12)`` frame placements of the snapshot.
        q: ``(nq,)`` configuration (spring angles).
        wrench: ``(n,)`` requested wrench.
        kept: ``(k,)`` indices of the prescribed axes.
        axis_rows: ``(n,)`` rows of the selected axes among ``x y z rx ry rz``.
        frame_rows: ``(2 + p,)`` rows of {B}, {O} and each {A_i} in ``frames``.
        chain_ints: ``(p, HEADER + K + C + 3)``: ``k``, ``c``, ``nb``, then the velocity columns,
            the positions of the own constrained joints among them, the ball axes (0-2).
        chain_signs: ``(p, K)`` +1/-1 of each chain column.
        springs: ``(nv, 5)`` stiffness, rest angle, ``idx_q`` (-1: none), 1 for a (cos, sin)
            joint, 1 if actuated.
        const_rows: ``(s, p, n)`` constant design rows.
        const_rhs: ``(s,)`` their right-hand sides.
        normals_world: ``(p, 3)`` unit contact normals in the world.
        frame_normals: ``(p,)`` 1 where the contact normal is the reaction frame's own z axis
            (read from ``frames`` this tick; ``normals_world`` ignored there), else 0.
        settings: ``(4,)``: friction (< 0: none), least normal force, 1 to keep the normal row,
            the declaration's part of the scale (largest bound and constant right-hand side).
        soles: ``(p, 3)``: 1 for a sole, its half length and half width [m].
        limited_v: ``(t,)`` velocity indices of the torque-limited joints.
        limits: ``(t,)`` their limits [N m, N].
        buffer: The thread's workspace, overwritten: the arrays below, at ``layout``.
        layout: ``(LAYOUT,)`` offsets of the arrays in ``buffer``, then ``d``, ``s + k``, ``m``,
            ``s`` (see `views`).

    Returns:
        ``(status, worst ratio, scale)``: status 1 when a chain is (nearly) rank deficient
        (nothing else is valid). ``buffer`` holds the basis ``(p n, d)``, ``x0`` ``(p n,)``,
        the equality rows ``(s + k, d)`` (design rows first) and their right-hand sides, the
        inequality rows ``(m, d)``, lows and uppers (the right-hand sides and bounds divided by
        ``scale``), the torque map ``(nv, d)`` and the torques of ``x0`` (zero at limp and
        passive joints), and the spring torques ``(nv,)``.

    """
    n = axis_rows.shape[0]
    p = chain_ints.shape[0]
    nv = jacobian_world.shape[1]
    K = chain_signs.shape[1]
    C = chain_ints.shape[1] - HEADER - K - 3
    friction, min_normal, with_normal = settings[0], settings[1], settings[2] > 0.0
    force_axes = 0
    moment_axes = 0
    for a in range(n):
        force_axes += axis_rows[a] < 3
        moment_axes += axis_rows[a] >= 3
    faces = 0
    if force_axes:
        faces = (1 if with_normal else 0) + (4 if friction >= 0.0 else 0)
    s = const_rows.shape[0]
    buffer[:] = 0.0
    (basis, x0, equality, equality_rhs, inequality, lows, uppers, tmap, tau0, passive) = views(
        buffer, layout, p * n, nv
    )
    free, m_in = layout[LAYOUT - 4], layout[LAYOUT - 2]
    uppers[:] = INFINITY
    # -- the Jacobian in {O} at {B}'s origin, and the spring torques ---------------------------
    b, o = frame_rows[0], frame_rows[1]
    rot_o, transform = wrench_transform(frames, b, o)
    jac_t = np.zeros((n, nv))
    for a in range(n):
        row = axis_rows[a]
        for w in range(6):
            t = transform[row, w]
            if t != 0.0:
                for v in range(nv):
                    jac_t[a, v] += t * jacobian_world[w, v]
    passive_torques(springs, q, passive)
    # -- per chain: free basis, particular solution, its rows ---------------------------------
    columns = np.empty((K + 3, n))
    r_mat = np.empty((K + 3, K + 3))
    targets = np.empty(K + 3)
    face_o = np.empty((5, 3))
    normal_w = np.empty(3)
    worst = np.inf
    start = 0
    sole_row = p * faces
    for i in range(p):
        k_i, c_i, nb = chain_ints[i, K_COLS], chain_ints[i, C_CON], chain_ints[i, NB_BALL]
        d_i = k_i - c_i
        a_row = frame_rows[2 + i]
        d0, d1, d2 = offset_in_o(frames, b, a_row, rot_o)
        # columns in order: own constrained joints, ball axes, free joints
        at = c_i + nb
        for j in range(k_i):
            v, sign = chain_ints[i, HEADER + j], chain_signs[i, j]
            slot = -1
            for jj in range(c_i):
                if chain_ints[i, HEADER + K + jj] == j:
                    slot = jj
            if slot < 0:
                slot = at
                at += 1
            else:
                targets[slot] = passive[v]
            for a in range(n):
                columns[slot, a] = jac_t[a, v] * sign
        for j in range(nb):
            axis = chain_ints[i, HEADER + K + C + j]
            targets[c_i + j] = 0.0
            for a in range(n):
                columns[c_i + j, a] = ball_entry(axis, axis_rows[a], d0, d1, d2)
        ratio = _orthonormalise(columns, k_i + nb, r_mat)
        worst = min(worst, ratio)
        if not ratio >= RANK_TOL:
            return 1, worst, 1.0
        m_c = c_i + nb
        for j in range(m_c):  # R_CC^T y = t, forward; x0 = Q_C y
            acc = targets[j]
            for jj in range(j):
                acc -= r_mat[jj, j] * targets[jj]
            targets[j] = acc / r_mat[j, j]
            for a in range(n):
                x0[i * n + a] += targets[j] * columns[j, a]
        for j in range(d_i):
            for a in range(n):
                basis[i * n + a, start + j] = columns[m_c + j, a]
        chain_x0 = x0[i * n : (i + 1) * n]
        chain_basis = basis[i * n : (i + 1) * n, start : start + d_i]
        # torques: sign J_v^T (x0 + N z) at the chain's joints (zero at limp and passive ones)
        for j in range(k_i):
            v = chain_ints[i, HEADER + j]
            sign = chain_signs[i, j] * springs[v, 4]
            if sign == 0.0:
                continue
            acc = 0.0
            for a in range(n):
                acc += jac_t[a, v] * chain_x0[a]
            tau0[v] += sign * acc
            for jj in range(d_i):
                acc = 0.0
                for a in range(n):
                    acc += jac_t[a, v] * chain_basis[a, jj]
                tmap[v, start + jj] += sign * acc
        # the request and the design rows: sum_i F_i on the kept axes
        for r in range(kept.shape[0]):
            a = kept[r]
            for jj in range(d_i):
                equality[s + r, start + jj] = chain_basis[a, jj]
            equality_rhs[s + r] -= chain_x0[a]
        for t in range(s):
            for jj in range(d_i):
                acc = 0.0
                for a in range(n):
                    acc += const_rows[t, i, a] * chain_basis[a, jj]
                equality[t, start + jj] = acc
            acc = 0.0
            for a in range(n):
                acc += const_rows[t, i, a] * chain_x0[a]
            equality_rhs[t] -= acc
        # the pyramid about the normal, built in the world (the contact's, whatever {O} is) and
        # turned into {O}, on the chain's force entries
        for c in range(3):  # a frame normal: its z axis in the world, column 2 of its rotation
            normal_w[c] = frames[a_row, 3 * c + 2] if frame_normals[i] else normals_world[i, c]
        if faces:
            to_o(rot_o, face_o, face_rows(normal_w, friction, with_normal, face_o))
            for f in range(faces):
                row = i * faces + f
                force_row(face_o[f], axis_rows, chain_x0, chain_basis, inequality[row, start:],
                           lows, row, min_normal if (with_normal and f == 0) else 0.0)  # fmt: skip
        if moment_axes and soles[i, 0] > 0.0:
            sole_rows(frames[a_row], rot_o, soles[i], friction, (d0, d1, d2), axis_rows,
                       chain_x0, chain_basis, inequality[sole_row : sole_row + 6, start:],
                       lows[sole_row : sole_row + 6])  # fmt: skip
            sole_row += 6
        start += d_i
    scale = settings[3]
    for r in range(kept.shape[0]):
        equality_rhs[s + r] += wrench[kept[r]]
        scale = max(scale, abs(wrench[kept[r]]))
    for t in range(s):
        equality_rhs[t] += const_rhs[t]
    for v in range(nv):
        scale = max(scale, abs(passive[v]))
    for t in range(limited_v.shape[0]):  # -limit <= tau0 + T z <= limit
        v = limited_v[t]
        row = m_in - limited_v.shape[0] + t
        for j in range(free):
            inequality[row, j] = tmap[v, j]
        lows[row] = -limits[t] - tau0[v]
        uppers[row] = limits[t] - tau0[v]
    scale = max(scale, 1e-300)  # the request, spring torques and bounds to ~1
    for r in range(equality_rhs.shape[0]):
        equality_rhs[r] /= scale
    for r in range(m_in):  # bounds that do not set the scale may exceed "no bound": clipped
        lows[r] = max(lows[r] / scale, -INFINITY)
        uppers[r] = min(uppers[r] / scale, INFINITY) if uppers[r] < INFINITY else INFINITY
    return 0, worst, scale


class QPViews(NamedTuple):
    """The arrays of `reduced_qp` in its buffer, as views.

    Attributes:
        basis: ``(p n, d)`` the chains' null-space bases ``N``.
        x0: ``(p n,)`` the particular forces.
        equality: ``(s + k, d)`` the design rows, then the request's.
        equality_rhs: ``(s + k,)`` their right-hand sides (scaled).
        inequality: ``(m, d)`` the contact and torque-limit rows.
        lows: ``(m,)`` their lower bounds (scaled).
        uppers: ``(m,)`` their upper bounds (scaled).
        tmap: ``(nv, d)`` the torque map.
        tau0: ``(nv,)`` the torques of ``x0``.
        passive: ``(nv,)`` the spring torques.

    """

    basis: np.ndarray
    x0: np.ndarray
    equality: np.ndarray
    equality_rhs: np.ndarray
    inequality: np.ndarray
    lows: np.ndarray
    uppers: np.ndarray
    tmap: np.ndarray
    tau0: np.ndarray
    passive: np.ndarray


@njit(cache=True)
def views(buffer: np.ndarray, layout: np.ndarray, pn: int, nv: int) -> QPViews:
    """The arrays of `reduced_qp` in ``buffer``, as views (`QPViews`)."""
    free, rows_eq, m_in = layout[LAYOUT - 4], layout[LAYOUT - 3], layout[LAYOUT - 2]
    return QPViews(
        buffer[layout[0] : layout[0] + pn * free].reshape((pn, free)),
        buffer[layout[1] : layout[1] + pn],
        buffer[layout[2] : layout[2] + rows_eq * free].reshape((rows_eq, free)),
        buffer[layout[3] : layout[3] + rows_eq],
        buffer[layout[4] : layout[4] + m_in * free].reshape((m_in, free)),
        buffer[layout[5] : layout[5] + m_in],
        buffer[layout[6] : layout[6] + m_in],
        buffer[layout[7] : layout[7] + nv * free].reshape((nv, free)),
        buffer[layout[8] : layout[8] + nv],
        buffer[layout[9] : layout[9] + nv],
    )

__all__ = ["HEADER", "LAYOUT", "QPViews", "reduced_qp", "views"]
