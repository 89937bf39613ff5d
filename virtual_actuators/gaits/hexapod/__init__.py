"""The 1996 hexapod's tripod gait (VAC section 4): walker, body components, guidance, walk."""

from ..guidance import SinePath, TrackObject, VelocityCommand
from .parameters import HexapodParameters
from .walker import LEGS, TRIPODS, HexapodWalker

__all__ = [
    "LEGS",
    "TRIPODS",
    "HexapodParameters",
    "HexapodWalker",
    "SinePath",
    "TrackObject",
    "VelocityCommand",
]
