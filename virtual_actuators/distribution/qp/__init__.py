"""The contact-aware distribution as a quadratic program (``solve(..., method="qp")``).

``solver.py`` is `QPDistribution` (its matrices on the numpy path, the answer),
``stages.py`` the stages (DAQP and ProxQP) with ``stage_types.py`` their budget, rows and
answer, ``limits.py`` the inequalities,
``weights.py`` the closest-wrench weights, ``compiled.py`` with ``buffer.py`` the compiled
core's matrices, ``exact.py`` the exact step on an active set,
``conflict.py`` the rows that cannot hold.
"""

from .conflict import CONFLICT_MAX_ITER
from .limits import ContactLimits, torque_map
from .solver import QPDistribution
from .stages import BUDGET_EXHAUSTED, EXACT_MAX_ITER, ITERATION_BUDGET
from .weights import check_weights

__all__ = [
    "BUDGET_EXHAUSTED",
    "CONFLICT_MAX_ITER",
    "EXACT_MAX_ITER",
    "ITERATION_BUDGET",
    "ContactLimits",
    "QPDistribution",
    "check_weights",
    "torque_map",
]
