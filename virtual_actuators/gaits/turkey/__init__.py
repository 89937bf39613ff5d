"""Turkey walking (VMC section 5): Spring Turkey's level-ground gait."""

from .parameters import TurkeyParameters
from .walker import TurkeyWalker

__all__ = ["TurkeyParameters", "TurkeyWalker"]
