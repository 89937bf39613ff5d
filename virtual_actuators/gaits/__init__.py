"""Walking gaits of the seeds' planar bipeds: a controller driven by a state machine.

:class:`Gait` is the common machinery; :class:`TurkeyWalker` (Spring Turkey, VMC 5-6) and
:class:`FlamingoWalker` (Spring Flamingo, blind walking over slopes) are the two gaits, each
with its parameters dataclass.
"""

from .base import Gait
from .flamingo import FlamingoParameters, FlamingoWalker
from .turkey import TurkeyParameters, TurkeyWalker

__all__ = ["FlamingoParameters", "FlamingoWalker", "Gait", "TurkeyParameters", "TurkeyWalker"]
