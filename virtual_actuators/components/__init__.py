"""Virtual components (VMC section 3): springs, dampers and forces that act through actuators."""

from .base import Component
from .energy_tank import EnergyTank
from .gravity import GravityCompensation
from .posture import Posture
from .springs import ConstantForce, Damper, Inertance, Spring, SpringDamper
from .walking import DogtrackBunny, GrannyWalker, SwingLegLinkage

__all__ = [
    "Component",
    "ConstantForce",
    "Damper",
    "DogtrackBunny",
    "EnergyTank",
    "GravityCompensation",
    "GrannyWalker",
    "Inertance",
    "Posture",
    "Spring",
    "SpringDamper",
    "SwingLegLinkage",
]
