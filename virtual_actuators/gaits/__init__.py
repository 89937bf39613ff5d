"""Walking gaits of the seeds' robots: a controller driven by a state machine."""

from .base import Gait
from .flamingo import FlamingoParameters
from .hexapod import HexapodParameters

__all__ = ["FlamingoParameters", "Gait", "HexapodParameters"]
