"""The contact-aware distribution as a quadratic program (``solve(..., method="qp")``)."""

from .solver import ContactLimits, QPDistribution, check_weights
from .stages import BUDGET_EXHAUSTED, CONFLICT_MAX_ITER, EXACT_MAX_ITER, ITERATION_BUDGET

__all__ = [
    "BUDGET_EXHAUSTED",
    "CONFLICT_MAX_ITER",
    "EXACT_MAX_ITER",
    "ITERATION_BUDGET",
    "ContactLimits",
    "QPDistribution",
    "check_weights",
]
