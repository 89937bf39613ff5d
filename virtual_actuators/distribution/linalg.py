"""Small dense linear-algebra helpers shared by the solvers."""

from __future__ import annotations

import math

import numpy as np

from .tolerances import DEPENDENT_TOL, RCOND, TINY


def stable_norm(x: np.ndarray) -> float:
    """``||x||_2`` of an array of any shape, scaled by its peak: no over- or underflow.

    Returns:
        The norm (inf or NaN only if ``x`` holds them).
    """
    peak = float(np.abs(x).max(initial=0.0))
    if peak == 0.0 or not math.isfinite(peak):
        return peak
    y = x / peak
    return peak * math.sqrt(float(np.vdot(y, y)))


def power_of_two_scale(*arrays: np.ndarray) -> float:
    """A power of two ``f`` that brings the largest entry of ``arrays`` into ``[0.5, 1)``.

    Multiplying by ``f`` is exact (away from subnormals): no overflow or underflow, same bits.

    Returns:
        ``f`` (1.0 when every entry is zero or one is not finite).
    """
    peak = max((float(np.abs(a).max(initial=0.0)) for a in arrays), default=0.0)
    if peak == 0.0 or not math.isfinite(peak):
        return 1.0
    return math.ldexp(1.0, -math.frexp(peak)[1])


def backward_tolerance(rows: np.ndarray, x: np.ndarray, rhs: np.ndarray) -> float:
    """Largest ``||rows x - rhs||`` that rounding explains: ``1e-8 (|rhs| + |rows| |x|)``."""
    size = float(np.abs(rhs).max(initial=0.0))
    if rows.size and x.size:
        size += float(np.abs(rows).sum(axis=1).max()) * float(np.abs(x).max())
    return 1e-8 * size


def select_columns(matrix: np.ndarray, count: int, weights: np.ndarray | None = None) -> np.ndarray:
    """Indices of ``count <= cols`` well-conditioned columns, in the order picked (pivoted QR).

    ``weights``: ``(cols,)`` positive factors; a column of small weight is picked only when the
    others cannot do.
    """
    work = np.array(matrix, dtype=float, copy=True)
    if weights is not None:
        work = work * weights[None, :]
    picked: list[int] = []
    available = np.ones(work.shape[1], dtype=bool)
    for _ in range(count):
        norms = np.einsum("ij,ij->j", work, work)
        norms[~available] = -1.0
        j = int(np.argmax(norms))
        picked.append(j)
        available[j] = False
        column = work[:, j]
        norm = np.sqrt(max(norms[j], 0.0))
        if norm > 0.0:
            unit = column / norm
            work -= np.outer(unit, unit @ work)
    return np.array(picked, dtype=int)


def dependent_rows(matrix: np.ndarray) -> list[int]:
    """Indices of the rows that depend on the ones before (`DEPENDENT_TOL` of each row's norm)."""
    basis: list[np.ndarray] = []
    dependent = []
    for i, row in enumerate(np.asarray(matrix, dtype=float)):
        scale = np.linalg.norm(row)
        residual = row.copy()
        for b in basis:
            residual -= (b @ residual) * b
        norm = np.linalg.norm(residual)
        if scale == 0.0 or norm <= DEPENDENT_TOL * scale:
            dependent.append(i)
        else:
            basis.append(residual / norm)
    return dependent


def dependent_rows_at_scale(matrix: np.ndarray) -> bool:
    """Whether the rows of ``matrix``, each scaled to unit norm, are linearly dependent."""
    if not matrix.shape[0]:
        return False
    norms = np.linalg.norm(matrix, axis=1)
    if not norms.all() or matrix.shape[0] > matrix.shape[1]:
        return True
    s = np.linalg.svd(matrix / norms[:, None], compute_uv=False)
    return bool(s[-1] <= RCOND * s[0])


def safe_inverse(matrices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Inverses of stacked ``(..., k, k)`` matrices and their condition ``||A||_inf ||A^-1||_inf``.

    Returns:
        ``(inverses, conditions)``: NaN inverses and inf condition where one is singular.
    """
    try:
        inverses = np.linalg.inv(matrices)
    except np.linalg.LinAlgError:
        inverses = np.empty_like(matrices)
        count = int(np.prod(matrices.shape[:-2]))  # (-1 fails on 0 x 0 blocks)
        flat_in = matrices.reshape(count, *matrices.shape[-2:])
        flat_out = inverses.reshape(count, *matrices.shape[-2:])
        for i, m in enumerate(flat_in):
            try:
                flat_out[i] = np.linalg.inv(m)
            except np.linalg.LinAlgError:
                flat_out[i] = np.nan
    norm = np.abs(matrices).sum(axis=-1).max(axis=-1, initial=0.0)  # 0 x 0: condition 0
    estimate = norm * np.abs(inverses).sum(axis=-1).max(axis=-1, initial=0.0)
    return inverses, np.where(np.isfinite(estimate), estimate, np.inf)


def scaled_condition(matrix: np.ndarray, inverse: np.ndarray, row_scale: np.ndarray) -> float:
    """Condition ``max(||D^-1 A||_inf, 1) ||A^-1 D||_inf`` of ``A`` (``inverse`` its inverse).

    ``D = diag(row_scale)``: the rows' positive sizes before a reduction; inf if not finite.
    """
    scaled = float(np.abs(matrix / row_scale[:, None]).sum(axis=1).max(initial=0.0))
    scaled_inverse = float(np.abs(inverse * row_scale[None, :]).sum(axis=1).max(initial=0.0))
    estimate = max(scaled, 1.0) * scaled_inverse
    return estimate if np.isfinite(estimate) else np.inf


def constrained_min_norm(
    hard: np.ndarray,
    hard_rhs: np.ndarray,
    soft: np.ndarray,
    soft_rhs: np.ndarray,
    hard_scale: float = 0.0,
    soft_scale: float = 0.0,
) -> tuple[np.ndarray, float]:
    """Minimise ``||x||`` among minimisers of ``||soft x - soft_rhs||`` with ``hard x = hard_rhs``.

    Args:
        hard: ``(h, m)`` rows that must hold exactly.
        hard_rhs: ``(h,)``.
        soft: ``(s, m)`` rows met in the least-squares sense.
        soft_rhs: ``(s,)``.
        hard_scale: Singular values of ``hard`` at most ``RCOND * max(largest, hard_scale)``
            are dropped (the rows' size before a reduction); 0 for the rows' own scale.
        soft_scale: The same floor for the soft rows (in the null space of ``hard``).

    Returns:
        ``(x, hard_residual)``: the solution and ``||hard x - hard_rhs||``.
    """
    m = soft.shape[1] if soft.size else hard.shape[1]
    if hard.shape[0]:
        u, s, vt = np.linalg.svd(hard, full_matrices=True)
        floor = RCOND * max(float(s[0]) if s.size else 0.0, hard_scale, TINY)
        rank = int(np.sum(s > floor))
        x_h = vt[:rank].T @ ((u[:, :rank].T @ hard_rhs) / s[:rank])
        null = vt[rank:].T
    else:
        x_h = np.zeros(m)
        null = np.eye(m)
    if soft.shape[0] and null.shape[1]:
        reduced = soft @ null
        target = soft_rhs - soft @ x_h
        if soft_scale > 0.0:
            u, s, vt = np.linalg.svd(reduced, full_matrices=False)
            rank = int(np.sum(s > RCOND * max(float(s[0]) if s.size else 0.0, soft_scale)))
            z = vt[:rank].T @ ((u[:, :rank].T @ target) / s[:rank])
        else:
            z = np.linalg.lstsq(reduced, target, rcond=RCOND)[0]
        x = x_h + null @ z
    else:
        x = x_h
    hard_residual = stable_norm(hard @ x - hard_rhs) if hard.shape[0] else 0.0
    return x, hard_residual
