"""The force distribution problem: the declaration parsed, its structure, its checks."""

from .problem import DistributionProblem

__all__ = ["DistributionProblem"]
