"""A push on a robot's body: ``--push N@T[:DEG]`` of ``demo legged`` and ``demo balance``."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, NamedTuple

from ..exceptions import InvalidInputError

if TYPE_CHECKING:  # no MuJoCo import for the command line's parsing
    from ..simulation.simulator import Simulator

#: How long a push lasts unless told otherwise [s].
PUSH_DURATION = 0.1


class Push(NamedTuple):
    """A push on the body: ``force`` newtons from ``time`` seconds along ``direction`` degrees.

    The direction is in the ground plane, 0 = +x; a negative force given to `parse` or `of`
    pushes the other way (``force`` is never negative).
    """

    force: float
    time: float
    direction: float = 0.0

    @classmethod
    def parse(cls, text: str) -> Push:
        """``"N@T"`` or ``"N@T:DEG"`` (``250@1.0:90``: 250 N at 1 s along +y).

        Raises:
            InvalidInputError: Not of that form, or not finite numbers with ``T >= 0``.
        """
        try:
            force, rest = str(text).split("@")
            when, _, angle = rest.partition(":")
            return cls.of((float(force), float(when), float(angle) if angle else 0.0))
        except (ValueError, InvalidInputError):
            raise InvalidInputError(
                f"push must be N@T[:DEG] (newtons at T >= 0 seconds, along DEG degrees; negative "
                f"newtons push the other way), got {text!r}."
            ) from None

    @classmethod
    def of(cls, value: str | Push | tuple[float, ...]) -> Push:
        """A push from its text, a `Push` or ``(N, T)`` / ``(N, T, DEG)``.

        Raises:
            InvalidInputError: Not finite numbers with ``T >= 0``, or a bad text.
        """
        if isinstance(value, str):
            return cls.parse(value)
        try:
            push = cls(*(float(v) for v in value))
        except (TypeError, ValueError):
            push = None
        if push is None or not all(map(math.isfinite, push)) or push.time < 0:
            raise InvalidInputError(
                f"push must be (N, T[, DEG]): newtons at T >= 0 seconds along DEG degrees "
                f"(negative newtons push the other way), got {value!r}."
            )
        if push.force < 0:
            push = cls(-push.force, push.time, (push.direction + 180.0) % 360.0)
        return push

    def apply(self, simulator: Simulator, frame: str, duration: float = PUSH_DURATION) -> None:
        """Start the push on ``frame`` in ``simulator`` for ``duration`` seconds."""
        angle = math.radians(self.direction)
        force = (self.force * math.cos(angle), self.force * math.sin(angle), 0.0)
        simulator.push(force, frame, duration)

    def __str__(self) -> str:
        return f"{self.force:g}@{self.time:g}:{self.direction:g}"
