"""Small dense linear algebra for the compiled distribution (numba, plain loops, no BLAS).

Products, Gauss-Jordan inverses with a condition estimate, the left null space of a chain's
Jacobian by pivoted Gram-Schmidt, and the a-posteriori check of the exact rows.
"""

from __future__ import annotations

import numpy as np

from ...kinematics.kernels import njit
from ..tolerances import JACOBIAN_FLOOR
from .kernel_tables import C_CON, NB_BALL


@njit(cache=True)
def mm(a: np.ndarray, b: np.ndarray) -> np.ndarray:
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
def mv(a: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Small matrix-vector product with plain loops."""
    out = np.zeros(a.shape[0])
    for r in range(a.shape[0]):
        acc = 0.0
        for k in range(a.shape[1]):
            acc += a[r, k] * x[k]
        out[r] = acc
    return out


@njit(cache=True)
def invert(matrix: np.ndarray) -> tuple[np.ndarray, float]:
    """Inverse by Gauss-Jordan with partial pivoting and ``||A||_inf ||A^-1||_inf``."""
    m = matrix.shape[0]
    inv = np.empty((m, m))
    cond = inverse_into(matrix, m, np.empty((m, m)), inv)
    return inv, cond


@njit(cache=True)
def inverse_into(matrix: np.ndarray, m: int, a: np.ndarray, inv: np.ndarray) -> float:
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
def scaled_condition(matrix: np.ndarray, inverse: np.ndarray, row_scale: np.ndarray) -> float:
    """``max(||D^-1 A||_inf, 1) ||A^-1 D||_inf`` with ``D = diag(row_scale)``.

    The rows of ``matrix`` measured against their sizes before a reduction, as in numpy's
    `scaled_condition` (inf for a zero scale).
    """
    m = matrix.shape[0]
    norm, norm_inv = 0.0, 0.0
    for i in range(m):
        if not row_scale[i] > 0.0:
            return np.inf
        row, row_inv = 0.0, 0.0
        for j in range(m):
            row += abs(matrix[i, j])
            row_inv += abs(inverse[i, j]) * row_scale[j]
        norm = max(norm, row / row_scale[i])
        norm_inv = max(norm_inv, row_inv)
    estimate = max(norm, 1.0) * norm_inv
    if not np.isfinite(estimate):
        estimate = np.inf
    return estimate


@njit(cache=True)
def null_rows(
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


@njit(cache=True)
def constraint_error(
    rows: np.ndarray,
    rhs: np.ndarray,
    hard: np.ndarray,
    hard_rhs: np.ndarray,
    forces: np.ndarray,
) -> float:
    """Largest miss of an exact row (natural or hard), relative to ``|row| |F| + |rhs|``.

    ``rows`` (l, n, p) and ``rhs`` (l, p) have the chain index last.
    """
    p, n = forces.shape
    peak = 0.0
    for i in range(p):
        for a in range(n):
            peak = max(peak, abs(forces[i, a]))
    worst = 0.0
    forces_t = forces.T.copy()  # side by side over the chains
    acc = np.empty(p)
    size = np.empty(p)
    for r in range(rows.shape[0]):
        for i in range(p):
            acc[i] = -rhs[r, i]
            size[i] = abs(rhs[r, i])
        for a in range(n):
            row, force = rows[r, a], forces_t[a]
            for i in range(p):
                acc[i] += row[i] * force[i]
                size[i] = max(size[i], abs(row[i]) * peak)
        for i in range(p):
            if size[i] > 0.0:
                worst = max(worst, abs(acc[i]) / size[i])
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
def ball_entry(axis: int, row: int, d0: float, d1: float, d2: float) -> float:
    """Entry ``row`` (``x y z rx ry rz``) of a point contact's column ``(e_axis x d, e_axis)``."""
    if row >= 3:
        return 1.0 if row - 3 == axis else 0.0
    if axis == 0:
        return (0.0, -d2, d1)[row]
    if axis == 1:
        return (d2, 0.0, -d0)[row]
    return (-d1, d0, 0.0)[row]


@njit(cache=True)
def offset_in_o(
    frames: np.ndarray, b: int, a: int, rot_o: np.ndarray
) -> tuple[float, float, float]:
    """``R_O^T (p_B - p_A)``: the offset from {A} to {B} in {O} (``b``, ``a``: frame rows)."""
    dx = frames[b, 9] - frames[a, 9]
    dy = frames[b, 10] - frames[a, 10]
    dz = frames[b, 11] - frames[a, 11]
    d0 = rot_o[0, 0] * dx + rot_o[1, 0] * dy + rot_o[2, 0] * dz
    d1 = rot_o[0, 1] * dx + rot_o[1, 1] * dy + rot_o[2, 1] * dz
    d2 = rot_o[0, 2] * dx + rot_o[1, 2] * dy + rot_o[2, 2] * dz
    return d0, d1, d2


@njit(cache=True)
def wrench_transform(frames: np.ndarray, b: int, o: int) -> tuple[np.ndarray, np.ndarray]:
    """``(R_O, T)``: {O}'s rotation and the map of world twists to {B}'s twist in {O}.

    ``T`` (6, 6) takes a twist at the world origin to ``(R_O^T (v - skew(p_B) w), R_O^T w)``,
    the twist of {B}'s origin in {O}; ``b``, ``o`` are rows of the frame table.
    """
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
            acc = 0.0
            for k in range(3):
                acc += rot_o[k, r] * shift[k, c]
            transform[r, 3 + c] = acc
    return rot_o, transform


@njit(cache=True)
def passive_torques(springs: np.ndarray, q: np.ndarray, passive: np.ndarray) -> None:
    """``passive[v] = -k (angle - rest)`` at the spring joints of the ``springs`` table."""
    for v in range(springs.shape[0]):
        if springs[v, 2] >= 0:
            iq = int(springs[v, 2])
            angle = np.arctan2(q[iq + 1], q[iq]) if springs[v, 3] > 0 else q[iq]
            passive[v] = -springs[v, 0] * (angle - springs[v, 1])


@njit(cache=True)
def shared_ball_columns(
    header: np.ndarray,
    ball_start: int,
    axis_rows: np.ndarray,
    offsets: np.ndarray,
    fulls: np.ndarray,
    rows: np.ndarray,
) -> None:
    """The ball columns of chains that share their ball axes, side by side over the chains.

    ``header`` is the first chain's row of the chain table; ``offsets`` (3, p) each chain's
    offset ``d`` from {A_i} to {B} in {O}. Writes the columns (QR order, after the own
    constrained joints) into ``fulls`` and the chains' rows.
    """
    c_i, nb = header[C_CON], header[NB_BALL]
    K = fulls.shape[0] - 4
    for j in range(nb):
        axis = header[ball_start + j]
        slot = c_i + j
        fulls[K + 3, slot, :] = 0.0
        for a in range(axis_rows.shape[0]):
            row = axis_rows[a]
            out, out_rows = fulls[slot, a], rows[slot, a]
            if row >= 3 or row == axis:
                value = 1.0 if row - 3 == axis else 0.0
                out[:] = value
                out_rows[:] = value
                continue
            # e_axis x d: entry row of (0, -d2, d1), (d2, 0, -d0) or (-d1, d0, 0)
            sign = 1.0 if (row - axis) % 3 == 2 else -1.0
            values = offsets[3 - axis - row]
            for i in range(values.shape[0]):
                out[i] = sign * values[i]
                out_rows[i] = out[i]


__all__ = [
    "ball_entry",
    "constraint_error",
    "invert",
    "inverse_into",
    "mm",
    "mv",
    "null_rows",
    "offset_in_o",
    "passive_torques",
    "shared_ball_columns",
    "scaled_condition",
    "wrench_transform",
]
