"""Gait patterns as data: which feet swing together, and in which order.

Every foot has the phase of the cycle (0 to 1) at which its swing starts; feet with the same
phase form a *swing group*. The named patterns are described in the legged reference page.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ...exceptions import GaitPatternError, InvalidInputError

PATTERNS = ("trot", "pace", "walk", "tripod")

#: A pace's swing time in units of ``sqrt(h / g)`` (the others': 1): short, as the centre of
#: mass off the support line falls sideways as an inverted pendulum.
PACE_SWING_TIME = 0.3

#: A pace's stance width, a fraction of the standing pose's (the support line nearer the CoM).
PACE_WIDTH = 0.6


@dataclass(frozen=True)
class GaitPattern:
    """Phase offsets per foot: when in the cycle each foot's swing starts.

    Attributes:
        name: Label.
        offsets: ``{foot: phase in [0, 1)}``.
        swing_time: Duration of a swing in units of ``sqrt(h / g)`` [-].
        width: The stance's width across the heading, a fraction of the standing pose's [-].

    Raises:
        InvalidInputError: Fewer than two feet, an offset outside ``[0, 1)``, or a swing time
            or width out of range.
    """

    name: str
    offsets: Mapping[str, float]
    swing_time: float = 1.0
    width: float = 1.0

    def __post_init__(self) -> None:
        if len(self.offsets) < 2:
            raise InvalidInputError(
                f"Gait pattern {self.name!r} needs two or more feet, got {list(self.offsets)}."
            )
        for foot, phase in self.offsets.items():
            if not 0.0 <= float(phase) < 1.0:
                raise InvalidInputError(
                    f"Gait pattern {self.name!r}: the phase of {foot!r} must be in [0, 1), "
                    f"got {phase}."
                )
        if not (self.swing_time > 0.0 and 0.0 < self.width <= 1.0):
            raise InvalidInputError(
                f"Gait pattern {self.name!r}: swing_time must be > 0 and width in (0, 1], got "
                f"{self.swing_time}, {self.width}."
            )

    @property
    def feet(self) -> tuple[str, ...]:
        """The feet, in the order given."""
        return tuple(self.offsets)

    def groups(self) -> tuple[tuple[str, ...], ...]:
        """The swing groups in cycle order: feet with equal phases swing together."""
        phases = sorted({round(float(p), 9) for p in self.offsets.values()})
        return tuple(
            tuple(f for f, p in self.offsets.items() if round(float(p), 9) == phase)
            for phase in phases
        )

    def swinging(self, phase: float) -> tuple[str, ...]:
        """The feet swinging at ``phase`` of the cycle (each group owns an equal slot)."""
        groups = self.groups()
        return groups[int((phase % 1.0) * len(groups)) % len(groups)]


def npod(groups: Sequence[Sequence[str]], name: str = "n-pod") -> GaitPattern:
    """A pattern whose groups swing in the order given, one equal slot each.

    Raises:
        InvalidInputError: A foot in two groups, or fewer than two feet.
    """
    offsets: dict[str, float] = {}
    for k, group in enumerate(groups):
        for foot in group:
            if foot in offsets:
                raise InvalidInputError(f"npod: foot {foot!r} is in two groups.")
            offsets[foot] = k / len(groups)
    return GaitPattern(name, offsets)


def sides(feet: Sequence[str], positions: np.ndarray) -> tuple[list[str], list[str]]:
    """The left feet and the right feet (``y`` >= 0 is left), each from front to back.

    Args:
        feet: Foot names.
        positions: ``(len(feet), 2 or 3)`` their places in body axes [m].
    """
    order = np.argsort(-np.asarray(positions)[:, 0], kind="stable")
    left = [feet[i] for i in order if positions[i][1] >= 0.0]
    right = [feet[i] for i in order if positions[i][1] < 0.0]
    return left, right


#: What each named pattern needs: ``(feet on each side: fewest, most or None; in words)``.
NEEDS: dict[str, tuple[int, int | None, str]] = {
    "trot": (2, 2, "two feet on each side"),
    "pace": (1, None, "a foot on each side at least"),
    "walk": (0, None, "two feet or more"),
    "tripod": (3, None, "three feet or more on each side"),
}


def fits(name: str, left: Sequence[str], right: Sequence[str]) -> bool:
    """Whether pattern ``name`` (one of `PATTERNS`) fits these feet on the left and right."""
    fewest, most, _ = NEEDS[name]
    return len(left) + len(right) >= 2 and all(
        fewest <= len(side) and (most is None or len(side) <= most) for side in (left, right)
    )


def fitting_patterns(feet: Sequence[str], positions: np.ndarray) -> tuple[str, ...]:
    """The `PATTERNS` that fit these feet, from where they stand (see `fits`)."""
    left, right = sides(feet, positions)
    return tuple(name for name in PATTERNS if fits(name, left, right))


def named_pattern(name: str, feet: Sequence[str], positions: np.ndarray) -> GaitPattern:
    """One of `PATTERNS` for these feet, from where they stand.

    Args:
        name: ``"trot"``, ``"pace"``, ``"walk"`` or ``"tripod"``.
        feet: Foot names.
        positions: ``(len(feet), 2 or 3)`` their places in body axes [m].

    Raises:
        InvalidInputError: An unknown name.
        GaitPatternError: A pattern that does not fit the feet (`NEEDS`); the message names
            the patterns that fit.
    """
    if name not in PATTERNS:
        raise InvalidInputError(f"Unknown gait pattern {name!r}; choose one of {PATTERNS}.")
    left, right = sides(feet, positions)
    if not fits(name, left, right):
        valid = fitting_patterns(feet, positions)
        raise GaitPatternError(
            f"Gait {name!r} needs {NEEDS[name][2]}; these feet stand {len(left)} on the left "
            f"({', '.join(left) or 'none'}) and {len(right)} on the right "
            f"({', '.join(right) or 'none'}): the gaits that fit them are "
            f"{', '.join(valid) or 'none'} (or give the swing groups with npod())."
        )
    if name in ("trot", "tripod"):
        first = left[0::2] + right[1::2]
        return npod([first, [f for f in feet if f not in first]], name)
    if name == "pace":
        pace = npod([left, right], name)
        return GaitPattern(name, pace.offsets, PACE_SWING_TIME, PACE_WIDTH)
    return npod([[f] for f in left[::-1] + right[::-1]], name)
