"""Design constraints (VAC eq. 16, 19; VMC eq. 12): extra equations that pick a distribution.

A *label* names one entry of the force distribution: ``(reaction_frame, axis)``, e.g.
``("FR_FOOT", "x")`` is the x force that the chain ending at ``FR_FOOT`` exerts on the action
frame.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

Label = tuple[str, str]


class DesignConstraint:
    """Base class of the design constraints accepted by ``ParallelVirtualActuator(design=...)``."""

    def labels(self) -> list[Label]:
        """Return the force entries this constraint involves (empty for torque constraints)."""
        return []


@dataclass(frozen=True)
class Equal(DesignConstraint):
    """Two force entries are equal: ``force[a] == force[b]`` (e.g. VAC eq. 26, ``f_x3 = f_x2``).

    Attributes:
        a: First label ``(reaction, axis)``.
        b: Second label ``(reaction, axis)``.

    """

    a: Label
    b: Label

    def labels(self) -> list[Label]:
        """Return both labels."""
        return [self.a, self.b]

    def __repr__(self) -> str:
        return f"Equal({self.a!r}, {self.b!r})"


@dataclass(frozen=True)
class Linear(DesignConstraint):
    """A linear equation over force entries: ``sum(coeff * force[label]) == rhs``.

    Example: ``Linear({("FL_FOOT", "y"): 1.0, ("FR_FOOT", "y"): -2.0}, rhs=0.0)`` is VAC eq. 26's
    ``f_y1 = 2 f_y2``.

    Attributes:
        coefficients: Map from label ``(reaction, axis)`` to its coefficient.
        rhs: Right-hand side [N or N m].

    """

    coefficients: Mapping[Label, float]
    rhs: float = 0.0

    def labels(self) -> list[Label]:
        """Return the labels with a coefficient."""
        return list(self.coefficients)

    def __hash__(self) -> int:
        return hash((tuple(self.coefficients.items()), self.rhs))

    def __repr__(self) -> str:
        terms = ", ".join(f"{k!r}: {v:g}" for k, v in self.coefficients.items())
        return f"Linear({{{terms}}}, rhs={self.rhs:g})"


@dataclass(frozen=True)
class EqualTorque(DesignConstraint):
    """Two joints get the same effort: ``tau[joint_a] == tau[joint_b]`` (VMC eq. 12).

    The torque of a joint is linear in the chains' forces through the Jacobians, so this
    constraint depends on the configuration and is re-evaluated at every solve.

    Attributes:
        joint_a: Name of the first joint (one degree of freedom, on a chain of the actuator).
        joint_b: Name of the second joint.

    """

    joint_a: str
    joint_b: str

    def __repr__(self) -> str:
        return f"EqualTorque({self.joint_a!r}, {self.joint_b!r})"
