"""Linear inequalities over the stacked reaction forces, with a name per row."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True, slots=True)
class Constraint:
    """``lows <= G x <= uppers`` over ``x = forces.ravel()`` (``p n`` entries), a name a row.

    Attributes:
        G: ``(m, p n)`` the rows.
        lows: ``(m,)`` their lower bounds.
        uppers: ``(m,)`` their upper bounds (``INFINITY`` for one-sided rows).
        names: ``m`` names, one per row (what the conflict error reports).

    """

    G: np.ndarray
    lows: np.ndarray
    uppers: np.ndarray
    names: Sequence[str]

    @staticmethod
    def empty(width: int) -> Constraint:
        """No row over ``width`` entries."""
        return Constraint(np.zeros((0, width)), np.zeros(0), np.zeros(0), [])


__all__ = ["Constraint"]
