"""Walking gaits of the seeds' robots: a controller driven by a state machine.

`Gait` is the common machinery; `TurkeyWalker` (Spring Turkey, VMC 5-6),
`FlamingoWalker` (Spring Flamingo, blind walking over slopes) and `HexapodWalker`
(the 1996 hexapod's tripod gait, VAC 4) are the gaits, each with its parameters dataclass; the
hexapod's paths and tracking are `VelocityCommand`, `SinePath` and
`TrackObject`.
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
