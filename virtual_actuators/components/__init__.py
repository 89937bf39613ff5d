"""Virtual components (VMC section 3): springs, dampers and forces that act through actuators."""

from .base import Component
from .springs import ConstantForce, Damper, Spring, SpringDamper
from .walking import DogtrackBunny, GrannyWalker, SwingLegLinkage

__all__ = [
    "Component",
    "ConstantForce",
    "Damper",
    "DogtrackBunny",
    "GrannyWalker",
    "Spring",
    "SpringDamper",
    "SwingLegLinkage",
]
