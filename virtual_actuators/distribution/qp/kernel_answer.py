"""Compiled checks and read-out of a solved reduced QP (see :mod:`.kernels`).

:func:`violation` measures how far ProxQP's answer misses the rows it must meet (an infeasible
request can look solved to the solver's accuracy); :func:`finish` turns the answer in free
coordinates into the chains' forces, the joint torques and the active inequalities, in one call
and one output array, and closes the tick with the shared tail
(:func:`~virtual_actuators.distribution.result.close_norms`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ...kinematics.kernels import njit
from ..result import close_norms
from .kernels import views


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
    """What :func:`finish` hands back.

    The tick's buffer and norms (:meth:`.TickResult.from_buffer`; the rounding includes the
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
        buffer: The tick's workspace (see :func:`reduced_qp`).
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
        The :class:`Answer` (its tail by
        :func:`~virtual_actuators.distribution.result.close_norms`).

    """
    n = wrench.shape[0]
    arrays = views(buffer, layout, pn, nv)
    basis, x0, tmap, tau0 = arrays.basis, arrays.x0, arrays.tmap, arrays.tau0
    passive = arrays.passive
    out = np.zeros(pn + 2 * nv + 2 * n)
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
        count += abs(multipliers[r]) > active_tol
    active = np.empty(count, dtype=np.int64)
    count = 0
    for r in range(multipliers.shape[0]):
        if abs(multipliers[r]) > active_tol:
            active[count] = r
            count += 1
    return Answer(out, residual, size, rounding + accuracy * 10.0 * scale, active)

__all__ = ["Answer", "finish", "violation"]
