"""What the QP's stages share: the iteration budget, a ProxQP workspace slot, the rows."""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np


class Budget:
    """ProxQP (outer) iterations one solve has left (``left``), all stages together."""

    __slots__ = ("left",)

    def __init__(self, left: int) -> None:
        self.left = left

    def charge(self, used: int) -> None:
        """Take ``used`` iterations off (never below zero)."""
        self.left -= min(used, self.left)


class ProxSlot:
    """One ProxQP workspace of this thread, and whether its next solve needs ``init``.

    Args:
        qp: The ``proxqp.dense.QP`` (None until ProxQP first runs on this slot).
        fresh: True until a solve succeeded (and after a failure): start from ``init``.

    Attributes:
        active: The inequalities' multipliers of the last certified answer, or None.
    """

    __slots__ = ("active", "fresh", "qp")

    def __init__(self, qp: object, fresh: bool = True) -> None:
        self.qp = qp
        self.fresh = fresh
        self.active: np.ndarray | None = None


class StageRows:
    """The scaled rows of one solve, shared by its stages.

    Args:
        equality: The ``design`` rows that always hold, then the request's rows.
        equality_rhs: Their right-hand sides (the request's part is rewritten in place by the
            closest-wrench stages).
        design: How many of ``equality``'s rows always hold.
        inequality: The inequality rows.
        lows: Their lower bounds.
        uppers: Their upper bounds.
    """

    __slots__ = ("design", "equality", "equality_rhs", "inequality", "lows", "uppers")

    def __init__(self, equality, equality_rhs, design, inequality, lows, uppers) -> None:
        self.equality, self.equality_rhs, self.design = equality, equality_rhs, design
        self.inequality, self.lows, self.uppers = inequality, lows, uppers


class StageAnswer(NamedTuple):
    """What `ProxStages.solve` hands back.

    Attributes:
        x: The answer (scaled).
        multipliers: The inequalities' multipliers.
        exhausted: The budget ran out before the last stage converged (``x`` is then the
            feasible point of least weighted miss found).
    """

    x: np.ndarray
    multipliers: np.ndarray
    exhausted: bool


__all__ = ["Budget", "ProxSlot", "StageAnswer", "StageRows"]


class PlanTables(NamedTuple):
    """What a compiled plan runs a request with on the last certified active set."""

    core: Any  # the core's ``QP``
    workspace: Any  # this thread's workspace (its buffer the core's scratch)
    keep: np.ndarray  # the kept request rows, 0/1 integers
    weights: np.ndarray  # the kept rows' weights
    tolerances: np.ndarray  # (active, exact, accuracy)
    slot: Any  # the slot whose ``active`` is the warm start
