"""Turkey walking (VMC section 5): Spring Turkey's level-ground gait."""

from .walker import TurkeyParameters, TurkeyWalker

__all__ = ["TurkeyParameters", "TurkeyWalker"]
