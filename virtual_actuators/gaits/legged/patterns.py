"""Gait patterns as data: which feet swing together, and in which order.

A [`GaitPattern`][] gives every foot the phase of the cycle (0 to 1) at which its swing
starts; feet with the same phase form a *swing group* and swing together, the groups in the
order of their phases, one after the other. The walker
([`LeggedWalker`][]) turns the groups into states.

The named patterns are built from where the feet stand (body axes: x forward, y left), so
they work on any robot whatever its frame names:

* ``trot``: diagonal pairs (left-front with right-hind), two groups;
* ``pace``: lateral pairs (the left legs, then the right legs), with short swings and a narrow
  stance (`PACE_SWING_TIME`, `PACE_WIDTH`): on the two feet of one side the centre
  of mass, off their line, falls sideways as an inverted pendulum, ``e^(t / sqrt(h / g))``, so
  the swing must be short and the line near the centre of mass;
* ``walk``: one foot at a time, the lateral sequence (left hind, left front, right hind, right
  front on a quadruped; back to front along each side);
* ``tripod`` (alternating): legs alternate along each side and across (a hexapod's tripods,
  a quadruped's trot, a millipede's two waves);
* [`npod`][]: any groups you give.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ...exceptions import InvalidInputError

PATTERNS = ("trot", "pace", "walk", "tripod")

#: A pace's swing time in units of ``sqrt(h / g)`` (the others': 1). In 0.3 of the pendulum's
#: time the centre of mass, ``w`` off the support line, gains ``0.3 w / sqrt(h / g)`` of sideways
#: speed, which the next side's touchdown turns around (go2, solo12, anymal pace at 0.4 m/s with
#: roll below 0.2 rad; with the trot's swing time of 1 they fall in the first swing).
PACE_SWING_TIME = 0.3

#: A pace's stance width, a fraction of the standing pose's: the footholds nearer the line of
#: the hips' middle, so the support line passes nearer the centre of mass.
PACE_WIDTH = 0.6


@dataclass(frozen=True)
class GaitPattern:
    """Phase offsets per foot: when in the cycle each foot's swing starts.

    Attributes:
        name: Label.
        offsets: ``{foot: phase in [0, 1)}``.
        swing_time: Duration of a swing in units of ``sqrt(h / g)`` when
            [`LeggedParameters`][] leaves it to the pattern (``None``) [-].
        width: The nominal stance's width across the heading, as a fraction of the standing
            pose's, in (0, 1] [-].

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

    def duty_factor(self) -> float:
        """Fraction of the cycle a foot stands (double supports left out)."""
        return 1.0 - 1.0 / len(self.groups())


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


def named_pattern(name: str, feet: Sequence[str], positions: np.ndarray) -> GaitPattern:
    """One of `PATTERNS` for these feet, from where they stand.

    Args:
        name: ``"trot"``, ``"pace"``, ``"walk"`` or ``"tripod"``.
        feet: Foot names.
        positions: ``(len(feet), 2 or 3)`` their places in body axes [m].

    Raises:
        InvalidInputError: Unknown name; ``trot`` or ``pace`` without two feet on each side.

    """
    left, right = sides(feet, positions)
    if name == "tripod" or (name == "trot" and len(left) == len(right) == 2):
        first = left[0::2] + right[1::2]
        return npod([first, [f for f in feet if f not in first]], name)
    if name == "pace" and left and right:
        pace = npod([left, right], name)
        return GaitPattern(name, pace.offsets, PACE_SWING_TIME, PACE_WIDTH)
    if name == "walk":
        return npod([[f] for f in left[::-1] + right[::-1]], name)
    if name in PATTERNS:
        raise InvalidInputError(
            f"Pattern {name!r} needs two feet on each side (left {left}, right {right}); "
            "give the swing groups with npod()."
        )
    raise InvalidInputError(f"Unknown gait pattern {name!r}; choose one of {PATTERNS}.")


__all__ = [
    "PACE_SWING_TIME",
    "PACE_WIDTH",
    "PATTERNS",
    "GaitPattern",
    "named_pattern",
    "npod",
    "sides",
]
