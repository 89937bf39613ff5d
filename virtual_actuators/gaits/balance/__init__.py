"""Standing balance for any legged robot: the body on the contact QP, a posture, pushes."""

from .balancer import Balancer
from .parameters import BalanceParameters
from .walk import BalanceResult, Push, run_balance

__all__ = ["BalanceParameters", "BalanceResult", "Balancer", "Push", "run_balance"]
