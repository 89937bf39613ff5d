"""An energy tank that keeps any component passive.

A component can inject energy into the robot (a spring whose set point moves, a bunny pulling
the body, a user law). Wrapped in an [`EnergyTank`][], the energy it injects is drawn from a
tank of finite capacity and the energy it dissipates refills it: over any run the component
injects at most the tank's initial energy plus what it dissipated. When the tank is empty, the
part of the wrench that would inject power (along the velocity) is removed; the rest, which does
no work, is kept.

Power is ``wrench . velocity`` on the component's axes (forces times the relative velocity of
{B} with respect to {A}, moments times the relative angular velocity), accounted once per tick
over the time since the previous tick (a first tick, after construction or `reset`, may
not inject). The arithmetic holds at any scale of the velocity (from subnormal to near the
float range): the tick's work is compared with the energy left as a product of mantissas and
powers of two, and the velocity's norm comes from `math.hypot` (or, for a subnormal or
overflowing norm, from the velocity divided by its largest entry), so nothing squares the
velocity, overflows or underflows on the way; the tank never goes negative, and once it is empty
the wrench keeps no part along the velocity.
"""

from __future__ import annotations

import math
import operator
import sys

import numpy as np

from ..exceptions import InvalidInputError
from ..vocabulary.arguments import check_number, describe
from .base import Component

#: The least positive normal float: below it a float holds fewer bits.
_NORMAL = sys.float_info.min


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
        InvalidInputError: ``component`` is not a [`Component`][], or ``capacity`` /
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
            InvalidInputError: If ``velocity`` does not have one entry per axis, or holds NaN or
                an infinity.

        """
        wrench = np.array(self.component.compute_wrench(position, velocity, time), dtype=float)
        values = np.asarray(velocity, dtype=float).reshape(-1).tolist()  # a few plain floats
        if len(values) != wrench.size:
            raise InvalidInputError(
                f"{self.name}: velocity has {len(values)} entries, expected one per axis "
                f"{self.axes}."
            )
        dt = 0.0 if self._last_time is None else max(time - self._last_time, 0.0)
        self._last_time = time
        speed = math.hypot(*values)  # [m/s or rad/s] hypot scales: it overflows only past 1e308
        if _NORMAL <= speed < math.inf:
            speeds = (speed, 1.0)
            direction = [value / speed for value in values]
        elif speed == 0.0:
            return wrench  # no motion, no work
        else:  # past the float range, or subnormal (a few bits): divide by the largest entry
            if not all(map(math.isfinite, values)):
                raise InvalidInputError(f"{self.name}: velocity must be finite, got {values}.")
            largest = max(map(abs, values))  # |v| = largest * |v / largest|, both finite
            speeds = (largest, math.hypot(*(value / largest for value in values)))
            direction = [value / largest / speeds[1] for value in values]
        along = sum(map(operator.mul, wrench.tolist(), direction))  # [N or N m] along the velocity
        # the work over this tick, along * |velocity| * dt, as mantissa * 2**exponent
        mantissa, exponent = _product(along, speeds[0], speeds[1], dt)
        work = _value(mantissa, exponent)  # [J], > 0: injected into the robot
        if along > 0.0 and (dt == 0.0 or self.energy == 0.0 or work > self.energy):
            # Only what is left may be injected over this tick (nothing on a first tick, whose
            # duration is unknown): keep the fraction energy / work of the wrench along the
            # velocity (the orthogonal part does no work).
            kept = 0.0
            if dt > 0.0 and self.energy > 0.0:
                energy_mantissa, energy_exponent = math.frexp(self.energy)
                kept = math.ldexp(energy_mantissa / mantissa, energy_exponent - exponent)  # < 1
            wrench = wrench - (along * (1.0 - kept)) * np.array(direction)
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


def _product(along: float, speed: float, factor: float, dt: float) -> tuple[float, int]:
    """The product of four finite floats as ``(mantissa, exponent)``, never overflowing.

    Returns:
        ``mantissa * 2**exponent`` equals the product (to rounding), with ``|mantissa|`` in
        ``[1/16, 1)``, or a zero mantissa when a factor is zero.
    """
    m1, e1 = math.frexp(along)
    m2, e2 = math.frexp(speed)
    m3, e3 = math.frexp(factor)
    m4, e4 = math.frexp(dt)
    return m1 * m2 * m3 * m4, e1 + e2 + e3 + e4


def _value(mantissa: float, exponent: int) -> float:
    """``mantissa * 2**exponent``: an infinity beyond the float range, 0 below it."""
    try:
        return math.ldexp(mantissa, exponent)
    except OverflowError:
        return math.copysign(math.inf, mantissa)


__all__ = ["EnergyTank"]
