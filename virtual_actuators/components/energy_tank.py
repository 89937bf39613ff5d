"""An energy tank that keeps any component passive.

A component can inject energy into the robot (a spring whose set point moves, a bunny pulling
the body, a user law). Wrapped in an :class:`EnergyTank`, the energy it injects is drawn from a
tank of finite capacity and the energy it dissipates refills it: over any run the component
injects at most the tank's initial energy plus what it dissipated. When the tank is empty, the
part of the wrench that would inject power (along the velocity) is removed; the rest, which does
no work, is kept.

Power is ``wrench . velocity`` on the component's axes (forces times the relative velocity of
{B} with respect to {A}, moments times the relative angular velocity), accounted once per tick
over the time since the previous tick (a first tick, after construction or :meth:`reset`, may
not inject). The arithmetic holds at any scale of the velocity (from subnormal to near the
float range): the power is compared with the energy left as a product of mantissas and powers of
two, and the velocity's norm is taken on the velocity divided by its largest entry, so nothing
squares, overflows or underflows on the way; the tank never goes negative, and once it is empty
the wrench keeps no part along the velocity.
"""

from __future__ import annotations

import math

import numpy as np

from ..exceptions import InvalidInputError
from ..vocabulary.frames import check_number, describe
from .base import Component


class EnergyTank(Component):
    """Wrap a component so that it never injects more energy than its tank holds.

    Args:
        component: The component to keep passive.
        capacity: Largest energy in the tank [J] (dissipated energy beyond it is lost).
        initial: Energy at the start [J] (default: ``capacity``).
        name: Label used in reports (default: ``tank(<component name>)``).

    Attributes:
        energy: Energy left in the tank [J].
        injected: Energy the component injected so far [J].
        dissipated: Energy it dissipated so far [J].

    Raises:
        InvalidInputError: ``component`` is not a :class:`Component`, or ``capacity`` /
            ``initial`` is negative or not finite, or ``initial > capacity``.

    """

    def __init__(
        self,
        component: Component,
        capacity: float,
        initial: float | None = None,
        name: str | None = None,
    ) -> None:
        if not isinstance(component, Component):
            raise InvalidInputError(
                f"EnergyTank: component must be a va.Component, got {describe(component)}."
            )
        super().__init__(component.axes, name or f"tank({component.name})")
        self.component = component
        self.capacity = check_number(capacity, f"{self.name}: capacity [J]", minimum=0.0)
        start = self.capacity if initial is None else initial
        self.energy = check_number(start, f"{self.name}: initial [J]", minimum=0.0)
        if self.energy > self.capacity:
            raise InvalidInputError(
                f"{self.name}: initial energy {self.energy} J exceeds the capacity "
                f"{self.capacity} J."
            )
        self.injected = 0.0
        self.dissipated = 0.0
        self._last_time: float | None = None

    def reset(self, position: np.ndarray, time: float) -> None:
        """Reset the wrapped component; the tank keeps its energy."""
        self.component.reset(position, time)
        self._last_time = None

    def compute_wrench(self, position: np.ndarray, velocity: np.ndarray, time: float) -> np.ndarray:
        """The wrapped component's wrench, without its injecting part once the tank is empty.

        Raises:
            InvalidInputError: If ``velocity`` holds NaN or an infinity.

        """
        wrench = np.array(self.component.compute_wrench(position, velocity, time), dtype=float)
        velocity = np.asarray(velocity, dtype=float)
        dt = 0.0 if self._last_time is None else max(time - self._last_time, 0.0)
        self._last_time = time
        scale = float(np.max(np.abs(velocity))) if velocity.size else 0.0
        if not math.isfinite(scale):
            raise InvalidInputError(f"{self.name}: velocity must be finite, got {velocity}.")
        if scale == 0.0:
            return wrench  # no motion, no work
        unit = velocity / scale  # largest entry +-1: its norm neither overflows nor underflows
        norm = math.hypot(*unit.tolist())
        direction = unit / norm  # the velocity's direction; |velocity| = scale * norm
        along = float(wrench @ direction)  # [N or N m] the wrench along the velocity
        # the work over this tick, along * |velocity| * dt, as mantissa * 2**exponent
        mantissa, exponent = _product(along, scale, norm, dt)
        work = _value(mantissa, exponent)  # [J], > 0: injected into the robot
        if along > 0.0 and (dt == 0.0 or self.energy == 0.0 or work > self.energy):
            # Only what is left may be injected over this tick (nothing on a first tick, whose
            # duration is unknown): keep the fraction energy / work of the wrench along the
            # velocity (the orthogonal part does no work).
            kept = 0.0
            if dt > 0.0 and self.energy > 0.0:
                energy_mantissa, energy_exponent = math.frexp(self.energy)
                kept = math.ldexp(energy_mantissa / mantissa, energy_exponent - exponent)  # < 1
            wrench = wrench - (along * (1.0 - kept)) * direction
            work = self.energy if kept > 0.0 else 0.0
        if work > 0.0:
            self.injected += work
            self.energy = max(self.energy - work, 0.0)
        else:
            self.dissipated -= work
            self.energy = min(self.energy - work, self.capacity)
        return wrench

    def _parameters(self) -> str:
        return (
            f"component={self.component.name!r}, energy={self.energy:.4g} J, "
            f"capacity={self.capacity:.4g} J"
        )


def _product(*factors: float) -> tuple[float, int]:
    """The product of finite floats as ``(mantissa, exponent)``, never overflowing on the way.

    Returns:
        ``mantissa * 2**exponent`` equals the product (to rounding), with ``|mantissa|`` in
        ``[2**-k, 1)`` for ``k`` nonzero factors, or ``(0.0, 0)`` when a factor is zero.
    """
    mantissa, exponent = 1.0, 0
    for factor in factors:
        factor_mantissa, factor_exponent = math.frexp(factor)
        mantissa *= factor_mantissa
        exponent += factor_exponent
    return mantissa, exponent


def _value(mantissa: float, exponent: int) -> float:
    """``mantissa * 2**exponent``: an infinity beyond the float range, 0 below it."""
    try:
        return math.ldexp(mantissa, exponent)
    except OverflowError:
        return math.copysign(math.inf, mantissa)


__all__ = ["EnergyTank"]
