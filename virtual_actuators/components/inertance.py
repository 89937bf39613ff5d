"""A virtual inertance: ``-m_v a``, ``a`` the low-pass filtered derivative of the velocity."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from ..exceptions import InvalidInputError
from ..vocabulary.arguments import check_number
from .base import Component


class Inertance(Component):
    """``wrench = -inertance * filtered d(velocity)/dt`` on each axis.

    Args:
        axes: Axes the component acts on.
        inertance: Per axis or scalar, >= 0 [kg or kg m^2].
        time_constant: Of the low-pass filter on the acceleration [s] (0: raw differences).
        name: Label used in reports.

    Raises:
        InvalidAxisError: Bad axes.
        InvalidInputError: A negative or non-finite inertance or time constant.

    Note:
        Keeps the last velocity and acceleration: one instance per controller, called once per
        tick with increasing times; [`reset`][] forgets them.
    """

    def __init__(
        self,
        axes: Sequence[str],
        inertance: float | Sequence[float] | np.ndarray,
        time_constant: float = 0.005,
        name: str | None = None,
    ) -> None:
        super().__init__(axes, name)
        self.inertance = self._per_axis(inertance, "inertance")
        if np.any(self.inertance < 0.0):
            raise InvalidInputError(f"{self.name}: inertance must be >= 0, got {self.inertance}.")
        self.time_constant = check_number(
            time_constant, f"{self.name}: time_constant [s]", minimum=0.0
        )
        self._last: tuple[float, np.ndarray] | None = None
        self.acceleration = np.zeros(len(self.axes))  # filtered estimate [m/s^2 or rad/s^2]

    def reset(self, position: np.ndarray, time: float) -> None:
        """Forget the velocity history (the next tick starts a new estimate)."""
        self._last = None
        self.acceleration = np.zeros(len(self.axes))

    def compute_wrench(self, position: np.ndarray, velocity: np.ndarray, time: float) -> np.ndarray:
        """``-inertance * acceleration``, the acceleration filtered from velocity differences."""
        velocity = np.array(velocity, dtype=float)
        if self._last is not None:
            last_time, last_velocity = self._last
            dt = time - last_time
            if dt > 0.0:
                raw = (velocity - last_velocity) / dt
                blend = 1.0 if self.time_constant == 0.0 else -math.expm1(-dt / self.time_constant)
                self.acceleration = self.acceleration + blend * (raw - self.acceleration)
        if self._last is None or time > self._last[0]:
            self._last = (time, velocity)
        return -self.inertance * self.acceleration

    def _parameters(self) -> str:
        return f"inertance={self.inertance.tolist()}, time_constant={self.time_constant}"
