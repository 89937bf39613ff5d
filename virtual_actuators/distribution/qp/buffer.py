"""The compiled core's reduced QP buffer (``src/core/qp.hpp``): its layout, views and answer.

The QP in the chains' free coordinates: per chain ``F_i = x0_i + N_i z_i``, ``N_i`` orthonormal.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

# columns of the per-chain integer table: counts, then the column blocks
K_COLS, C_CON, NB_BALL = 0, 1, 2
HEADER = 3
#: entries of the buffer layout: ten offsets, then d, s + k, m and s
LAYOUT = 14


class QPViews(NamedTuple):
    """The arrays of the core's reduced QP in its buffer, as views.

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


def views(buffer: np.ndarray, layout: np.ndarray, pn: int, nv: int) -> QPViews:
    """The arrays of the core's reduced QP in ``buffer``, as views (`QPViews`)."""
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


class Answer(NamedTuple):
    """The core's read-out of a solved reduced QP: the tick's buffer and norms, the active rows."""

    out: np.ndarray
    residual: float
    scale: float
    rounding: float
    active: np.ndarray


__all__ = ["HEADER", "LAYOUT", "Answer", "QPViews", "views"]
