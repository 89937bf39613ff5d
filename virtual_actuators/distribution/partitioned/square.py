"""The square reduced system's plan: which free entries the design rows fix (VAC eq. 16-18)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..linalg import safe_inverse, scaled_condition, select_columns
from ..tolerances import ILL_CONDITIONED


@dataclass
class SquarePlan:
    """Cached RFS/MFS choice for a square reduced system and one set of free axes."""

    rfs: np.ndarray
    mfs: np.ndarray
    gain: np.ndarray | None = None  # -H_r^-1 H_m when the hard rows are constant
    rfs_inverse: np.ndarray | None = None  # H_r^-1 when the hard rows are constant


def plan_square(h: np.ndarray, m: int, constant: bool = True) -> SquarePlan:
    """The RFS (``s`` columns of the hard rows ``h`` by pivoted QR) and the MFS (the rest).

    Args:
        h: ``(s, m)`` reduced hard rows.
        m: Number of reduced unknowns.
        constant: The hard rows do not depend on the configuration: factor the gain once.
    """
    s = h.shape[0]
    rfs = np.sort(select_columns(h, s)) if s else np.array([], dtype=int)
    mfs = np.setdiff1d(np.arange(m), rfs)
    plan = SquarePlan(rfs=rfs, mfs=mfs)
    if s and constant:
        inverse, cond = safe_inverse(h[:, rfs])
        if cond < ILL_CONDITIONED:
            plan.gain = -inverse @ h[:, mfs]
            plan.rfs_inverse = inverse
    return plan


def rfs_gain(
    h: np.ndarray, h_rhs: np.ndarray, plan: SquarePlan, scale: np.ndarray
) -> tuple[np.ndarray | None, np.ndarray | None]:
    """``(gain, bias)`` of ``f_r = gain f_m + bias`` here; ``(None, None)``: ill-conditioned."""
    block = h[:, plan.rfs]
    inverse, cond = safe_inverse(block)
    if cond > ILL_CONDITIONED or not scale.all():
        return None, None
    if scaled_condition(block, inverse, scale) > ILL_CONDITIONED:
        return None, None
    return -inverse @ h[:, plan.mfs], inverse @ h_rhs
