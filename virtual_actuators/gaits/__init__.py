"""Walking gaits of the seeds' robots: a controller driven by a state machine.

:class:`Gait` is the common machinery; :class:`TurkeyWalker` (Spring Turkey, VMC 5-6),
:class:`FlamingoWalker` (Spring Flamingo, blind walking over slopes) and :class:`HexapodWalker`
(the 1996 hexapod's tripod gait, VAC 4) are the gaits, each with its parameters dataclass; the
hexapod's paths and tracking are :class:`VelocityCommand`, :class:`SinePath` and
:class:`TrackObject`.
"""

from .base import Gait
from .flamingo import FlamingoParameters, FlamingoWalker
from .hexapod import HexapodParameters, HexapodWalker, SinePath, TrackObject, VelocityCommand
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
