"""Standing balance for any legged robot: the body on the contact QP, a posture, pushes."""

from ..push import Push
from .balancer import BalanceParameters, Balancer
from .walk import BalanceResult, run_balance

__all__ = ["BalanceParameters", "BalanceResult", "Balancer", "Push", "run_balance"]
