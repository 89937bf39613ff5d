"""Design constraints (VAC eq. 16, 19; VMC eq. 12): extra equations that pick a distribution.

A *label* ``(reaction_frame, axis)`` names one entry of the distribution: ``("FR_FOOT", "x")``
is the x force that the chain ending at ``FR_FOOT`` exerts on the action frame.
"""

from __future__ import annotations

import numbers
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..exceptions import ConstraintError, InvalidAxisError
from .arguments import check_name, describe
from .axes import AXES

Label = tuple[str, str]


def check_label(label: object, what: str) -> Label:
    """Return ``label`` as a ``(reaction, axis)`` tuple of str; ``what`` says where it was given.

    Raises:
        ConstraintError: ``label`` is not a pair of str.
        InvalidAxisError: Its axis is not one of ``x y z rx ry rz``.
    """
    if not (isinstance(label, (tuple, list)) and len(label) == 2):
        raise ConstraintError(
            f"{what} must be a label (reaction_frame, axis) such as ('FL_FOOT', 'x'), got "
            f"{describe(label)}."
        )
    reaction, axis = label
    check_name(reaction, f"{what}: the reaction frame of {tuple(label)!r}", ConstraintError)
    if axis not in AXES:
        raise InvalidAxisError(
            f"{what}: the axis of label {tuple(label)!r} must be one of {AXES}, got {axis!r}."
        )
    return (str(reaction), str(axis))


def _real(value: object, what: str) -> float:
    """``value`` as a float if it is a real number (not a bool, a complex or a str)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise ConstraintError(f"{what} must be a real number, got {describe(value)}.")
    return float(value)


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

    Raises:
        ConstraintError: A label is not a ``(reaction, axis)`` pair of str.
        InvalidAxisError: A label's axis is not one of ``x y z rx ry rz``.
    """

    a: Label
    b: Label

    def __post_init__(self) -> None:
        object.__setattr__(self, "a", check_label(self.a, "Equal: a"))
        object.__setattr__(self, "b", check_label(self.b, "Equal: b"))

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

    Raises:
        ConstraintError: ``coefficients`` is not a dict from labels to real numbers, or ``rhs``
            is not a real number (an empty dict and NaN or inf values are rejected when an
            actuator is declared with the constraint).
        InvalidAxisError: A label's axis is not one of ``x y z rx ry rz``.
    """

    coefficients: Mapping[Label, float]
    rhs: float = 0.0

    def __post_init__(self) -> None:
        if not isinstance(self.coefficients, Mapping):
            raise ConstraintError(
                "Linear: coefficients must be a dict {(reaction_frame, axis): coefficient}, got "
                f"{describe(self.coefficients)}."
            )
        coefficients: dict[Label, float] = {}
        for label, value in self.coefficients.items():
            label = check_label(label, "Linear: a key of coefficients")
            coefficients[label] = _real(value, f"Linear: the coefficient of {label!r}")
        object.__setattr__(self, "coefficients", coefficients)
        object.__setattr__(self, "rhs", _real(self.rhs, "Linear: rhs"))

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

    Attributes:
        joint_a: Name of the first joint (one degree of freedom, on a chain of the actuator).
        joint_b: Name of the second joint.

    Raises:
        ConstraintError: A joint name is not a str.
    """

    joint_a: str
    joint_b: str

    def __post_init__(self) -> None:
        check_name(self.joint_a, "EqualTorque: joint_a", ConstraintError)
        check_name(self.joint_b, "EqualTorque: joint_b", ConstraintError)

    def __repr__(self) -> str:
        return f"EqualTorque({self.joint_a!r}, {self.joint_b!r})"
