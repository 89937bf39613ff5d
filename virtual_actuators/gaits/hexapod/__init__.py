"""The 1996 hexapod's tripod gait (VAC section 4): walker, body components, walk."""

from .parameters import HexapodParameters
from .walker import HexapodWalker

__all__ = ["HexapodParameters", "HexapodWalker"]
