"""The contact-aware distribution as a quadratic program (``solve(..., method="qp")``)."""

from .solver import ContactLimits, QPDistribution, check_weights

__all__ = ["ContactLimits", "QPDistribution", "check_weights"]
