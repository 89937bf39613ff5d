"""A gait layer for any robot with two or more legs (trot, pace, walk, tripod, n-pod)."""

from .parameters import LeggedGains, LeggedParameters
from .patterns import GaitPattern, named_pattern, npod
from .walker import LeggedWalker

__all__ = [
    "GaitPattern",
    "LeggedGains",
    "LeggedParameters",
    "LeggedWalker",
    "named_pattern",
    "npod",
]
