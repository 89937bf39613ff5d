"""The contact-aware distribution as a quadratic program (``solve(..., method="qp")``)."""

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
