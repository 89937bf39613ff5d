"""Compiled checks and read-out of a solved reduced QP (see `kernels`).

`violation` measures how far ProxQP's answer misses the rows it must meet (an infeasible
request can look solved to the solver's accuracy); `finish` turns the answer in free
coordinates into the chains' forces, the joint torques and the active inequalities, in one call
and one output array, and closes the tick with the shared tail
(`close_norms`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ...kinematics.kernels import njit
from ..result import close_norms
from .exact import EXACT_STEPS, exact_step
from .kernels import LAYOUT, reduced_qp, views


@njit(cache=True)
def violation(
    buffer: np.ndarray, layout: np.ndarray, pn: int, nv: int, z: np.ndarray, equalities: int
) -> float:
    """Largest miss of ``z`` (scaled) on the rows it must meet.

    Those are the first ``equalities`` equality rows and every inequality row (``-inf`` for
    none; a non-finite ``z`` gives ``inf``).
    """
    arrays = views(buffer, layout, pn, nv)
    equality, equality_rhs = arrays.equality, arrays.equality_rhs
    inequality, lows, uppers = arrays.inequality, arrays.lows, arrays.uppers
    worst = -np.inf
    for r in range(equalities):
        acc = -equality_rhs[r]
        for j in range(z.shape[0]):
            acc += equality[r, j] * z[j]
        worst = max(worst, abs(acc))
    for r in range(lows.shape[0]):
        acc = 0.0
        for j in range(z.shape[0]):
            acc += inequality[r, j] * z[j]
        worst = max(worst, lows[r] - acc, acc - uppers[r])
    for j in range(z.shape[0]):
        if not np.isfinite(z[j]):
            return np.inf
    return worst


class Answer(NamedTuple):
    """What `finish` hands back.

    The tick's buffer and norms (`TickResult.from_buffer`; the rounding includes the
    solver's accuracy) and the indices of the active inequalities.
    """

    out: np.ndarray
    residual: float
    scale: float
    rounding: float
    active: np.ndarray


@njit(cache=True)
def finish(
    buffer: np.ndarray,
    layout: np.ndarray,
    pn: int,
    nv: int,
    z: np.ndarray,
    multipliers: np.ndarray,
    scale: float,
    wrench: np.ndarray,
    keep: np.ndarray,
    active_tol: float,
    accuracy: float,
) -> Answer:
    """Forces and torques of the answer ``z`` (scaled) and what the solution reports.

    Args:
        buffer: The tick's workspace (see `reduced_qp`).
        layout: Its layout.
        pn: ``p n``.
        nv: Velocity dimension.
        z: ``(d,)`` the QP's answer (scaled).
        multipliers: ``(m,)`` the inequalities' multipliers.
        scale: The tick's scale.
        wrench: ``(n,)`` the request.
        keep: ``(n,)`` 1 for prescribed axes.
        active_tol: A multiplier above this marks its row active.
        accuracy: The solver's absolute accuracy on the scaled problem.

    Returns:
        The `Answer` (its tail by
        `close_norms`).

    """
    out = np.zeros(pn + 2 * nv + 2 * wrench.shape[0])
    active = np.empty(multipliers.shape[0], dtype=np.int64)
    count, norms = read_out(
        buffer, layout, pn, nv, z, multipliers, scale, wrench, keep, active_tol, accuracy, out,
        active,
    )  # fmt: skip
    return Answer(out, norms[0], norms[1], norms[2], active[:count].copy())


@njit(cache=True)
def read_out(
    buffer: np.ndarray, layout: np.ndarray, pn: int, nv: int, z: np.ndarray,
    multipliers: np.ndarray, scale: float, wrench: np.ndarray, keep: np.ndarray,
    active_tol: float, accuracy: float, out: np.ndarray, active: np.ndarray,
) -> tuple[int, tuple[float, float, float]]:
    """`finish` into ``out`` and ``active``.

    ``out`` (zeros) receives the forces, tau, the spring torques, the produced and the
    requested wrench; ``active`` the active rows first.

    Returns:
        ``(count of active rows, (residual, scale, rounding))``.

    """
    n = wrench.shape[0]
    arrays = views(buffer, layout, pn, nv)
    basis, x0, tmap, tau0 = arrays.basis, arrays.x0, arrays.tmap, arrays.tau0
    passive = arrays.passive
    forces = out[:pn]
    tau = out[pn : pn + nv]
    produced = out[pn + 2 * nv : pn + 2 * nv + n]
    requested = out[pn + 2 * nv + n :]
    free = z.shape[0]
    for r in range(pn):
        acc = 0.0
        for j in range(free):
            acc += basis[r, j] * z[j]
        forces[r] = x0[r] + acc * scale
        produced[r % n] += forces[r]
    for v in range(nv):
        acc = 0.0
        for j in range(free):
            acc += tmap[v, j] * z[j]
        tau[v] = tau0[v] + acc * scale
        out[pn + nv + v] = passive[v]
    residual, size, rounding = close_norms(keep, wrench, forces, produced, requested)
    count = 0
    for r in range(multipliers.shape[0]):
        if abs(multipliers[r]) > active_tol:
            active[count] = r
            count += 1
    return count, (residual, size, rounding + accuracy * 10.0 * scale)


@njit(cache=True)
def again(
    jacobian: np.ndarray, frames: np.ndarray, q: np.ndarray, wrench: np.ndarray,
    kept: np.ndarray, axis_rows: np.ndarray, frame_rows: np.ndarray, chain_ints: np.ndarray,
    chain_signs: np.ndarray, springs: np.ndarray, const_rows: np.ndarray,
    const_rhs: np.ndarray, normals_world: np.ndarray, frame_normals: np.ndarray,
    settings: np.ndarray, soles: np.ndarray, limited_v: np.ndarray, limits: np.ndarray,
    buffer: np.ndarray, layout: np.ndarray, pn: int, nv: int, keep: np.ndarray,
    weights: np.ndarray, guess: np.ndarray, active_tol: float, exact_tol: float,
    accuracy: float, out: np.ndarray, active: np.ndarray,
) -> tuple[int, tuple[float, float, float]]:
    """A tick on a known active set in one call: the matrices, the exact step, the read-out.

    `reduced_qp` (its arguments first, then ``pn``, ``nv``), then
    `exact_step` of the request exactly on the active set that ``guess`` names
    (the multipliers of the last certified answer, replaced in place by the new ones when
    certified), then `read_out` into ``out`` (zeros) and ``active``.

    Returns:
        `read_out`'s, with a count of -1 when the exact step did not certify the answer
        (or the matrices need the numpy path): nothing else is then meaningful.

    """
    status, _, scale = reduced_qp(
        jacobian, frames, q, wrench, kept, axis_rows, frame_rows, chain_ints, chain_signs,
        springs, const_rows, const_rhs, normals_world, frame_normals, settings, soles,
        limited_v, limits, buffer, layout,
    )  # fmt: skip
    if status != 0:
        return -1, (0.0, 0.0, 0.0)
    rows = views(buffer, layout, pn, nv)
    certified, z, multipliers = exact_step(
        rows.equality, rows.equality_rhs, layout[LAYOUT - 1], weights, rows.inequality,
        rows.lows, rows.uppers, guess, True, active_tol, exact_tol, EXACT_STEPS,
    )  # fmt: skip
    if not certified:
        return -1, (0.0, 0.0, 0.0)
    guess[:] = multipliers
    return read_out(
        buffer, layout, pn, nv, z, multipliers, scale, wrench, keep, active_tol, accuracy, out,
        active,
    )  # fmt: skip


__all__ = ["Answer", "again", "finish", "read_out", "violation"]
