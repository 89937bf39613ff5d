"""Walking gaits of the seeds' robots: a controller driven by a state machine."""

from .base import Gait
from .flamingo import FlamingoParameters, FlamingoWalker
from .guidance import SinePath, TrackObject, VelocityCommand
from .hexapod import HexapodParameters, HexapodWalker
from .turkey import TurkeyParameters, TurkeyWalker

__all__ = [
    "FlamingoParameters",
    "FlamingoWalker",
    "Gait",
    "HexapodParameters",
    "HexapodWalker",
    "SinePath",
    "TrackObject",
    "TurkeyParameters",
    "TurkeyWalker",
    "VelocityCommand",
]
